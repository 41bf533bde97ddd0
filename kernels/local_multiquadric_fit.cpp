#include "kernels/local_multiquadric_fit.hpp"

#include <algorithm>
#include <vector>

#include "kernels/local_spacing.hpp"

namespace meshless {

LocalFitResult fit_local_multiquadric(MultiquadricSolver& solver, std::span<const Vec3> pos, std::span<const double> value,
                                      std::span<const std::uint32_t> idx, double c_global, const FieldParams& params,
                                      MultiquadricLocal& out, std::span<double> lambda) {
    const bool local_c = params.hardy_c_spacing > 0 || params.hardy_c_rough > 0;
    const double s = local_c ? mean_neighbour_spacing(pos, idx) : 0.0;
    LocalFitResult r;
    r.c = hardy_c_local(params, c_global, s);
    r.fit = solver.fit(pos, value, idx, r.c, out, lambda);
    const bool ill = r.fit.outcome == MultiquadricOutcome::regularised || r.fit.outcome == MultiquadricOutcome::linear_fallback;
    const double narrow = params.hardy_c_rough * s;
    if (!ill || !(narrow > 0) || !(narrow < r.c)) return r;
    const MultiquadricLocal first = out;
    std::vector<double> kept(lambda.begin(), lambda.end());
    const MultiquadricFitResult again = solver.fit(pos, value, idx, narrow, out, lambda);
    if (again.outcome == MultiquadricOutcome::interpolated) {
        r.fit = again;
        r.c = narrow;
        r.refitted = true;
        return r;
    }
    out = first;  // the narrow basis did no better: keep the first fit
    std::copy(kept.begin(), kept.end(), lambda.begin());
    return r;
}

}  // namespace meshless
