// Software surface splatting (dissertation section 3.6): quadrilateral (QSplat-style) and
// elliptical EWA-style kernels, rendering oriented points (PointRecord) into an RGB8 image.
//
// Quad kernel: each point becomes a screen-aligned square of side 2 * r_px centred on its
//   projection, r_px = radius * pixels_per_unit(depth) (= radius * focal / depth in perspective);
//   pixels whose centres fall inside [x - r_px, x + r_px) x [y - r_px, y + r_px) are covered (at
//   least the pixel under the centre). The square has the centre's depth; a z-buffer keeps the
//   nearest; each splat is shaded once with its own normal (flat, QSplat-style).
// EWA kernel: each point is a disk of radius `radius` in its tangent plane (normal of the record).
//   Its two scaled tangent axes are projected through the 2x2 Jacobian J of the projection at the
//   centre; the screen-space Gaussian has variance V = J J^T / c^2 + lowpass * I (c = ewa_cutoff,
//   lowpass in pixel^2), so the disk boundary is the Mahalanobis radius c, and the footprint is
//   cut off there. Pass 1 (visibility) writes the nearest splat-plane depth per pixel; pass 2
//   (accumulation) adds weight * normal and weight of every fragment whose depth is within
//   depth_epsilon * radius of the visible depth, each normal first aligned (sign) with the visible
//   fragment's; the blended normal is normalised per pixel, flipped towards the viewer when
//   two-sided, and shaded (deferred Phong). Accumulation is in 64-bit fixed point, so the image does not depend
//   on the order of the points.
// Shading: Lambert + Phong with a directional light given in camera space (default: a headlight
//   from the viewer), view vector towards the eye; two_sided flips normals that face away from
//   the viewer (quad: per splat; ewa: the blended normal per pixel). Points with a zero normal face the camera. Points with non-finite positions or
//   behind the near plane are skipped. Pixels that no splat covers get the background colour.
// Determinism: the same input gives the same bytes, and for both kernels a permutation of the
//   points gives the same bytes (quad ties are broken by the shaded colour), so the points may be
//   drawn in any split: SplatFrame draws any subset into a partial buffer, partial buffers are
//   merged by min (keys) and integer sum (EWA accumulators), and the result equals one pass over all
//   points, byte for byte, whatever the split or the thread count (stream/splat_sink.hpp).
// Speed (EWA, same bytes as the plain per-pixel loops): footprints four points at a time and rows four
//   pixels at a time (SSE2, the scalar float operations in the same order), eight at a time with AVX2
//   where the CPU has it (eight points; eight pixels of a row, or two rows of four for footprints at
//   most four pixels wide; chosen at run time, no FMA: the same bits; ewa_isa()); both passes may take
//   footprints computed once (EwaFootprint, SplatFrame::footprints); pass 1 from footprints may
//   skip splats behind everything drawn under them so far (EwaCull), pass 2 those hidden behind the
//   visible depth of every tile they touch (VisibleDepthTiles).
// Cost: O(points + covered fragments), no per-splat allocation; buffers live in SplatRenderer and
//   are reused across frames (a 36-frame turntable allocates once).
// Thread-safety: render_splats is reentrant; a SplatRenderer is used by one thread at a time.
// Throws nothing but std::bad_alloc.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <type_traits>
#include <vector>

#include "kernels/camera.hpp"
#include "kernels/colormap.hpp"
#include "kernels/records.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

enum class SplatKernel { quad, ewa };

/// The base colour of each splat before shading (meshless splat --color):
///   none:   ShadingParams::base for every point (the picture as before colouring existed);
///   value:  colormap(value) over [value_lo, value_hi] (clamped; NaN grey);
///   block:  categorical_color(block id) (kernels/colormap.hpp; the ids are given beside the points:
///           Batch::point_block; a point without one gets id 0);
///   normal: (n + 1) / 2 per component of the world-space unit normal (zero normal: grey).
/// The colour is then lit like the surface colour (Lambert + Phong). With the EWA kernel the base
/// colours of the fragments near the visible surface are blended with their Gaussian weights
/// (3 more 64-bit fixed-point accumulators per pixel), so block colours blend across seams.
enum class ColorBy { none, value, block, normal };

struct ShadingParams {
    double ambient = 0.15, diffuse = 0.75, specular = 0.2, shininess = 24;
    Vec3 light_dir{0, 0, 1};  ///< direction towards the light, camera space (x right, y up, z to viewer)
    bool two_sided = true;    ///< flip normals facing away from the viewer before shading
    std::array<std::uint8_t, 3> base{226, 214, 190};     ///< surface colour (bone)
    std::array<std::uint8_t, 3> background{0, 0, 0};     ///< uncovered pixels
    // EWA reconstruction (ignored by the quad kernel)
    double ewa_cutoff = 2.0;       ///< footprint cut-off, Mahalanobis radius; the disk edge maps here
    double ewa_lowpass_px2 = 1.0;  ///< screen-space low-pass variance added to the footprint (pixel^2)
    double depth_epsilon = 1.0;    ///< blend fragments within depth_epsilon * radius of the visible depth
    // Per-point colour (see ColorBy)
    ColorBy color_by = ColorBy::none;
    Colormap colormap = Colormap::viridis;
    double value_lo = 0, value_hi = 1;  ///< ColorBy::value: the colour map's range
};

struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  ///< row-major, top row first, 3 bytes per pixel
    std::array<std::uint8_t, 3> at(int x, int y) const {
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

struct SplatStats {
    /// splats in front of the eye whose footprint touches the image; EWA pass 1 from footprints
    /// with an EwaCull counts only those not culled, so a sink's count depends on the order and the
    /// thread count (its image does not)
    std::int64_t splats_drawn = 0;
    std::int64_t fragments = 0;     ///< pixels tested inside footprints (EWA: per pass, summed)
    double seconds = 0;             ///< wall time of the render call
};

/// Axis-aligned bounds of the finite positions; {0,0,0},{0,0,0} when there are none.
std::array<Vec3, 2> point_bounds(std::span<const PointRecord> points);

/// point_bounds over points that come in parts (a stream, a spool): add() each part, in any order
/// and split; bounds() equals point_bounds of all of them. Not thread-safe.
class PointBounds {
public:
    void add(std::span<const PointRecord> points);
    /// As if o's points had been added too.
    void merge(const PointBounds& o);
    /// {0,0,0},{0,0,0} while no finite position was added.
    std::array<Vec3, 2> bounds() const;

private:
    static constexpr double kInf = std::numeric_limits<double>::infinity();
    double lo_[3] = {kInf, kInf, kInf}, hi_[3] = {-kInf, -kInf, -kInf};
};

/// The screen-space footprint of one EWA splat, as computed from its point: either pass may take it
/// instead of the point (the streaming sink spools footprints, stream/splat_sink.hpp), with the
/// same bytes as recomputing it. 60 bytes, trivially copyable (written raw to a spool file).
/// Depth plane: depth(dx, dy) = depth + gx dx + gy dy (dx, dy: pixel-centre offsets from (sx, sy)),
/// clamped to [max(depth - radius, 0), depth + radius]; normal: camera space, unit (raw orientation).
struct EwaFootprint {
    float sx, sy;           ///< centre, pixels
    float q00, q01, q11;    ///< conic V^-1, pixel^-2
    float depth, gx, gy;    ///< splat-plane depth at the centre (world units) and its screen gradient
    float radius;           ///< splat radius (world units; non-finite / negative radii are 0)
    float n[3];             ///< unit normal, camera space
    std::uint16_t x0, x1, y0, y1;  ///< pixel range of the cut-off ellipse's bounding box, inside the image
    std::uint32_t base;     ///< base colour 0xRRGGBB (splat_base_color), used with ColorBy other than none
};
static_assert(sizeof(EwaFootprint) == 60 && std::is_trivially_copyable_v<EwaFootprint>);

/// The largest visible depth (the float depth of the final EWA visibility keys) over square tiles
/// of kSize x kSize pixels, +infinity where a tile holds a pixel without a finite non-negative
/// depth. Pass 2 skips a splat whose nearest possible depth lies beyond the largest visible depth of
/// every tile its footprint touches by more than its blending tolerance: none of its fragments
/// could pass the per-pixel depth test, so the skip changes no byte of the image.
struct VisibleDepthTiles {
    static constexpr int kShift = 2, kSize = 1 << kShift;
    int tiles_x = 0, tiles_y = 0;
    std::vector<float> max_depth;  ///< tiles_x * tiles_y, row-major
};

/// The culling state of one EWA pass-1 key buffer (SplatFrame::draw on footprints; one key buffer,
/// one frame size): the visible-depth tiles of the buffer as it was at the last refresh. Keys only
/// decrease, so stale tiles are conservative. The first refresh comes after refresh_after(npix)
/// splats drawn (an empty buffer hides nothing), the next after as many again.
struct EwaCull {
    VisibleDepthTiles tiles;
    std::int64_t drawn_since = 0;
    static std::int64_t refresh_after(std::size_t npix) { return std::max<std::int64_t>(1024, static_cast<std::int64_t>(npix / 16)); }
};

/// One frame's fixed set-up (view, shading, kernel) and the pieces of the render, for drawing the
/// points in parts (streaming, threads). Buffers are the caller's, npix() entries each:
///   keys: uint64 per pixel, start at kEmptyKey; quad: draw() leaves min((depth << 32) | rgb);
///         ewa: draw() is the visibility pass, min((depth << 32) | packed normal).
///   acc:  ewa only, 4 int64 per pixel, start at 0; accumulate() adds the fragments near the
///         visible depth of the *final* keys (all points drawn and merged first).
/// Const members are thread-safe (distinct buffers per thread, or read-only keys in accumulate()).
class SplatFrame {
public:
    static constexpr std::uint64_t kEmptyKey = ~std::uint64_t{0};
    SplatFrame(const Camera& cam, SplatKernel kernel, const ShadingParams& shading, const std::array<Vec3, 2>& bounds);
    int width() const { return view_.width; }
    int height() const { return view_.height; }
    std::size_t npix() const { return static_cast<std::size_t>(view_.width) * view_.height; }
    SplatKernel kernel() const { return kernel_; }
    bool two_pass() const { return kernel_ == SplatKernel::ewa; }
    const ViewTransform& view() const { return view_; }

    /// Accumulator words per pixel (EWA): 4 (weight, weighted normal), 7 with per-point colours
    /// (and the weighted base colour).
    std::size_t acc_words() const { return shading_.color_by == ColorBy::none ? 4 : 7; }

    /// Quad: the only pass; ewa: pass 1 (visibility). Adds to stats.splats_drawn / fragments.
    /// blocks: empty, or the block id of each point (ColorBy::block; quad only: EWA pass 1 draws no
    /// colour).
    void draw(std::span<const PointRecord> points, std::uint64_t* keys, SplatStats& stats,
              std::span<const std::uint32_t> blocks = {}) const;
    /// EWA only: the footprints of the splats that touch the image, in order, with their base colours
    /// (blocks as in draw()): out is cleared, then filled; nothing is drawn. draw() on them gives the
    /// keys draw() gives on the points.
    void footprints(std::span<const PointRecord> points, std::vector<EwaFootprint>& out,
                    std::span<const std::uint32_t> blocks = {}) const;
    /// EWA only: pass 1 on footprints (any order, any split: the keys are a minimum). cull (may be null):
    /// this key buffer's EwaCull; a splat whose nearest depth lies beyond the largest depth of every
    /// tile under it is not drawn, which changes no key (so no byte of the image) and saves most of
    /// the drawing when the footprints come roughly front to back. Adds to stats.splats_drawn
    /// (splats drawn, culled ones excluded) and stats.fragments.
    void draw(std::span<const EwaFootprint> footprints, std::uint64_t* keys, SplatStats& stats, EwaCull* cull) const;
    /// The visible-depth tiles of the final visibility keys (ewa), for accumulate()'s skipping.
    VisibleDepthTiles depth_tiles(const std::uint64_t* keys) const;
    /// EWA pass 2 against the final visibility keys; acc has acc_words() per pixel. tiles (may be
    /// null): depth_tiles(keys), to skip splats hidden everywhere (the same image, faster).
    void accumulate(std::span<const PointRecord> points, const std::uint64_t* keys, std::int64_t* acc,
                    SplatStats& stats, std::span<const std::uint32_t> blocks = {},
                    const VisibleDepthTiles* tiles = nullptr) const;
    /// As above on the footprints draw() gave (any order, any split): the same sums.
    void accumulate(std::span<const EwaFootprint> footprints, const std::uint64_t* keys, std::int64_t* acc,
                    SplatStats& stats, const VisibleDepthTiles* tiles = nullptr) const;
    /// The instruction set of the EWA loops (footprints, both passes): "avx2" where the CPU has it
    /// (x86-64, detected once per process), else "sse2" (or "scalar" off x86); every variant gives
    /// the same bits, so the image does not depend on the machine.
    const char* ewa_isa() const;
    /// Tests: this frame's EWA loops take the baseline (SSE2) variants.
    void use_baseline_isa() { ewa_avx2_ = false; }
    /// Shades the buffers into img (resized to width x height); acc is unused by the quad kernel.
    void resolve(const std::uint64_t* keys, const std::int64_t* acc, Image& img) const;

    /// dst[i] = min(dst[i], src[i]) over n keys; dst[i] += src[i] over n accumulator words, leaving
    /// dst unwritten where a run of 512 words (4 KiB) of src is all zero (no splat reached those
    /// pixels: their pages of dst may never have been touched, stream/zeroed_buffer.hpp).
    static void merge_keys(std::uint64_t* dst, const std::uint64_t* src, std::size_t n);
    static void merge_acc(std::int64_t* dst, const std::int64_t* src, std::size_t n);

private:
    void init_ewa();
    void draw_quad(std::span<const PointRecord> points, std::uint64_t* keys, SplatStats& stats,
                   std::span<const std::uint32_t> blocks) const;
    void draw_ewa(std::span<const PointRecord> points, std::uint64_t* keys, SplatStats& stats) const;
    void resolve_quad(const std::uint64_t* keys, Image& img) const;
    void resolve_ewa(const std::int64_t* acc, Image& img) const;

    ViewTransform view_;
    ShadingParams shading_;
    SplatKernel kernel_;
    std::vector<float> gauss_;  // ewa: Gaussian over q in [0, cutoff^2]
    bool ewa_avx2_ = false;     // ewa: the AVX2 variants of the loops (see ewa_isa())
};

/// The base colour of point i (0xRRGGBB) under `shading`'s ColorBy (none: shading.base).
std::uint32_t splat_base_color(const ShadingParams& shading, const PointRecord& p, std::span<const std::uint32_t> blocks,
                               std::size_t i);

class SplatRenderer {
public:
    SplatRenderer(const Camera& cam, const ShadingParams& shading, const std::array<Vec3, 2>& bounds);

    void set_camera(const Camera& cam);
    void set_bounds(const std::array<Vec3, 2>& bounds);
    const Camera& camera() const { return cam_; }
    const ViewTransform& view() const { return view_; }

    /// Renders with the current camera. The returned image lives until the next render.
    /// blocks: empty, or one block id per point (ShadingParams::color_by == block).
    const Image& render(std::span<const PointRecord> points, SplatKernel kernel, SplatStats* stats = nullptr,
                        std::span<const std::uint32_t> blocks = {});
    /// Sets the camera's azimuth (degrees) and renders: one frame of a turntable.
    const Image& render(std::span<const PointRecord> points, SplatKernel kernel, double azimuth_deg,
                        SplatStats* stats = nullptr);

private:
    Camera cam_;
    ShadingParams shading_;
    std::array<Vec3, 2> bounds_;
    ViewTransform view_;
    Image image_;
    std::vector<std::uint64_t> key_;   // per pixel: (depth bits << 32) | rgb (quad) or packed normal (ewa)
    std::vector<std::int64_t> acc_;    // ewa: weight, weight * normal (x, y, z) per pixel, fixed point
};

/// One frame; bounds default to point_bounds(points).
Image render_splats(std::span<const PointRecord> points, const Camera& cam, SplatKernel kernel,
                    const ShadingParams& shading, SplatStats* stats = nullptr,
                    std::optional<std::array<Vec3, 2>> bounds = {}, std::span<const std::uint32_t> blocks = {});

}  // namespace meshless
