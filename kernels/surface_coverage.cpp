#include "kernels/surface_coverage.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "kernels/errors.hpp"
#include "kernels/splitmix.hpp"

namespace meshless {

namespace {

bool finite(const Vec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

}  // namespace

SamplingGrid sampling_grid(const Box3& box, const SurfaceSampling& s) {
    if (!(s.spacing > 0) || !std::isfinite(s.spacing)) throw InvalidArgument("surface sampling: the spacing must be > 0");
    if (!(box.hi.x > box.lo.x && box.hi.y > box.lo.y && box.hi.z > box.lo.z) || !finite(box.lo) || !finite(box.hi))
        throw InvalidArgument("surface sampling: empty or inverted box");
    SamplingGrid g;
    for (int a = 0; a < 3; ++a) {
        const double c = std::ceil((box.hi[a] - box.lo[a]) / s.spacing);
        if (c > 1e5) throw InvalidArgument("surface sampling: the spacing is too fine for the box (over 1e5 cells per axis)");
        g.n[a] = std::max<std::int64_t>(1, static_cast<std::int64_t>(c));
    }
    g.diag = norm(box.hi - box.lo);
    g.lo = {box.lo.x + s.margin, box.lo.y + s.margin, box.lo.z + s.margin};
    g.hi = {box.hi.x - s.margin, box.hi.y - s.margin, box.hi.z - s.margin};
    g.max_move = s.spacing * std::sqrt(3.0);
    return g;
}

std::vector<Vec3> sample_isosurface(AnalyticField f, double iso, const Box3& box, const SurfaceSampling& s) {
    const SamplingGrid grid = sampling_grid(box, s);
    const std::int64_t* n = grid.n;
    const double diag = grid.diag, max_move = grid.max_move;
    const Vec3 lo = grid.lo, hi = grid.hi;
    SplitMix rng{s.seed};
    std::vector<Vec3> out;
    for (std::int64_t k = 0; k < n[2]; ++k)
        for (std::int64_t j = 0; j < n[1]; ++j)
            for (std::int64_t i = 0; i < n[0]; ++i) {
                const Vec3 x0{box.lo.x + (static_cast<double>(i) + rng.unit()) * s.spacing,
                              box.lo.y + (static_cast<double>(j) + rng.unit()) * s.spacing,
                              box.lo.z + (static_cast<double>(k) + rng.unit()) * s.spacing};
                const double f0 = analytic_value(f, x0) - iso;
                const Vec3 g0 = analytic_gradient(f, x0);
                const double gg0 = dot(g0, g0);
                if (!(gg0 > 0) || std::abs(f0) >= s.spacing * std::sqrt(gg0)) continue;
                Vec3 x = x0;
                bool converged = false;
                for (int it = 0; it < 30; ++it) {
                    const double fv = analytic_value(f, x) - iso;
                    const Vec3 g = analytic_gradient(f, x);
                    const double gg = dot(g, g);
                    if (!(gg > 0)) break;
                    const Vec3 step = g * (fv / gg);
                    x = x - step;
                    if (norm(step) < 1e-12 * diag) {
                        converged = true;
                        break;
                    }
                }
                if (!converged || !finite(x) || norm(x - x0) > max_move) continue;
                if (x.x < lo.x || x.y < lo.y || x.z < lo.z || x.x > hi.x || x.y > hi.y || x.z > hi.z) continue;
                out.push_back(x);
            }
    return out;
}

CoverageResult surface_coverage(std::span<const Vec3> samples, std::span<const Vec3> points, std::span<const float> radii,
                                std::vector<std::uint8_t>* covered_mask) {
    if (points.size() != radii.size())
        throw InvalidArgument("coverage: " + std::to_string(points.size()) + " points but " + std::to_string(radii.size()) + " radii");
    CoverageResult r;
    r.samples = samples.size();
    if (covered_mask) covered_mask->assign(samples.size(), 0);
    std::vector<std::uint32_t> use;
    double rmax = 0;
    Vec3 lo{INFINITY, INFINITY, INFINITY};
    for (std::size_t i = 0; i < points.size(); ++i) {
        const double rad = radii[i];
        if (!finite(points[i]) || !std::isfinite(rad) || !(rad > 0)) {
            ++r.nonfinite;
            continue;
        }
        use.push_back(static_cast<std::uint32_t>(i));
        rmax = std::max(rmax, rad);
        lo = {std::min(lo.x, points[i].x), std::min(lo.y, points[i].y), std::min(lo.z, points[i].z)};
    }
    if (use.empty() || samples.empty()) return r;
    // cells of edge rmax, keys packed 21 bits per axis (cell indices clamped into range: a clamped
    // cell only merges far-away cells, which the exact distance test then rejects)
    const double cell = rmax;
    const auto cidx = [&](double v, double o) {
        const double c = std::floor((v - o) / cell);
        return static_cast<std::int64_t>(std::clamp(c, -1.0, 2097150.0)) + 1;  // 0 .. 2^21 - 1
    };
    const auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
        return static_cast<std::uint64_t>(x) | (static_cast<std::uint64_t>(y) << 21) | (static_cast<std::uint64_t>(z) << 42);
    };
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
    keyed.reserve(use.size());
    for (const std::uint32_t i : use)
        keyed.push_back({key(cidx(points[i].x, lo.x), cidx(points[i].y, lo.y), cidx(points[i].z, lo.z)), i});
    std::sort(keyed.begin(), keyed.end());
    for (std::size_t s = 0; s < samples.size(); ++s) {
        const Vec3& q = samples[s];
        if (!finite(q)) continue;
        const std::int64_t cx = cidx(q.x, lo.x), cy = cidx(q.y, lo.y), cz = cidx(q.z, lo.z);
        bool hit = false;
        for (std::int64_t dz = -1; dz <= 1 && !hit; ++dz)
            for (std::int64_t dy = -1; dy <= 1 && !hit; ++dy)
                for (std::int64_t dx = -1; dx <= 1 && !hit; ++dx) {
                    const std::int64_t x = cx + dx, y = cy + dy, z = cz + dz;
                    if (x < 0 || y < 0 || z < 0 || x > 2097151 || y > 2097151 || z > 2097151) continue;
                    const std::uint64_t k = key(x, y, z);
                    auto it = std::lower_bound(keyed.begin(), keyed.end(), std::make_pair(k, std::uint32_t{0}));
                    for (; it != keyed.end() && it->first == k; ++it) {
                        const Vec3 d = q - points[it->second];
                        const double rad = radii[it->second];
                        if (dot(d, d) <= rad * rad) {
                            hit = true;
                            break;
                        }
                    }
                }
        if (hit) {
            ++r.covered;
            if (covered_mask) (*covered_mask)[s] = 1;
        }
    }
    return r;
}

PointErrors point_errors(AnalyticField f, double iso, std::span<const Vec3> points, std::span<const Vec3> normals) {
    if (!normals.empty() && normals.size() != points.size())
        throw InvalidArgument("point errors: " + std::to_string(points.size()) + " points but " +
                              std::to_string(normals.size()) + " normals");
    PointErrors e;
    double sum_d = 0, sum_a = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!finite(points[i])) continue;
        const double d = analytic_distance(f, iso, points[i]);
        if (!std::isfinite(d)) continue;
        ++e.points;
        sum_d += d;
        e.max_distance = std::max(e.max_distance, d);
        if (normals.empty()) continue;
        const Vec3 g = analytic_gradient(f, points[i]);
        const double ng = norm(normals[i]) * norm(g);
        if (!(ng > 0) || !std::isfinite(ng)) continue;
        const double c = -dot(normals[i], g) / ng;  // cosine to -grad f, VTK's normal
        if (c < 0) ++e.reversed;
        const double deg = std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / std::numbers::pi;
        ++e.normals;
        sum_a += deg;
        e.max_normal_deg = std::max(e.max_normal_deg, deg);
    }
    if (e.points) e.mean_distance = sum_d / static_cast<double>(e.points);
    if (e.normals) e.mean_normal_deg = sum_a / static_cast<double>(e.normals);
    return e;
}

}  // namespace meshless
