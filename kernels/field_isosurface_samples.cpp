#include "kernels/field_isosurface_samples.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <tbb/parallel_for.h>

#include "kernels/splitmix.hpp"

namespace meshless {

namespace {
bool finite3(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

std::vector<Vec3> sample_field_isosurface(const Field& f, double iso, const Box3& box, const SurfaceSampling& s) {
    const SamplingGrid grid = sampling_grid(box, s);
    const std::int64_t* n = grid.n;
    const double diag = grid.diag, max_move = grid.max_move;
    const Vec3 lo = grid.lo, hi = grid.hi;
    std::vector<std::vector<Vec3>> slab_out(static_cast<std::size_t>(n[2]));
    tbb::parallel_for(std::int64_t{0}, n[2], [&](std::int64_t k) {
        SplitMix rng{s.seed + static_cast<std::uint64_t>(k)};
        const std::size_t m = static_cast<std::size_t>(n[0] * n[1]);
        std::vector<Vec3> x0(m);
        for (std::int64_t j = 0; j < n[1]; ++j)
            for (std::int64_t i = 0; i < n[0]; ++i)
                x0[static_cast<std::size_t>(i + n[0] * j)] = {box.lo.x + (static_cast<double>(i) + rng.unit()) * s.spacing,
                                                              box.lo.y + (static_cast<double>(j) + rng.unit()) * s.spacing,
                                                              box.lo.z + (static_cast<double>(k) + rng.unit()) * s.spacing};
        std::vector<double> v(m);
        std::vector<Vec3> g(m);
        f.evaluate(x0, v, g);
        // the grid points within one spacing of the surface (first order), then Newton on all of them at once
        std::vector<Vec3> start, x;
        for (std::size_t t = 0; t < m; ++t) {
            const double gg = dot(g[t], g[t]);
            if (std::isfinite(v[t]) && gg > 0 && std::isfinite(gg) && std::abs(v[t] - iso) < s.spacing * std::sqrt(gg)) start.push_back(x0[t]);
        }
        x = start;
        std::vector<std::uint8_t> state(x.size(), 0);  // 0 moving, 1 converged, 2 failed
        std::vector<std::size_t> active(x.size());
        for (std::size_t t = 0; t < active.size(); ++t) active[t] = t;
        std::vector<Vec3> q;
        for (int it = 0; it < 30 && !active.empty(); ++it) {
            q.resize(active.size());
            for (std::size_t t = 0; t < active.size(); ++t) q[t] = x[active[t]];
            v.resize(q.size());
            g.resize(q.size());
            f.evaluate(q, v, g);
            std::size_t keep = 0;
            for (std::size_t t = 0; t < active.size(); ++t) {
                const std::size_t a = active[t];
                const double gg = dot(g[t], g[t]);
                if (!std::isfinite(v[t]) || !(gg > 0) || !std::isfinite(gg)) {
                    state[a] = 2;
                    continue;
                }
                const Vec3 step = g[t] * ((v[t] - iso) / gg);
                x[a] = x[a] - step;
                if (norm(step) < 1e-10 * diag) state[a] = 1;
                else active[keep++] = a;
            }
            active.resize(keep);
        }
        std::vector<Vec3>& out = slab_out[static_cast<std::size_t>(k)];
        for (std::size_t t = 0; t < x.size(); ++t) {
            const Vec3& p = x[t];
            if (state[t] != 1 || !finite3(p) || norm(p - start[t]) > max_move) continue;
            if (p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z) continue;
            out.push_back(p);
        }
    });
    std::vector<Vec3> out;
    for (const auto& o : slab_out) out.insert(out.end(), o.begin(), o.end());
    return out;
}

}  // namespace meshless
