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

namespace meshless {

void GlobalRbfField::save_state(FieldStateWriter& w) const {
    put_frame(w, origin_, scale_, bounds_);
    std::vector<double> p;
    p.reserve(3 * pos_.size());
    for (const Vec3& v : pos_) p.insert(p.end(), {v.x, v.y, v.z});
    w.put("points", std::span<const double>(p));
    w.put("lambda", std::span<const double>(lambda_));
    put_locals(w, std::span<const MultiquadricLocal>(&h_, 1));
    const std::uint32_t outcome = static_cast<std::uint32_t>(outcome_);
    w.put("outcome", std::span<const std::uint32_t>(&outcome, 1));
}

std::unique_ptr<GlobalRbfField> GlobalRbfField::load_state(FieldState& s) {
    std::unique_ptr<GlobalRbfField> f(new GlobalRbfField);
    take_frame(s, f->origin_, f->scale_, f->bounds_);
    const std::vector<double> p = s.take_f64("points");
    if (p.empty() || p.size() % 3 != 0) s.fail("points", "array 'points' does not hold 3 values per point");
    const std::size_t n = p.size() / 3;
    if (n > 0xFFFFFFF0u) s.fail("points", "more than 2^32-16 points");
    f->pos_.resize(n);
    for (std::size_t i = 0; i < n; ++i) f->pos_[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
    f->idx_.resize(n);
    std::iota(f->idx_.begin(), f->idx_.end(), 0u);
    f->lambda_ = s.take_f64("lambda", n);
    const std::vector<MultiquadricLocal> h = take_locals(s);
    if (h.size() != 1) s.fail("locals", "a global field has one interpolant, not " + std::to_string(h.size()));
    f->h_ = h[0];
    if (f->h_.first != 0 || (f->h_.count != 0 && f->h_.count != n))
        s.fail("local_ranges", "the interpolant does not span the points");
    const std::uint32_t outcome = s.take_u32("outcome", 1)[0];
    if (outcome > static_cast<std::uint32_t>(MultiquadricOutcome::polynomial_only)) s.fail("outcome", "unknown fit outcome");
    f->outcome_ = static_cast<MultiquadricOutcome>(outcome);
    return f;
}

}  // namespace meshless
