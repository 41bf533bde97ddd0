#include "kernels/make_field.hpp"

#include <chrono>
#include <string>

#include "kernels/errors.hpp"
#include "kernels/global_rbf_field.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/rbf_grid_field.hpp"

namespace meshless {

std::unique_ptr<Field> make_field(const PointSet& points, const FieldParams& params, FieldBuildStats* stats,
                                  const FieldProgress& progress, const FitShare* share) {
    const std::string who(field_kind_name(params.kind));
    if (points.pos.size() < 4)
        throw InvalidArgument(who + ": " + std::to_string(points.pos.size()) + " points, at least 4 are needed");
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
