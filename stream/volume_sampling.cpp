#include "stream/volume_sampling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "kernels/errors.hpp"
#include "kernels/splitmix.hpp"
#include "kernels/trilinear_field.hpp"

namespace meshless {

VolumeSample sample_volume(const Volume& v, std::uint64_t count, std::uint64_t seed, const std::string& name) {
    const GridSpec& g = v.grid;
    const TrilinearField field(v.view());
    std::array<double, 3> lo{}, ext{};
    for (int k = 0; k < 3; ++k) {
        lo[k] = g.origin[k];
        ext[k] = static_cast<double>(g.dims[k] - 1) * g.spacing[k];
    }
    SplitMix rng{seed};
    VolumeSample out;
    PointSet& ps = out.points;
    ps.value_name = "value";
    ps.pos.reserve(static_cast<std::size_t>(count));
    ps.value.reserve(static_cast<std::size_t>(count));
    const std::size_t batch = 4096;
    std::vector<Vec3> p;
    std::vector<double> val;
    const std::uint64_t max_draws = count * 20 + 1000;
    std::uint64_t draws = 0;
    while (ps.pos.size() < static_cast<std::size_t>(count)) {
        const std::size_t want = std::min<std::size_t>(batch, static_cast<std::size_t>(count) - ps.pos.size());
        p.resize(want);
        val.resize(want);
        for (auto& q : p) q = Vec3{lo[0] + rng.unit() * ext[0], lo[1] + rng.unit() * ext[1], lo[2] + rng.unit() * ext[2]};
        draws += want;
        field.evaluate(p, val, {});
        for (std::size_t i = 0; i < want; ++i) {
            if (!std::isfinite(val[i])) {
                ++out.redrawn;
                continue;
            }
            ps.pos.push_back(p[i]);
            ps.value.push_back(val[i]);
        }
        if (draws > max_draws)
            throw FormatError(name + ": too many NaN/Inf cells: " + std::to_string(out.redrawn) + " of " + std::to_string(draws) +
                              " random positions had no finite value");
    }
    ps.blocks = {PointSetBlock{"sample", {static_cast<std::int64_t>(count), 1, 1}, 0, count}};
    return out;
}

}  // namespace meshless
