// Whether a local fit's points are flat: coplanar or collinear, so that the linear part of a
// multiquadric fit over them (kernels/multiquadric.hpp: the polynomial [1 x y z], QR with relative
// pivot threshold 1e-10) has rank 3 or 2 and its derivative across their plane or line would be a
// guess. The local fields (kernels/rbf_grid_field.hpp, kernels/mpu_field.hpp) then add the nearest
// points off that hull to the fit. Layered data and curvilinear grids whose planes lie farther apart
// than the fields' cells make such locals (the blunt fin's x-planes, 1.5-3.5 units apart).
// Flat: the smallest eigenvalue of the points' covariance is below 1e-12 of the largest (a thickness
// below 1e-6 of the spread, which also absorbs the rounding of the one-pass moments); a line when
// the middle one is too. Off the hull: farther than 1e-4 of the spread. Units: world. Reentrant;
// throws nothing.
// Dissertation: sections 4.3 and 5.5 (the local fits of the RBF grid and the MPU octree).
#pragma once
#include <cstdint>
#include <optional>
#include <span>

#include "kernels/vec3.hpp"

namespace meshless {

/// Count, sum and sum of outer products of points taken relative to `ref` (add() takes p - ref).
struct PointMoments {
    Vec3 ref{0, 0, 0};
    std::uint32_t count = 0;
    double sum[3] = {0, 0, 0};
    double sq[6] = {0, 0, 0, 0, 0, 0};  ///< xx, xy, xz, yy, yz, zz
    void add(const Vec3& e) {
        sum[0] += e.x, sum[1] += e.y, sum[2] += e.z;
        sq[0] += e.x * e.x, sq[1] += e.x * e.y, sq[2] += e.x * e.z;
        sq[3] += e.y * e.y, sq[4] += e.y * e.z, sq[5] += e.z * e.z;
        ++count;
    }
};

/// The plane (nacross = 1) or line (2) the points lie in: their mean `o`, the unit directions
/// `across` they do not vary along, and their spread (square root of the largest eigenvalue).
struct FlatHull {
    Vec3 o{0, 0, 0};
    Vec3 across[2];
    int nacross = 0;
    double spread = 0;
    /// True when p lies off the hull by more than 1e-4 of the spread.
    bool off(const Vec3& p) const;
};

/// nullopt when the points span 3-D (or are fewer than 2, or all one point).
std::optional<FlatHull> flat_hull(const PointMoments& m);
/// Whether a whole point set is flat (all in one plane or line: 2-D scattered data): no local fit
/// of it can find a point off its plane, so the fields skip the search. False when empty.
bool all_flat(std::span<const Vec3> pts);

}  // namespace meshless
