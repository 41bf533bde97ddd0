#include "stream/point_outputs.hpp"

#include <array>
#include <optional>

#include "formats/atomic_file.hpp"
#include "formats/png_writer.hpp"
#include "stream/pipe_closure.hpp"
#include "stream/point_file_sink.hpp"
#include "stream/point_spool.hpp"
#include "stream/runner.hpp"
#include "stream/splat_sink.hpp"
#include "stream/stream_metadata.hpp"
#include "stream/tee_sink.hpp"

namespace meshless {

namespace {
/// Hands batches on to `to` (or drops them when null) but leaves its finish() to the caller.
class HeldSink final : public Sink {
public:
    PayloadSet takes() const override { return to_ ? to_->takes() : PayloadSet::any(); }
    explicit HeldSink(Sink* to) : to_(to) {}
    void consume(Batch&& b) override {
        if (to_) to_->consume(std::move(b));
    }
    void observe(const Batch& b) override {
        if (to_) to_->observe(b);
    }
    void finish() override {}

private:
    Sink* to_;
};

/// The picture's point spool as a sink: block ids are kept only for a picture coloured by block
/// (the MPI root merges its own batches, which carry them, with other ranks', which do not).
class PictureSpoolSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::points; }
    PictureSpoolSink(PointSpool& spool, bool blocks) : spool_(spool), blocks_(blocks) {}
    void consume(Batch&& b) override { observe(b); }
    void observe(const Batch& b) override {
        if (blocks_) spool_.observe(b);
        else if (b.kind != RecordKind::point) spool_.observe(b);  // (refused there, with its message)
        else spool_.append(b.points);
    }
    void finish() override { spool_.finish(); }

private:
    PointSpool& spool_;
    bool blocks_;
};

/// The picture's colour settings with the colouring --ply-color asks for (range, colour map as the picture's).
std::optional<ShadingParams> ply_colors(const GeometryOutput& out, const RenderSettings& rs) {
    if (!out.ply_color) return std::nullopt;
    ShadingParams s = rs.shading;
    s.color_by = *out.ply_color;
    return s;
}
}  // namespace

std::size_t run_to_outputs(const std::optional<GeometryOutput>& out, const std::optional<std::string>& png,
                           const StreamMeta& meta, const RenderSettings& rs, int nthreads, const GraphRun& run,
                           IsoSplatResult& r, bool parallel_draw, bool with_blocks) {
    if (!png) {
        VtpOptions vo = out->vtp;
        if (vo.threads == 0) vo.threads = nthreads;
        if (const auto name = meta.get("value_name")) vo.value_name = *name;  // (coloured by another array: its name)
        PointFileSink sink(out->path, out->format, ply_comments(meta), vo, with_blocks, ply_colors(*out, rs));
        r = run(nullptr, sink);
        return sink.count();
    }
    AtomicFile png_file(*png);  // before any work: a PNG that cannot be created fails the run at once
    const std::optional<std::array<Vec3, 2>> frame = picture_bounds(meta);
    // without a frame known before the first point (the scattered surface), the points go to a
    // spool; the picture frames the spool's bounds and replays it
    std::optional<PointSpool> spool;
    std::optional<PictureSpoolSink> spooled;
    std::optional<SplatSink> drawn;
    if (frame) {
        drawn.emplace(rs.camera, rs.kernel, rs.shading, *frame, nthreads);
        drawn->set_spool_memory(rs.spool_memory);
    } else {
        spool.emplace("picture-spool");
        spooled.emplace(*spool, rs.shading.color_by == ColorBy::block);
    }
    Sink& picture_sink = frame ? static_cast<Sink&>(*drawn) : static_cast<Sink&>(*spooled);
    std::optional<PointFileSink> ply;
    if (out) {
        VtpOptions vo = out->vtp;
        if (vo.threads == 0) vo.threads = nthreads;
        if (const auto name = meta.get("value_name")) vo.value_name = *name;  // (coloured by another array: its name)
        ply.emplace(out->path, out->format, ply_comments(meta), vo, with_blocks, ply_colors(*out, rs));
    }
    // the point file is committed after the picture is written (to its temporary), so a failed
    // picture leaves the previous -o file as it was
    HeldSink held(ply ? static_cast<Sink*>(&*ply) : nullptr);
    std::optional<TeeSink> tee;
    if (ply) tee.emplace(picture_sink, held);
    PipeClosure pipe;  // stdout's reader went away: the other output is still completed
    try {
        r = run(parallel_draw && drawn ? &drawn->stage() : nullptr, tee ? static_cast<Sink&>(*tee) : picture_sink);
    } catch (const BrokenPipe&) {
        if (!tee || !tee->live(0)) throw;  // the picture's branch never closes during the run
        pipe.caught();
    }
    if (spool) {
        spool->flush();
        const auto box = spool->size() > 0 ? std::optional(spool->bounds()) : meta_bounds(meta);
        drawn.emplace(rs.camera, rs.kernel, rs.shading, box ? *box : std::array<Vec3, 2>{}, nthreads, &*spool);
        drawn->set_spool_memory(rs.spool_memory);
        PointSpoolSource replay(*spool);
        const Stage* draw_stage[] = {&drawn->stage()};
        run_pipeline(replay, draw_stage, *drawn, {nthreads});
    }
    SplatSink& splat = *drawn;
    Image picture = splat.image();
    RenderSettings labelled = rs;  // the scale bar in the unit the points' volume recorded
    if (labelled.length_unit.empty()) labelled.length_unit = meta_length_unit(meta);
    // the colour bar titled with the values' unit (not when they are another array's: --color-by)
    if (labelled.legend_title.empty() && !meta.get("value_name")) labelled.legend_title = meta.get("value_unit").value_or("");
    decorate_picture(labelled, picture, &splat.frame().view());
    const bool png_live = pipe.step([&] { write_png(picture, png_file); });
    if (ply && tee->live(1)) pipe.step([&] { ply->finish(); });  // stdout's PLY is written here
    if (png_live) pipe.step([&] { png_file.commit(); });
    pipe.rethrow_if_closed();
    return splat.points();
}

}  // namespace meshless
