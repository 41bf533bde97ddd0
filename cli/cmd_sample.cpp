// meshless sample: scattered points from a volume (uniform random positions in the volume's
// bounds, values by trilinear interpolation, dissertation Eq. 3.1): options parsed here, the points
// drawn by stream/volume_sampling.hpp.
#include <cstdint>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "formats/point_set_writer.hpp"
#include "stream/volume_sampling.hpp"

namespace meshless::cli {

int cmd_sample(int argc, char** argv) {
    Args a("sample", "VOLUME --count N -o points.ply|points.csv|points.vtp",
           "Scattered samples of a volume: N uniform random positions in the volume's bounds, values by\n"
           "trilinear interpolation. PLY (binary, double x y z value), CSV (header x,y,z,value) or VTP (float32\n"
           "points with a value array, for ParaView).\n"
           "The same seed gives the same points.");
    a.option("count", "n", "N", "number of points (required, >= 1; held in memory, 32 bytes each)")
        .option("seed", "", "S", "random seed, any integer of at most 18 digits", "1")
        .option("output", "o", "FILE", "output .ply, .csv or .vtp ('-' = CSV on stdout; required)");
    add_volume_options(a);
    add_crop_option(a);
    if (!a.parse(argc, argv, 2)) return 0;
    const long long count = a.get_int_or("count", -1);
    if (!a.has("count")) throw UsageError("missing --count N");
    if (count < 1) throw UsageError("--count: expected a positive number, got " + std::to_string(count));
    const std::string out = a.require("output");
    require_point_set_output(out, "a point set with values");
    const long long seed = a.get_int_or("seed", 1);
    // the points are held whole before they are written: position and value, 32 bytes a point
    const std::uint64_t n = static_cast<std::uint64_t>(count);
    check_option_fits(a, "--count " + std::to_string(count), "the points (32 bytes each)",
                      n > UINT64_MAX / 32 ? UINT64_MAX : n * 32, "");
    const Volume v = load_volume(a);
    const VolumeSample sample = sample_volume(v, static_cast<std::uint64_t>(count), static_cast<std::uint64_t>(seed), a.positional()[0]);
    write_point_set(out, sample.points, {"source " + a.positional()[0], "producer meshless sample", "seed " + std::to_string(seed)});
    const std::uint64_t redrawn = sample.redrawn;
    if (redrawn) std::fprintf(stderr, "meshless sample: %llu positions in cells with NaN/Inf corners were redrawn\n",
                              static_cast<unsigned long long>(redrawn));
    return 0;
}

}  // namespace meshless::cli
