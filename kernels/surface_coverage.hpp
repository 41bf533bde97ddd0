// The crack-free oracle of the multiblock isosurface (dissertation chapter 4, Figures 4.6-4.8: cracks and holes where
// blocks meet): how completely and how accurately a set of oriented, sized points (splats) covers
// the true isosurface of an analytic field (kernels/analytic_volumes.hpp).
//
// 1. sample_isosurface: a dense sampling of the true isosurface f = iso inside a box (the data
//    domain). Points of a jittered grid of spacing `spacing` (one point uniformly at random in each
//    grid cube, SplitMix seeded by `seed`, so the set is reproducible) whose first-order distance
//    |f - iso| / |grad f| is below `spacing` are projected by Newton steps along the gradient
//    (x -= (f - iso) grad f / |grad f|^2, at most 30, until the step < 1e-12 of the box diagonal);
//    a point is kept when it converged, moved less than `spacing` * sqrt(3) and lies in the box
//    shrunk by `margin`. Density: about 2/spacing^2 samples per unit area (each surface patch
//    receives the grid points within one spacing on either side), nearly uniform for spacing much
//    smaller than the curvature radii, so fractions of samples estimate fractions of area with a
//    binomial standard error sqrt(p(1-p)/N).
// 2. surface_coverage: a surface sample s is covered when some output point p_i satisfies
//    |s - p_i| <= radius_i (one splat radius; the splat is a disc of that radius around p_i, and a
//    point is counted against the sphere of that radius, i.e. a disc tilted by less than the
//    surface's own curvature still reaches it). Uniform hash grid of cell size = the largest radius
//    (no kd-tree: nanoflann stays in one file of the project), 27 neighbour cells per query.
// 3. point_errors: per output point, the distance to the true surface (analytic_distance: exact for
//    sphere and torus, an upper-bound estimate for gyroid / ML) and the normal error in degrees
//    against the analytic normal of VTK's convention, -grad f (towards decreasing values):
//    acos(-n . g / (|n||g|)), 0..180 (a flipped normal is an error of 180 - its tilt); the number
//    of normals pointing towards increasing values (n . g > 0, against the convention) is also
//    reported apart as `reversed`, so a consistently flipped set is named as such.
// Units: world units, degrees. Points or radii that are not finite are counted in `nonfinite` and
// take no part. Throws InvalidArgument on spacing <= 0, an empty/inverted box, or points and radii
// (normals) of different lengths. Reentrant, single-threaded.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "kernels/analytic_volumes.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct Box3 {
    Vec3 lo, hi;
};

struct SurfaceSampling {
    double spacing = 0.01;     ///< jittered grid spacing, world units
    double margin = 0.0;       ///< samples closer than this to the box faces are dropped
    std::uint64_t seed = 1;
};

std::vector<Vec3> sample_isosurface(AnalyticField f, double iso, const Box3& box, const SurfaceSampling& s = {});

/// The jittered grid both samplers walk (this one and kernels/field_isosurface_samples.hpp): cells per
/// axis, the box diagonal, the kept region (the box shrunk by the margin) and the largest Newton move.
/// Throws InvalidArgument on spacing <= 0, an empty/inverted box, over 1e5 cells per axis.
struct SamplingGrid {
    std::int64_t n[3] = {1, 1, 1};
    double diag = 0;
    Vec3 lo, hi;  ///< kept region
    double max_move = 0;
};
SamplingGrid sampling_grid(const Box3& box, const SurfaceSampling& s);

struct CoverageResult {
    std::size_t samples = 0;    ///< surface samples tested
    std::size_t covered = 0;    ///< within one radius of some point
    std::size_t nonfinite = 0;  ///< output points skipped (NaN/Inf position or radius, radius <= 0)
    double fraction() const { return samples ? static_cast<double>(covered) / static_cast<double>(samples) : 0.0; }
};

/// `covered_mask`, when non-null, receives one flag per sample (1 = covered).
CoverageResult surface_coverage(std::span<const Vec3> samples, std::span<const Vec3> points, std::span<const float> radii,
                                std::vector<std::uint8_t>* covered_mask = nullptr);

struct PointErrors {
    std::size_t points = 0;          ///< finite points measured
    double mean_distance = 0, max_distance = 0;
    double mean_normal_deg = 0, max_normal_deg = 0;  ///< angle to -grad f, over points with a finite unit normal
    std::size_t normals = 0;         ///< points whose normal and gradient are non-zero
    std::size_t reversed = 0;        ///< normals with n . grad f > 0 (towards increasing values)
};

/// `normals` may be empty (no normal statistics).
PointErrors point_errors(AnalyticField f, double iso, std::span<const Vec3> points, std::span<const Vec3> normals);

}  // namespace meshless
