#include "kernels/local_multiquadric_fit.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "kernels/local_spacing.hpp"

namespace meshless {

namespace {
// Ranks two fits of the same points: an interpolating fit beats a regularised one (which no longer
// reproduces its data), which beats the linear fallback; between fits of the same outcome, the one
// with the smaller leave-one-out error wins.
int outcome_rank(const MultiquadricFitResult& f) {
    switch (f.outcome) {
        case MultiquadricOutcome::interpolated: return 0;
        case MultiquadricOutcome::regularised: return 1;
        default: return 2;
    }
}
double loo_score(const MultiquadricFitResult& f) { return f.loo < 0 ? std::numeric_limits<double>::infinity() : f.loo; }
bool better(const MultiquadricFitResult& a, const MultiquadricFitResult& b) {
    if (outcome_rank(a) != outcome_rank(b)) return outcome_rank(a) < outcome_rank(b);
    return loo_score(a) < loo_score(b);
}
}  // namespace

LocalFitResult fit_local_multiquadric(MultiquadricSolver& solver, std::span<const Vec3> pos, std::span<const double> value,
                                      std::span<const std::uint32_t> idx, double c_global, const FieldParams& params,
                                      MultiquadricLocal& out, std::span<double> lambda) {
    const bool local_c = params.hardy_c_spacing > 0 || params.hardy_c_rough > 0;
    const double s = local_c ? mean_neighbour_spacing(pos, idx) : 0.0;
    LocalFitResult r;
    r.c = hardy_c_local(params, c_global, s);
    const double narrow = params.hardy_c_rough * s;
    const bool second = narrow > 0 && narrow < r.c;
    r.fit = solver.fit(pos, value, idx, r.c, out, lambda, second);
    if (!second || r.fit.outcome == MultiquadricOutcome::polynomial_only || r.fit.loo == 0) return r;
    const MultiquadricLocal first = out;
    std::vector<double> kept(lambda.begin(), lambda.end());
    const MultiquadricFitResult again = solver.fit(pos, value, idx, narrow, out, lambda, true);
    if (better(again, r.fit)) {
        r.fit = again;
        r.c = narrow;
        r.refitted = true;
        return r;
    }
    out = first;  // the wide basis predicts its own points better: keep it
    std::copy(kept.begin(), kept.end(), lambda.begin());
    return r;
}

}  // namespace meshless
