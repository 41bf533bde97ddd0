// The streaming splat sink (dissertation section 3.6): oriented points are rasterised (quad) or
// turned into screen footprints and spooled to a file (EWA) as their batches arrive, into the
// renderer's per-pixel buffers (kernels/splat_rasterizer.hpp SplatFrame); no point is collected.
// Memory = the image buffers (one set per drawing thread) + one batch, for any number of points
// (EWA: + 32 KiB per thread for the depth-ordered groups of the spool, and its memory tier: at most
// kSpoolMemory, 64 MiB, about 1.1 M footprints, for all threads together, which saves their trips
// through the kernel's page cache: 5 % of an 8-isovalue `isosurface --png` run on the lung CT).
//
// The camera must be framed before the first point (the surface bounds of the stream's META or the
// PLY comments, see cli/common.hpp surface_bounds). Kernels:
//  - quad: one pass; each pixel keeps min((depth << 32) | colour), which does not depend on the
//    order or the split of the points.
//  - ewa: two passes (visibility, then accumulation against the final visibility). As the batches
//    arrive, the sink computes the screen footprints of their splats (conic, bounding box, depth
//    plane, normal, base colour: kernels/splat_rasterizer.hpp EwaFootprint, 60 bytes) and appends
//    them to a footprint spool per drawing thread (stream/footprint_spool.hpp: chunks in memory
//    while the spools' shared budget of kSpoolMemory bytes lasts, the rest in unlinked temporary
//    files in $TMPDIR or /tmp), noting the mean depth of each group of consecutive batches (4,096
//    footprints or more; at most 1,024 groups per thread, coarser for larger spools). finish()
//    replays the spools twice: pass 1 group by group, nearest groups first (each thread takes the
//    nearest group left), skipping the splats that lie behind everything already drawn under them
//    (EwaCull: about half of the splats of a CT isosurface, whose blocks arrive in Morton order,
//    often back to front); then pass 2 in batches of kMaxBatchRecords, skipping the splats hidden
//    everywhere behind the final visible depth (SplatFrame::depth_tiles). Neither skip changes a
//    byte. A caller whose points are already in a spool (a turntable replays one spool per frame)
//    passes it as `replay`: the sink then draws pass 1 as the batches arrive, spools nothing, and
//    pass 2 recomputes the footprints from the replay spool. The accumulators are 64-bit fixed
//    point, so the sum is exact in any order and any split.
// The image is byte-identical to render_splats() on all the points at once, for any batch split
// and any thread count (the tests check both kernels).
//
// Threads: stage() returns a Stage that draws (or spools) each batch inside the runner's parallel
// section into a per-thread partial buffer (the batch passes through unchanged); partial buffers
// are merged by min (keys) and integer sum (EWA accumulators) in finish(). Without stage(),
// consume() draws or spools (serial). finish() replays the EWA spools with `threads` threads (its
// own task arena), one key buffer per thread in pass 1.
// Colours (ShadingParams::color_by, kernels/splat_rasterizer.hpp): block colours read each batch's
// Batch::point_block (the footprints keep the base colour for pass 2; a replay spool its block ids); a non-empty batch without them is a
// FormatError when colouring by block.
// Errors: FormatError on sample batches; IoError naming the spool file when it cannot be created,
// written or read back; std::logic_error when a `replay` spool does not hold the points drawn. Not thread-safe apart from the stage (Sink rules, stream/stage.hpp).
#pragma once
#include <array>
#include <memory>

#include "kernels/splat_rasterizer.hpp"
#include "stream/footprint_spool.hpp"
#include "stream/point_spool.hpp"
#include "stream/stage.hpp"

namespace meshless {

class SplatSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    /// replay (ewa only, may be null): a flushed spool holding exactly the points this sink will be
    /// given (in any order); it must outlive finish().
    SplatSink(const Camera& cam, SplatKernel kernel, const ShadingParams& shading, const std::array<Vec3, 2>& bounds,
              int threads = 1, const PointSpool* replay = nullptr);
    ~SplatSink() override;

    /// Bytes of EWA footprints the spools keep in memory before their files take the rest, for
    /// all drawing threads together (stream/footprint_spool.hpp).
    static constexpr std::size_t kSpoolMemory = std::size_t{64} << 20;
    /// Another memory budget for the footprint spools (bytes, all threads together; 0: all to disk);
    /// call before the first point (std::logic_error otherwise). The image does not change.
    void set_spool_memory(std::size_t bytes);
    /// EWA spool groups (tuning, tests): a group takes consecutive batches until it holds min_group
    /// footprints (default 4096); when a thread has max_groups (default 1024) groups, neighbours
    /// merge pairwise and its min_group doubles. Call before the first point (std::logic_error
    /// otherwise, or when min_group < 1 or max_groups is odd or < 2). The image does not change.
    void set_spool_groups(std::uint64_t min_group, std::size_t max_groups);

    /// The parallel drawing stage; put it last in the runner's stage list. Once called, consume()
    /// no longer draws (only counts and spools).
    const Stage& stage();
    void consume(Batch&& b) override { observe(b); }
    /// As consume(); the batch is only read.
    void observe(const Batch& b) override;
    /// Merges, runs the EWA accumulation pass, shades. Then image() is valid.
    void finish() override;

    const Image& image() const { return image_; }
    const SplatFrame& frame() const { return frame_; }
    /// Splats drawn and fragments tested, summed over threads and passes (EWA pass 1 from the
    /// spools: culled splats are not counted, so these depend on the thread count; the image does
    /// not); seconds = time in finish().
    SplatStats stats() const { return stats_; }
    std::uint64_t points() const { return points_; }
    /// Bytes held by the sink's buffers now (keys, accumulators, image, spool staging), for tests.
    std::size_t retained_bytes() const;

private:
    struct Canvas;
    struct Canvases;
    class DrawStage;
    /// Footprints [first, first + count) of one spool, from consecutive batches; depth_sum: the
    /// sum of their depths.
    struct SpoolGroup {
        const FootprintSpool* spool;
        std::uint64_t first, count;
        double depth_sum;
        double mean_depth() const { return depth_sum / static_cast<double>(count); }
    };
    /// fn(i) for i in [0, n): serially with one thread, else in parallel in an arena of threads_.
    template <class Fn>
    void run_parts(std::size_t n, Fn&& fn) const;

    SplatFrame frame_;
    ShadingParams shading_;
    int threads_;
    std::unique_ptr<Canvases> canvases_;
    std::unique_ptr<DrawStage> stage_;
    bool staged_ = false;
    const PointSpool* pass2_ = nullptr;      // ewa: the replay spool pass 2 reads, else the footprint spools
    std::uint64_t points_ = 0;
    SplatStats stats_;
    Image image_;
};

}  // namespace meshless
