#include "kernels/global_rbf_field.hpp"

#include <numeric>
#include <string>

#include "kernels/errors.hpp"
#include "kernels/field_input.hpp"

namespace meshless {

GlobalRbfField::GlobalRbfField(const PointSet& points, const FieldParams& params, FieldBuildStats* stats) {
    FieldBuildStats local_stats;
    FieldBuildStats& st = stats ? *stats : local_stats;
    MergedPoints m = prepare_field_points(points, params, "global-rbf", &st);
    if (m.pos.size() > params.global_max_points)
        throw InvalidArgument("global-rbf: " + std::to_string(m.pos.size()) + " distinct points, more than the limit of " +
                              std::to_string(params.global_max_points) + " (use rbf-grid or mpu)");
    origin_ = m.origin;
    scale_ = m.scale;
    bounds_ = points.bounds();
    pos_ = std::move(m.pos);
    idx_.resize(pos_.size());
    std::iota(idx_.begin(), idx_.end(), 0u);
    lambda_.assign(pos_.size(), 0.0);
    const double c = hardy_c_world_for(params, bounds_);
    MultiquadricSolver solver;
    h_.first = 0;
    const MultiquadricFitResult r = solver.fit(pos_, m.value, idx_, c, h_, lambda_);
    outcome_ = r.outcome;
    st.locals = 1;
    st.interpolated = r.outcome == MultiquadricOutcome::interpolated;
    st.regularised = r.outcome == MultiquadricOutcome::regularised;
    st.linear_fallback = r.outcome == MultiquadricOutcome::linear_fallback;
    st.polynomial_only = r.outcome == MultiquadricOutcome::polynomial_only;
    st.rank_deficient = r.poly_rank < 4;
    st.max_local_points = pos_.size();
    st.mean_local_points = static_cast<double>(pos_.size());
    st.memory_bytes = pos_.size() * (sizeof(Vec3) + sizeof(std::uint32_t) + sizeof(double));
}

void GlobalRbfField::evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const {
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 d = p[i] - origin_;
        const Vec3 x{d.x * scale_.x, d.y * scale_.y, d.z * scale_.z};
        value[i] = multiquadric_evaluate(h_, pos_.data(), idx_.data(), lambda_.data(), x, grad.empty() ? nullptr : &grad[i]);
        if (!grad.empty()) grad[i] = {grad[i].x * scale_.x, grad[i].y * scale_.y, grad[i].z * scale_.z};
    }
}

}  // namespace meshless
