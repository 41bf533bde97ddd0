#include "kernels/field_newton_projection.hpp"

#include <cassert>
#include <cmath>
#include <vector>

namespace meshless {

namespace {

bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

struct Walker {
    std::size_t index;     ///< seed index
    double residual;       ///< f(p) - iso at the accepted position pos[index]
    double lambda = 1.0;   ///< step scale (halved on rejection)
    int halvings = 0;      ///< consecutive rejections
    int iterations = 0;    ///< evaluations after the seed's
};

void finish(FieldNewtonStatus s, std::size_t i, std::span<FieldNewtonStatus> status, FieldNewtonStats& st) {
    status[i] = s;
    switch (s) {
        case FieldNewtonStatus::converged: ++st.converged; break;
        case FieldNewtonStatus::flat: ++st.flat; break;
        case FieldNewtonStatus::too_far: ++st.too_far; break;
        case FieldNewtonStatus::not_converged: ++st.not_converged; break;
        case FieldNewtonStatus::stalled: ++st.stalled; break;
        case FieldNewtonStatus::nonfinite: ++st.nonfinite; break;
    }
}

}  // namespace

void project_onto_field(const Field& f, double iso, std::span<const Vec3> seeds, const FieldNewtonParams& params,
                        std::span<const double> max_displacement, std::span<Vec3> pos, std::span<Vec3> grad,
                        std::span<FieldNewtonStatus> status, FieldNewtonStats& stats, std::span<const double> tolerance) {
    const std::size_t n = seeds.size();
    assert(pos.size() == n && grad.size() == n && status.size() == n);
    assert(max_displacement.empty() || max_displacement.size() == n);
    assert(tolerance.empty() || tolerance.size() == n);
    stats.input += static_cast<std::int64_t>(n);
    if (n == 0) return;

    std::vector<double> value(n);
    for (std::size_t i = 0; i < n; ++i) pos[i] = seeds[i];
    f.evaluate(seeds, value, grad);
    stats.evaluations += static_cast<std::int64_t>(n);

    // a point converges when its first-order distance |f - iso| / |grad| is within tolerance
    auto settled = [&](double r, const Vec3& g, std::size_t i) {
        const double tol = tolerance.empty() ? params.tolerance : tolerance[i];
        if (!(dot(g, g) > 0.0)) {
            finish(FieldNewtonStatus::flat, i, status, stats);
            return true;
        }
        if (std::abs(r) <= tol * norm(g)) {
            // the last Newton step, whose length is within the tolerance, taken without evaluating
            // again (quadratic convergence puts p' far closer to the surface than p)
            if (params.final_step) pos[i] = pos[i] + g * (-r / dot(g, g));
            finish(FieldNewtonStatus::converged, i, status, stats);
            return true;
        }
        return false;
    };

    std::vector<Walker> active;
    active.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double r = value[i] - iso;
        if (!std::isfinite(r) || !finite(grad[i])) {
            finish(FieldNewtonStatus::nonfinite, i, status, stats);
            continue;
        }
        if (settled(r, grad[i], i)) continue;
        if (params.max_iterations <= 0) {
            finish(FieldNewtonStatus::not_converged, i, status, stats);
            continue;
        }
        active.push_back({i, r});
    }

    std::vector<Vec3> cand, cand_grad;
    std::vector<double> cand_value;
    std::vector<Walker> next;
    next.reserve(active.size());
    while (!active.empty()) {
        // candidates of every walker that may still move, in seed order (deterministic)
        cand.clear();
        next.clear();
        for (const Walker& w : active) {
            const Vec3& g = grad[w.index];
            const Vec3 q = pos[w.index] + g * (-w.residual / dot(g, g) * w.lambda);
            const double md = max_displacement.empty() ? params.max_displacement : max_displacement[w.index];
            const Vec3 d = q - seeds[w.index];
            if (dot(d, d) > md * md) {
                finish(FieldNewtonStatus::too_far, w.index, status, stats);
                continue;
            }
            cand.push_back(q);
            next.push_back(w);
        }
        if (cand.empty()) break;
        cand_value.resize(cand.size());
        cand_grad.resize(cand.size());
        f.evaluate(cand, cand_value, cand_grad);
        stats.evaluations += static_cast<std::int64_t>(cand.size());

        active.clear();
        for (std::size_t c = 0; c < cand.size(); ++c) {
            Walker w = next[c];
            ++w.iterations;
            const double r = cand_value[c] - iso;
            if (std::isfinite(r) && finite(cand_grad[c]) && std::abs(r) < std::abs(w.residual)) {
                pos[w.index] = cand[c];
                grad[w.index] = cand_grad[c];
                w.residual = r;
                w.lambda = 1.0;
                w.halvings = 0;
                if (settled(r, cand_grad[c], w.index)) continue;
            } else {
                w.lambda *= 0.5;
                if (++w.halvings > params.max_halvings) {
                    finish(FieldNewtonStatus::stalled, w.index, status, stats);
                    continue;
                }
            }
            if (w.iterations >= params.max_iterations) {
                finish(FieldNewtonStatus::not_converged, w.index, status, stats);
                continue;
            }
            active.push_back(w);
        }
    }
}

const char* to_string(FieldNewtonStatus s) {
    switch (s) {
        case FieldNewtonStatus::converged: return "converged";
        case FieldNewtonStatus::flat: return "flat";
        case FieldNewtonStatus::too_far: return "too far";
        case FieldNewtonStatus::not_converged: return "not converged";
        case FieldNewtonStatus::stalled: return "stalled";
        case FieldNewtonStatus::nonfinite: return "non-finite";
    }
    return "?";
}

}  // namespace meshless
