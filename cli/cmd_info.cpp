// meshless info: describes any file meshless reads or writes (stream/file_info.hpp), one FILE after
// another; a file that cannot be described is reported on stderr and the others are still described.
#include <cstdio>
#include <string>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/point_set_cli.hpp"
#include "stream/file_info.hpp"

namespace meshless::cli {

int cmd_info(int argc, char** argv) {
    Args a("info", "FILE...",
           "Describes files meshless reads or writes: volumes (format, dims, type, spacing, value range; the payload\n"
           "is checked and decoded through a small buffer, so bombs, truncated or corrupt data are reported),\n"
           "point/sample streams (records, frames, metadata; checks the END frame), brick stores (.mlb),\n"
           "sample stores (.mls), fitted fields (.mlf: kind, parameters, the data it was fitted to), PLY (point sets are read through, so truncation is reported), PNG, and\n"
           "scattered/multiblock point sets (CSV/TSV/text, .vtp, .vts, .vtu nodes, PLOT3D .bin/.xyz/.p3d, raw\n"
           "float32 records, 2-D .npy; a 3-D .npy is a volume): points, blocks and dims, value name and range, bounds, dropped samples;\n"
           "VTK multiblock .vtm and AMR .vthb/.vtm hierarchies: levels, boxes per level, refinement,\n"
           "spacing, arrays with their centring, the chosen array's range (--value), blocks and dims.\n"
           "Volumes of several point arrays (.vti, legacy .vtk, vtk.js) list them (name, type, components) and\n"
           "say which one is read by default; --array NAME describes that one.\n"
           "Files that cannot be described are reported on stderr; the others are still described.");
    a.flag("value-range", "volumes: also read the samples and print the value range").deprecated_alias("range");
    a.positionals(1, 100000);
    add_volume_options(a);
    add_point_set_options(a, false);
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().empty()) throw UsageError("missing FILE argument");
    int status = 0;
    for (const std::string& path : a.positional()) {
        try {
            // a kind's options are parsed when a file of that kind comes: a malformed one stops the
            // run there (exit 1), after the files before it, and is never looked at if no file reads it
            const FileKind kind = file_kind(path, a.has("dims"));
            if (a.has("array") && (kind == FileKind::brick_store || kind == FileKind::sample_store))
                throw UsageError("--array: " + path + " is a " + (kind == FileKind::brick_store ? "brick store (.mlb)" : "sample store (.mls)") +
                                 ", which holds one unnamed array");
            FileInfoOptions o;
            if (kind == FileKind::volume) o.raw = raw_options(a), o.value_range = a.has("value-range");
            if (kind == FileKind::point_set || kind == FileKind::multiblock) o.point_set = point_set_options(a);
            describe_file(path, kind, o, stdout);
        } catch (const std::exception& e) {  // report, go on with the other files, exit 2 at the end
            if (exit_code(e) == kExitUsage) throw;  // a bad option (UsageError, InvalidArgument) fails them all
            std::fflush(stdout);
            std::fprintf(stderr, "meshless info: %s\n", error_message(e).c_str());
            status = 2;
        }
    }
    return status;
}

}  // namespace meshless::cli
