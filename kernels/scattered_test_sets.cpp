#include "kernels/scattered_test_sets.hpp"

#include <algorithm>
#include <cmath>

#include "kernels/errors.hpp"
#include "kernels/splitmix.hpp"

namespace meshless {

int layered_layer_count(std::size_t n) {
    const double l = std::round(std::cbrt(static_cast<double>(n)) / 4.0);
    return std::max(4, static_cast<int>(l));
}

namespace {

std::array<Vec3, kClusterCount> draw_centres(SplitMix& rng) {
    std::array<Vec3, kClusterCount> c{};
    for (auto& p : c) {
        const double x = -0.7 + 1.4 * rng.unit();
        const double y = -0.7 + 1.4 * rng.unit();
        const double z = -0.7 + 1.4 * rng.unit();
        p = {x, y, z};
    }
    return c;
}

Vec3 uniform_in_cube(SplitMix& rng) {
    const double x = -1 + 2 * rng.unit();
    const double y = -1 + 2 * rng.unit();
    const double z = -1 + 2 * rng.unit();
    return {x, y, z};
}

}  // namespace

std::array<Vec3, kClusterCount> cluster_centres(std::uint64_t seed) {
    SplitMix rng{seed};
    return draw_centres(rng);
}

double clustered_density(const std::array<Vec3, kClusterCount>& centres, const Vec3& x) {
    double g = 0;
    for (const Vec3& c : centres) {
        const Vec3 d = x - c;
        g = std::max(g, std::exp(-dot(d, d) / (2 * kClusterSigma * kClusterSigma)));
    }
    return 1.0 + (kClusterContrast - 1.0) * g;
}

PointSet make_scattered_set(const ScatteredSetSpec& spec) {
    if (spec.count == 0) throw InvalidArgument("scattered test set: the point count must be >= 1");
    if (spec.count > kMaxScatteredCount) throw InvalidArgument("scattered test set: more than 2^28 points");
    PointSet ps;
    ps.value_name = "value";
    ps.pos.reserve(spec.count);
    ps.value.reserve(spec.count);
    SplitMix rng{spec.seed};
    switch (spec.distribution) {
        case ScatterDistribution::uniform:
            while (ps.pos.size() < spec.count) ps.pos.push_back(uniform_in_cube(rng));
            break;
        case ScatterDistribution::clustered: {
            const auto centres = draw_centres(rng);
            while (ps.pos.size() < spec.count) {
                const Vec3 x = uniform_in_cube(rng);
                if (rng.unit() * kClusterContrast < clustered_density(centres, x)) ps.pos.push_back(x);
            }
            break;
        }
        case ScatterDistribution::layered: {
            const int layers = layered_layer_count(spec.count);
            const double dz = 2.0 / (layers - 1);
            while (ps.pos.size() < spec.count) {
                const int l = std::min(layers - 1, static_cast<int>(rng.unit() * layers));
                const double x = -1 + 2 * rng.unit();
                const double y = -1 + 2 * rng.unit();
                const double j = (2 * rng.unit() - 1) * kLayerJitter * dz;
                const double z = std::clamp(-1 + dz * l + j, -1.0, 1.0);
                ps.pos.push_back({x, y, z});
            }
            break;
        }
    }
    for (const Vec3& p : ps.pos) ps.value.push_back(analytic_value(spec.field, p));
    ps.blocks.push_back({scattered_set_name(spec), {static_cast<std::int64_t>(spec.count), 1, 1}, 0, spec.count});
    return ps;
}

const char* to_string(ScatterDistribution d) {
    switch (d) {
        case ScatterDistribution::uniform: return "uniform";
        case ScatterDistribution::clustered: return "clustered";
        case ScatterDistribution::layered: return "layered";
    }
    return "?";
}

std::optional<ScatterDistribution> parse_scatter_distribution(std::string_view name) {
    if (name == "uniform") return ScatterDistribution::uniform;
    if (name == "clustered") return ScatterDistribution::clustered;
    if (name == "layered") return ScatterDistribution::layered;
    return std::nullopt;
}

std::string scattered_set_name(const ScatteredSetSpec& spec) {
    return std::string(to_string(spec.field)) + "-" + to_string(spec.distribution) + "-" + std::to_string(spec.count);
}

}  // namespace meshless
