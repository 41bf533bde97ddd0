// meshless fit DATA... --field rbf-grid|mpu|global-rbf -o field.mlf: the costly construction of a
// meshless field (dissertation sections 2.1.1, 4.3, 5.5) done once and saved as a fitted-field file
// (formats/field_file.hpp), which every command taking --field then loads instead of refitting.
// DATA are scattered point sets or multiblock/AMR inputs (every valid node, as the block commands
// see them). The file records the identity of the data, so commands given other data refuse it.
#include <chrono>
#include <cinttypes>
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/field_cli.hpp"
#include "cli/progress_meter.hpp"
#include "formats/atomic_file.hpp"
#include "formats/binary_file.hpp"
#include "kernels/point_set_identity.hpp"

namespace meshless::cli {

int cmd_fit(int argc, char** argv) {
    Args a("fit", "DATA... --field rbf-grid|mpu|global-rbf -o field.mlf",
           "Fits a meshless field to scattered points or to the nodes of multiblock/AMR grids once and saves\n"
           "it (versioned, checksummed, written atomically), so that probe, slice, resample, isosurface and\n"
           "project load it with --field field.mlf instead of refitting. A loaded field evaluates exactly as\n"
           "the freshly fitted one; the file records which data it was fitted to, and commands given other\n"
           "data refuse it. DATA: point sets (CSV/text, .ply, .vtp, .npy, raw records) or, when every file\n"
           "is one, multiblock inputs (PLOT3D, .vts, .vtm, .vthb).");
    a.option("output", "o", "FILE", "the fitted field (.mlf, required)")
        .option("zstd-level", "", "L", "zstd level of the arrays, 0..19, 0 = stored raw", "1")
        .deprecated_alias("level");
    add_field_options(a, /*with_coverage=*/false, kDataFieldDefaultHelp);
    add_quiet_option(a);
    a.positionals(1, 1000);
    a.epilog("example:\n  meshless fit combxyz.bin --q combq.bin --field mpu -o comb.mlf\n"
             "  meshless probe combxyz.bin --q combq.bin --field comb.mlf --at 8,0,30   (a point inside the combustor)");
    if (!a.parse(argc, argv, 2)) return 0;
    // the default field is the one `isosurface DATA` builds (stream/field_data.hpp)
    const FieldParams params = field_params(a, data_field_default(a.positional()));
    const std::string out = require_output_extension(a.require("output"), ".mlf", "-o", "a fitted field", /*to_stdout=*/false);
    if (is_streaming_output(out)) throw UsageError("-o " + out + ": a fitted field is written to a regular file (.mlf), not a stream");
    const long long level = a.get_int_or("zstd-level", 1);
    if (level < 0 || level > 19) throw UsageError("--zstd-level: expected 0..19");

    auto now = [] { return std::chrono::steady_clock::now(); };
    auto since = [&](auto t) { return std::chrono::duration<double>(now() - t).count(); };
    const auto t_read = now();
    const PointSet points = read_points_arg(a);
    const double read_s = since(t_read);
    FieldBuildStats st;
    const std::unique_ptr<Field> field = fit_input_field(a, points, params, st);
    const auto t_write = now();
    const FittedData data = write_fitted_field(out, *field, params, points, st, static_cast<int>(level));
    const double write_s = since(t_write);
    if (a.has("stats")) {
        print_field_build_report(stderr, a.command(), params, points, st);
        print_fit_report(stderr, out, data, st, read_s, write_s);
    }
    return 0;
}

}  // namespace meshless::cli
