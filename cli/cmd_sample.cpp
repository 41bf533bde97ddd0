// meshless sample: scattered points from a volume (uniform random positions in the volume's
// bounds, values by trilinear interpolation, dissertation Eq. 3.1): options parsed here, the points
// drawn by stream/volume_sampling.hpp.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/progress_meter.hpp"
#include "formats/atomic_file.hpp"
#include "formats/point_set_writer.hpp"
#include "formats/terminal_safe.hpp"
#include "ooc/brick_store.hpp"
#include "stream/volume_input.hpp"
#include "stream/volume_sampling.hpp"

namespace meshless::cli {

int cmd_sample(int argc, char** argv) {
    Args a("sample", "VOLUME --count N -o points.ply|points.csv|points.vtp",
           "Scattered samples of a volume: N uniform random positions in the volume's bounds, values by\n"
           "trilinear interpolation. PLY (binary, double x y z value), CSV (header x,y,z,value) or VTP (float32\n"
           "points with a value array, for ParaView).\n"
           "The same seed gives the same points.");
    a.option("count", "n", "N", "number of points (required, >= 1; written chunk by chunk: memory does not grow with N)")
        .option("seed", "", "S", "random seed, any integer of at most 18 digits", "1")
        .option("output", "o", "FILE", "output .ply, .csv or .vtp ('-' = CSV on stdout, written as drawn: a volume found to "
                                       "have too few finite cells fails after part of it; required)");
    add_volume_options(a);
    add_crop_option(a);
    a.option("memory", "", "BYTES", "brick stores (.mlb): the budget of the brick cache (half) and of the points drawn at once "
                                     "(half, 112 bytes a point, 65,536 to 4 Mi of them), e.g. 256M, 2G; other volumes: the most "
                                     "one read whole may take (raw samples are mapped)", "256M")
        .validate([](const std::string& v) { (void)parse_memory_size(v); });
    add_quiet_option(a);
    a.epilog("examples: meshless sample ../shared/data/tooth/tooth_103x94x161_uint8.raw --count 100000 -o tooth_pts.ply\n"
             "          meshless convert VOLUME -o vol.mlb && meshless sample vol.mlb --count 100000000 -o pts.ply --memory 512M\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const long long count = a.get_int_or("count", -1);
    if (!a.has("count")) throw UsageError("missing --count N");
    if (count < 1) throw UsageError("--count: expected a positive number, got " + std::to_string(count));
    const std::string out = a.require("output");
    require_point_set_output(out, "a point set with values");
    const long long seed = a.get_int_or("seed", 1);
    const std::string& path = a.positional()[0];
    const std::vector<std::string> comments{"source " + path, "producer meshless sample", "seed " + std::to_string(seed)};
    const auto n = static_cast<std::uint64_t>(count);
    // the points are streamed to the output: refuse at once a count whose file cannot fit (the least a
    // point takes: 32 bytes of PLY, 24 of VTP, 8 of CSV)
    const PointSetFormat format = point_set_output_format(out);
    const std::uint64_t per = format == PointSetFormat::ply ? 32 : format == PointSetFormat::vtp ? 24 : 8;
    if (const auto room = free_space_for_output(out); room && (n > *room / per))
        throw UsageError("--count " + std::to_string(count) + ": the points would take at least " +
                         byte_size_text(n > UINT64_MAX / per ? UINT64_MAX : n * per) + " in " + terminal_safe(out) + ", more than the " +
                         byte_size_text(*room) + " free there");
    const ProgressCounter progress = progress_counter(a);
    auto meter = progress ? progress("points", static_cast<double>(n)) : std::function<void(double)>();
    // a brick store is read brick by brick through its cache (--memory), the points of a chunk grouped
    // by brick; any other volume is read (raw samples: mapped) whole
    std::uint64_t redrawn = 0;
    SampleInput in;
    std::unique_ptr<BrickStore> store;
    std::optional<Volume> v;
    if (!a.has("crop") && is_brick_store(path)) {
        store = BrickStore::open(path);
        in.store = store.get();
        in.memory_bytes = parse_memory_size(a.get_or("memory", "256M"));
    } else {
        v = load_volume(path, volume_open_options(a, false), /*map=*/true);
        in.volume = &*v;
    }
    redrawn = sample_volume_to_file(in, n, static_cast<std::uint64_t>(seed), path, out, comments, meter);
    meter = {};  // (the progress line cleared before the message below)
    if (redrawn) std::fprintf(stderr, "meshless sample: %llu positions in cells with NaN/Inf corners were redrawn\n",
                              static_cast<unsigned long long>(redrawn));
    return 0;
}

}  // namespace meshless::cli
