#include "kernels/make_field.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "kernels/errors.hpp"
#include "kernels/global_rbf_field.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/rbf_grid_field.hpp"

namespace meshless {

std::uint64_t mpu_octree_bytes_estimate(std::uint64_t n, const FieldParams& params) {
    const double N = std::max<double>(1.0, params.mpu_max_points);
    const double grow = std::pow(params.mpu_alpha * std::sqrt(3.0), 3.0);
    const double leaves = std::max(1.0, grow * static_cast<double>(n) / N);
    const double bytes = leaves * (12.0 * N + 128.0);
    return bytes >= 1.8e19 || !std::isfinite(bytes) ? std::numeric_limits<std::uint64_t>::max() : static_cast<std::uint64_t>(bytes);
}

std::unique_ptr<Field> make_field(const PointSet& points, const FieldParams& params, FieldBuildStats* stats,
                                  const FieldProgress& progress, const FitShare* share) {
    const std::string who(field_kind_name(params.kind));
    if (points.pos.size() < 4)
        throw InvalidArgument(who + ": " + std::to_string(points.pos.size()) + " points, at least 4 are needed");
    if (params.kind == FieldKind::mpu && !(params.mpu_alpha <= kMaxMpuAlpha)) {  // (> 0.5: mpu_field.cpp)
        char m[96];
        std::snprintf(m, sizeof m, ": alpha %g is outside (0.5, %g]", params.mpu_alpha, kMaxMpuAlpha);
        throw InvalidArgument(who + m);
    }
    const auto t0 = std::chrono::steady_clock::now();
    FieldBuildStats local;
    FieldBuildStats* st = stats ? stats : &local;
    *st = FieldBuildStats{};
    std::unique_ptr<Field> f;
    switch (params.kind) {
        case FieldKind::rbf_grid: f = std::make_unique<RbfGridField>(points, params, st, progress); break;
        case FieldKind::mpu: f = std::make_unique<MpuField>(points, params, st, progress, share); break;
        case FieldKind::global_rbf: f = std::make_unique<GlobalRbfField>(points, params, st); break;
    }
    st->build_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return f;
}

}  // namespace meshless
