// meshless sample: scattered points from a volume (uniform random positions in the volume's
// bounds, values by trilinear interpolation, dissertation Eq. 3.1), as the paper made its
// scattered buckyball set (chapter 4). Deterministic for a seed (own generator and conversion,
// no std distributions). Points falling in cells with a NaN corner are redrawn (counted).
#include <cmath>
#include <cstdio>
#include <vector>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "formats/point_set_writer.hpp"
#include "kernels/errors.hpp"
#include "kernels/point_set.hpp"
#include "kernels/splitmix.hpp"
#include "kernels/trilinear_field.hpp"

namespace meshless::cli {

int cmd_sample(int argc, char** argv) {
    Args a("sample", "VOLUME --count N -o points.ply|points.csv|points.vtp",
           "Scattered samples of a volume: N uniform random positions in the volume's bounds, values by\n"
           "trilinear interpolation. PLY (binary, double x y z value), CSV (header x,y,z,value) or VTP (float32\n"
           "points with a value array, for ParaView).\n"
           "The same seed gives the same points.");
    a.option("count", "n", "N", "number of points (required, >= 1)")
        .option("seed", "", "S", "random seed", "1")
        .option("output", "o", "FILE", "output .ply, .csv or .vtp ('-' = CSV on stdout; required)");
    add_volume_options(a);
    if (!a.parse(argc, argv, 2)) return 0;
    const long long count = a.get_int_or("count", -1);
    if (!a.has("count")) throw UsageError("missing --count N");
    if (count < 1) throw UsageError("--count: expected a positive number, got " + std::to_string(count));
    const std::string out = a.require("output");
    require_point_set_output(out, "a point set with values");
    const long long seed = a.get_int_or("seed", 1);
    const Volume v = load_volume(a);
    const GridSpec& g = v.grid;
    const TrilinearField field(v.view());
    std::array<double, 3> lo{}, ext{};
    for (int k = 0; k < 3; ++k) {
        lo[k] = g.origin[k];
        ext[k] = static_cast<double>(g.dims[k] - 1) * g.spacing[k];
    }
    SplitMix rng{static_cast<std::uint64_t>(seed)};
    PointSet ps;
    ps.value_name = "value";
    ps.pos.reserve(static_cast<std::size_t>(count));
    ps.value.reserve(static_cast<std::size_t>(count));
    const std::size_t batch = 4096;
    std::vector<Vec3> p;
    std::vector<double> val;
    std::uint64_t redrawn = 0;
    const std::uint64_t max_draws = static_cast<std::uint64_t>(count) * 20 + 1000;
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
                ++redrawn;
                continue;
            }
            ps.pos.push_back(p[i]);
            ps.value.push_back(val[i]);
        }
        if (draws > max_draws)
            throw FormatError(a.positional()[0] + ": too many NaN/Inf cells: " + std::to_string(redrawn) + " of " +
                              std::to_string(draws) + " random positions had no finite value");
    }
    ps.blocks = {PointSetBlock{"sample", {count, 1, 1}, 0, static_cast<std::uint64_t>(count)}};
    write_point_set(out, ps, {"source " + a.positional()[0], "producer meshless sample", "seed " + std::to_string(seed)});
    if (redrawn) std::fprintf(stderr, "meshless sample: %llu positions in cells with NaN/Inf corners were redrawn\n",
                              static_cast<unsigned long long>(redrawn));
    return 0;
}

}  // namespace meshless::cli
