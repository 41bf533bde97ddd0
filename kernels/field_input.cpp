#include "kernels/point_set.hpp"
#include "kernels/field_input.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "kernels/errors.hpp"

namespace meshless {

MergedPoints prepare_field_points(const PointSet& points, const FieldParams& params, std::string_view who,
                                  FieldBuildStats* stats) {
    const std::string w(who);
    if (points.pos.size() != points.value.size())
        throw FormatError(w + ": point set has " + std::to_string(points.pos.size()) + " positions but " +
                          std::to_string(points.value.size()) + " values");
    if (points.pos.empty()) throw InvalidArgument(w + ": the point set is empty");
    if (points.pos.size() > 0xFFFFFFF0ull)
        throw InvalidArgument(w + ": " + std::to_string(points.pos.size()) + " points, at most 4294967280 supported");
    for (std::size_t i = 0; i < points.pos.size(); ++i) {
        const Vec3& p = points.pos[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(points.value[i]))
            throw FormatError(w + ": point " + std::to_string(i) + " has a non-finite coordinate or value");
    }
    if (!(params.merge_rel >= 0) || !(params.hardy_c_rel > 0) || !std::isfinite(params.hardy_c_world) ||
        params.hardy_c_world < 0)
        throw InvalidArgument(w + ": merge_rel must be >= 0, hardy_c_rel > 0 and hardy_c_world >= 0");
    const double tol = params.merge_rel * mean_point_spacing(points.pos);
    MergedPoints m = merge_near_duplicates(points.pos, points.value, tol);
    if (m.pos.size() < 4)
        throw InvalidArgument(w + ": " + std::to_string(m.pos.size()) + " distinct points (of " +
                              std::to_string(points.pos.size()) + " after merging near-duplicates), at least 4 are needed");
    if (params.normalise_axes && m.pos.size() > 1) {
        const auto [lo, hi] = bounding_box(m.pos);
        const Vec3 w = hi - lo;
        const double wmax = std::max({w.x, w.y, w.z});
        double sum2 = 0;
        int k = 0;
        for (int a = 0; a < 3; ++a)
            if (w[a] > 1e-9 * wmax) { sum2 += w[a] * w[a]; ++k; }
        if (k > 0) {
            const double edge = std::sqrt(sum2 / k);  // cube edge with the same diagonal
            double sc[3];
            for (int a = 0; a < 3; ++a) sc[a] = w[a] > 1e-9 * wmax ? edge / w[a] : 1.0;
            m.scale = {sc[0], sc[1], sc[2]};
            for (Vec3& p : m.pos) p = {p.x * sc[0], p.y * sc[1], p.z * sc[2]};
        }
    }
    if (stats) {
        stats->input_points = points.pos.size();
        stats->merged_points = m.merged;
        stats->used_points = m.pos.size();
        stats->merge_tolerance = m.tolerance;
        stats->hardy_c_world = hardy_c_world_for(params, points.bounds());
    }
    return m;
}

}  // namespace meshless
