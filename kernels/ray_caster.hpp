// Direct volume rendering by ray casting a Field (dissertation section 6.6 / Figure 6.6: the LOD
// fields of a cluster hierarchy volume rendered next to the original and differenced; section 7.4:
// volume rendering of scattered data). The field itself is sampled along each ray (trilinear for
// grids, the meshless fields for scattered data): nothing is resampled onto a grid first.
//
// Model (emission-absorption, front to back): ray r(t) = o + t d (|d| = 1, t in world units)
// through the pixel centre; the part inside `box` [t0, t1] is cut into segments of `step` (the last
// one shorter), each sampled once at its midpoint. A sample of value v takes colour c and opacity a
// from the transfer function; a is per `ref_step` and corrected to the segment length L:
//     a' = 1 - (1 - a)^(L / ref_step)
// so halving the step leaves the picture (nearly) unchanged. Compositing, front to back:
//     C += (1 - A) a' c,   A += (1 - A) a'
// and the pixel is C + (1 - A) background. A constant field of opacity a over a depth D therefore
// gives exactly A = 1 - (1 - a)^(D / ref_step) (the slab test of tests/kernels/test_ray_caster.cpp).
// Early ray termination: a ray stops once A >= termination. Empty-space skipping: with a
// ValueBoundsGrid, samples inside a macro cell whose value interval the transfer function maps to
// opacity 0 are not evaluated (they would add nothing; kernels/value_bounds_grid.hpp says how exact
// the intervals are; an empty interval, vmin > vmax, marks a cell without data, never sampled).
// Samples stay at the same positions whether or not cells are skipped.
// Shading (optional): headlight Phong with the normal -grad f / |grad f| (VTK's convention; two-sided,
// so the lighting does not depend on the sign):
//     c' = c (ambient + diffuse |n.l|) + specular |n.l|^shininess,  l = -d
// (a sample whose gradient vanishes is unshaded: c' = c (ambient + diffuse)). With
// RayCastParams::gradient_step set (volumes: the voxel spacing), the shading gradient is the
// central difference of the field's values over +-step along each axis instead of the field's own
// gradient: a trilinear interpolant's gradient jumps at every cell face, so shading with it draws
// each voxel cell as a facet (a checkerboard on smooth blobs, a lattice of lines at grazing light),
// while the central differences change continuously, as VTK's volume mappers' voxel gradients do.
// Only the samples that reach the pixel (opacity > 0, before early termination) pay for them: six
// value-only evaluations each, batched. A NaN on one side falls back to the one-sided difference.
// Transfer-function lookups go through a table of 4096 entries over the control points' value range,
// linearly interpolated (differences from TransferFunction::at stay within 1/4096 of the range
// around kinks and steps).
// NaN field values (outside a meshless field's coverage) are transparent.
//
// Camera: kernels/camera.hpp (orbit about the box centre; pixel (i, j) has its centre at
// (i + 0.5, j + 0.5)); perspective rays start at the eye, orthographic rays are parallel.
// Threads: pixels are rendered in tiles of RayCastParams::tile pixels, distributed over `threads`
// oneTBB workers (a task_arena); each pixel's value depends only on its own ray, so the image bytes
// do not depend on the thread count or the tiling. Field::evaluate is called concurrently
// (fields are thread-safe). progress (optional) is called with the finished fraction, serialised
// (never concurrently), at most once per tile.
// RayCastParts casts the same picture in parts along z (a field one slab at a time), each ray
// going on from where it stood.
// Throws InvalidArgument for step/ref_step not positive and finite, termination outside (0, 1],
// or a ray of more than 2^26 samples; whatever Field::evaluate throws (std::bad_alloc).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "kernels/camera.hpp"
#include "kernels/field.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "kernels/transfer_function.hpp"
#include "kernels/value_bounds_grid.hpp"

namespace meshless {

struct RayCastParams {
    double step = 0;       ///< world units between samples along a ray, > 0
    double ref_step = 0;   ///< the slab thickness the transfer function's opacities are for, > 0
    bool shade = false;    ///< headlight Phong from the field gradient
    /// shade: 0 (the field's own gradient), or per axis the step (world units, all three > 0) of the
    /// central differences that give the shading gradient instead (see above)
    std::array<double, 3> gradient_step{0, 0, 0};
    double ambient = 0.3, diffuse = 0.7, specular = 0.25, shininess = 20;
    double termination = 0.99;  ///< stop a ray once its accumulated opacity reaches this, (0, 1]
    std::array<double, 3> background{0, 0, 0};  ///< components in [0, 1]
    int tile = 32;          ///< tile edge in pixels (work unit of the threads), >= 1
};

struct RayCastStats {
    std::uint64_t rays = 0;        ///< pixels
    std::uint64_t rays_hit = 0;    ///< rays that meet the box
    std::uint64_t samples = 0;     ///< field evaluations
    std::uint64_t skipped = 0;     ///< samples not evaluated (empty space)
    std::uint64_t terminated = 0;  ///< rays stopped early (opacity reached termination)
};

/// Premultiplied colour and opacity per pixel: {C_r, C_g, C_b, A}, row-major, top row first,
/// before the background is added.
struct RgbaImage {
    int width = 0, height = 0;
    std::vector<float> rgba;
};

/// Renders `field` inside `box` as seen by `view`. skip: optional empty-space structure.
RgbaImage ray_cast_rgba(const Field& field, const std::array<Vec3, 2>& box, const ViewTransform& view,
                        const TransferFunction& tf, const RayCastParams& params, const ValueBoundsGrid* skip, int threads,
                        RayCastStats* stats = nullptr, const std::function<void(double)>& progress = {});

/// A picture cast in parts along z, for a field that exists one z range at a time (a point store's,
/// slab by slab: stream/store_render.hpp). Every ray keeps where it stands between the parts (its
/// next sample, the colour and opacity so far, its empty-space cell), so the picture is
/// ray_cast_rgba's, bit for bit, however the parts cut it, provided each ray meets its samples in
/// order: advance() the rays whose z rises (or stays) through parts of rising z, and those whose z
/// falls through parts of falling z. Memory: 64 bytes a pixel. Throws as ray_cast_rgba; the
/// constructor throws the parameters' errors and that of a ray of more than 2^26 samples.
class RayCastParts {
public:
    RayCastParts(const std::array<Vec3, 2>& box, const ViewTransform& view, const TransferFunction& tf,
                 const RayCastParams& params, const ValueBoundsGrid* skip);
    ~RayCastParts();
    RayCastParts(const RayCastParts&) = delete;
    RayCastParts& operator=(const RayCastParts&) = delete;
    /// Whether a ray going `rising` (its z rises or stays) or not has samples left.
    bool pending(bool rising) const;
    /// Advances the rays going `rising` through their samples whose midpoint z lies in [z[0], z[1])
    /// ([z[0], z[1]] when `closed`), evaluating `field` there, on `threads` threads (the picture does
    /// not depend on them); each stops at its first sample beyond the range, or ends. The field must
    /// hold there (and, with gradient_step, one step beyond along every axis).
    void advance(const Field& field, bool rising, const std::array<double, 2>& z, bool closed, int threads);
    /// The picture so far (ray_cast_rgba's once every ray has ended).
    RgbaImage image() const;
    const RayCastStats& stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// The 8-bit picture of a premultiplied image over params.background: round(255 (C + (1 - A) bg)).
Image compose_over_background(const RgbaImage& img, const std::array<double, 3>& background);

}  // namespace meshless
