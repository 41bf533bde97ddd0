// meshless demo: the main job on an embedded default, no input file needed. Builds an analytic
// volume, extracts its isosurface by iso-splatting (paradigm C, approximate projection) and writes
// DIR/demo.ply and DIR/demo.png (EWA splats, Phong shading): options parsed here, the run by
// stream/analytic_demo.hpp (the graph and outputs of `meshless isosurface`).
#include <cstdio>
#include <filesystem>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "formats/output_folder.hpp"
#include "kernels/analytic_volumes.hpp"
#include "stream/analytic_demo.hpp"
#include "kernels/errors.hpp"

namespace meshless::cli {

int cmd_demo(int argc, char** argv) {
    Args a("demo", "[-o DIR] [--field torus|sphere|gyroid|ml] [--n N]",
           "Builds an embedded analytic volume, extracts an isosurface by iso-splatting and writes\n"
           "DIR/demo.ply (oriented points) and DIR/demo.png (surface-splatted picture).");
    a.option("output", "o", "DIR", "output directory (created if missing)", ".")
        .option("field", "", "NAME", "analytic field: torus | sphere | gyroid | ml (Marschner-Lobb)", "torus")
        .option("n", "", "N", "grid resolution N^3, 8..1024", "128");
    a.positionals(0, 0);
    add_thread_option(a);
    add_camera_options(a);
    if (!a.parse(argc, argv, 2)) return 0;
    const auto parsed = parse_analytic_field(a.get_or("field", "torus"));
    if (!parsed) throw UsageError("--field: expected torus, sphere, gyroid or ml, got '" + a.get_or("field", "torus") + "'");
    const AnalyticField field = *parsed;
    const long long n = a.get_int_or("n", 128);
    if (n < 8 || n > 1024) throw UsageError("--n: expected 8..1024");
    const std::filesystem::path dir = a.get_or("output", ".");
    if (dir == "-") throw UsageError("-o -: the demo writes a folder of files (a PLY and a PNG), not one stream to standard output");
    // "-o pic.png" means a file to whoever types it: a folder of that name would surprise them
    std::error_code ec;
    const std::string ext = dir.extension().string();
    if (!std::filesystem::is_directory(dir, ec) && (ext == ".png" || ext == ".ply" || ext == ".vtp" || ext == ".csv" || ext == ".nrrd"))
        throw UsageError("-o " + dir.string() + ": the demo writes a folder (DIR/demo.ply and DIR/demo.png); give a folder name");
    RenderSettings rs = render_settings(a);  // option errors (--size over the memory) before the folder is made
    make_output_folder(dir.string());

    AnalyticDemo d;
    d.field = field;
    d.n = n;
    d.rs = rs;
    d.zoom_given = a.has("zoom");
    d.threads = threads(a);
    d.producer = a.command_line();
    run_analytic_demo(d, dir.string());
    return 0;
}

}  // namespace meshless::cli
