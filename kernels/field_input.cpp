#include "kernels/point_set.hpp"
#include "kernels/field_input.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "kernels/errors.hpp"
#include "kernels/morton.hpp"

namespace meshless {

MergedPoints prepare_field_points(const PointSet& points, const FieldParams& params, std::string_view who,
                                  FieldBuildStats* stats) {
    return prepare_field_points(points, params, who, stats, field_frame_of(points.pos));
}

std::array<Vec3, 2> frame_box(const MergedPoints& m, const std::array<Vec3, 2>& world) {
    const Vec3 lo = world[0] - m.origin, hi = world[1] - m.origin;
    return {Vec3{lo.x * m.scale.x, lo.y * m.scale.y, lo.z * m.scale.z}, Vec3{hi.x * m.scale.x, hi.y * m.scale.y, hi.z * m.scale.z}};
}

MergedPoints prepare_field_points(const PointSet& points, const FieldParams& params, std::string_view who,
                                  FieldBuildStats* stats, const FieldFrame& frame) {
    const std::string w(who);
    if (points.pos.size() != points.value.size())
        throw FormatError(w + ": point set has " + std::to_string(points.pos.size()) + " positions but " +
                          std::to_string(points.value.size()) + " values");
    if (points.pos.empty()) throw FormatError(w + ": the point set is empty");
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
    const double tol = params.merge_rel * mean_point_spacing(frame.bounds, frame.points);
    MergedPoints m = merge_near_duplicates(points.pos, points.value, tol, frame.bounds, frame.points);
    if (m.pos.size() < 4)
        throw FormatError(w + ": " + std::to_string(m.pos.size()) + " distinct points (of " +
                              std::to_string(points.pos.size()) + " after merging near-duplicates), at least 4 are needed");
    if (params.normalise_axes && m.pos.size() > 1) {
        const auto [lo, hi] = frame_box(m, frame.bounds);  // (the whole set's, relative to the origin)
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
        stats->hardy_c_world = hardy_c_world_for(params, frame.bounds);
    }
    return m;
}

void morton_order_points(MergedPoints& m, const Vec3& lo, const Vec3& hi) {
    const std::size_t n = m.pos.size();
    const Vec3 w = hi - lo;
    const double wm = std::max({w.x, w.y, w.z});
    const double k = wm > 0 ? 2097151.0 / wm : 0.0;  // 21 bits per axis
    std::vector<std::pair<std::uint64_t, std::uint32_t>> key(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            const Vec3 u = (m.pos[i] - lo) * k;
            auto axis = [](double v) { return static_cast<std::uint32_t>(std::clamp(v, 0.0, 2097151.0)); };
            key[i] = {morton_encode(axis(u.x), axis(u.y), axis(u.z)), static_cast<std::uint32_t>(i)};
        }
    });
    tbb::parallel_sort(key.begin(), key.end());  // the (key, index) pairs are distinct: deterministic
    std::vector<Vec3> pos(n);
    std::vector<double> value(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            pos[i] = m.pos[key[i].second];
            value[i] = m.value[key[i].second];
        }
    });
    m.pos.swap(pos);
    m.value.swap(value);
}

}  // namespace meshless
