// The pipeline stages as their own processes, joined by Unix pipes (docs/architecture.md):
//   meshless generate VOLUME --iso V | meshless project | meshless write -o out.ply
// Each reads/writes the versioned binary stream of formats/point_stream.hpp; one DATA frame per
// batch, so the bytes that reach the last stage equal the in-process `meshless isosurface` run.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/progress_meter.hpp"
#include "cli/errors.hpp"
#include "formats/binary_stream_output.hpp"
#include "cli/field_cli.hpp"
#include "cli/multiblock_isosurface.hpp"
#include "cli/scattered_isosurface.hpp"
#include "cli/point_set_cli.hpp"
#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"
#include "ooc/sample_store_writer.hpp"
#include "stream/cell_row_source.hpp"
#include "stream/generate_stage.hpp"
#include "stream/sample_stream_generation.hpp"
#include "stream/point_file_sink.hpp"
#include "stream/sample_stream_projection.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless::cli {

namespace {

void add_compress_option(Args& a) { a.flag("compress", "zstd-compress the stream's DATA frames"); }

}  // namespace

namespace {

/// generate --all: paradigm (A) sample store (ooc/sample_store_writer.hpp) of a brick store.
int generate_all(const Args& a) {
    if (a.has("iso")) throw UsageError("--all precomputes the index for every isovalue: drop --iso");
    const std::string out = a.get_or("output", "-");
    if (out == "-") throw UsageError("--all writes a sample store: give -o FILE.mls");
    require_output_extension(out, ".mls", "-o", "a sample store", /*to_stdout=*/false);
    VolumeInput in = open_volume_input(a);
    if (!in.store)
        throw UsageError("--all needs a brick store (.mlb), which the sample store recomputes samples from: "
                         "meshless convert " + in.path + " -o vol.mlb");
    ProgressMeter meter("meshless generate --all", "bricks", static_cast<double>(in.store->bricks().size()) * 2,
                        progress_wanted(a), progress_delay());
    SampleStoreParams params;
    params.progress = [&](double f) { meter.set_fraction(f); };
    const SampleStoreBuildStats st = write_sample_store(*in.store, out, params);
    meter.done();
    if (a.has("stats"))
        std::fprintf(stderr, "%s\n", sample_store_stats_line(st, in.path).c_str());
    return 0;
}

}  // namespace

int cmd_generate(int argc, char** argv) {
    Args a("generate", "VOLUME --iso V [-o FILE|-]   |   VOLUME --all -o vol.mls",
           "Point generation of paradigm (C) (section 3.4): one sample per active cell, at the cell centre,\n"
           "with trilinear value and gradient and the cell's corner values, written as a binary sample\n"
           "stream (stdout by default) for `meshless project`. Several isovalues (--iso V1,V2,...) give one\n"
           "segment of samples each, in order: project | write then gives isosurface --iso V1,V2,...'s points.\n"
           "With --all (VOLUME a brick store .mlb): paradigm (A) preprocessing (Table 3.1): the cell rows of\n"
           "the non-constant cells filed by value interval into a sample store (span-space index) that refers to\n"
           "the .mlb; `meshless extract vol.mls --iso V` then recomputes only the rows that can be active for V.");
    a.option("iso", "", "V", "isovalue (required unless --all), or several: V1,V2,... (at most 256; one segment of the stream "
                             "each, projected onto its own by project)")
        .flag("all", "paradigm (A): index the cells of a brick store for every isovalue into a sample store (-o FILE.mls)")
        .option("output", "o", "FILE", "stream output, '-' = stdout", "-")
        .flag("stats", "print sample counts and timing to stderr");
    add_fail_empty_option(a);
    add_compress_option(a);
    add_sampling_options(a);
    add_volume_options(a);
    add_crop_option(a);
    add_memory_option(a);
    add_thread_option(a);
    add_quiet_option(a);
    a.epilog("example: meshless generate vol.raw --iso 100.5 | meshless project | meshless splat -o img.png\n"
             "BLOCKS (PLOT3D, .vts pieces, .vtm/.vthb, or several files): multiblock seeds (meshless generate BLOCKS... --help)\n");
    {
        Args blocks("generate", "", "");
        add_point_set_options(blocks, /*with_endian=*/false);
        blocks.option("samples", "", "", "");
        Args scattered("generate", "", "");
        add_field_options(scattered, /*with_coverage=*/false);
        scattered.option("max-cells", "", "", "").option("max-level", "", "", "").option("reg-gap", "", "", "");
        const auto positionals = scan_positionals(argc, argv, 2, {&a, &blocks, &scattered});
        if (names_blocks(positionals)) return generate_blocks(argc, argv);
        if (scattered_invocation(positionals, argc, argv)) return generate_scattered(argc, argv);
    }
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.has("all")) return generate_all(a);
    const std::vector<double> isos = isovalue_list(a);
    const SamplingParams sp = sampling_params(a);
    const int nthreads = threads(a);
    BinaryStreamOutput out(a.get_or("output", "-"), "a sample stream");
    VolumeInput in = open_volume_input(a, /*stream=*/true);
    bool warned = false;
    const std::vector<IsoSplatResult> r =
        generate_sample_stream(in, isos, sp, out.f, out.name, a.command_line(), a.has("compress"), nthreads, stderr, &warned);
    if (a.has("stats")) print_generate_stats(stderr, in.path, isos, r);
    out.commit();
    std::uint64_t samples = 0;
    for (const IsoSplatResult& one : r) samples += static_cast<std::uint64_t>(one.sampling.active_cells);
    return empty_result_exit(a, samples, "samples", isos[0], in.path, warned);
}

int cmd_project(int argc, char** argv) {
    Args a("project", "[INPUT|-] [--projection approx|exact|none] [-o FILE|-]",
           "Projects a sample stream onto the isosurface (section 3.3): one Newton step with the\n"
           "displacement criterion (approx, Eq. 3.5), the ray-trilinear cubic (exact, Eq. 3.3), or none.\n"
           "Reads stdin by default; the isovalue comes from the stream unless --iso overrides it. A stream of\n"
           "several isovalues (generate --iso V1,V2,...) is projected segment by segment, each onto its own\n"
           "isovalue (--iso is refused then), into a point stream of the same segments.");
    a.option("iso", "", "V", "isovalue (default: the one recorded by generate)")
        .option("projection", "", "MODE", "approx | exact | none", "approx")
        .option("output", "o", "FILE", "point stream output, '-' = stdout", "-")
        .flag("stats", "print projection counts to stderr");
    add_compress_option(a);
    add_thread_option(a);
    a.epilog("With --field KIND DATA...: projects a multiblock seed stream onto a meshless field (meshless project --field mpu --help).\n");
    if (project_seeds_invocation(argc, argv)) return project_seeds(argc, argv);
    if (!a.parse(argc, argv, 2)) return 0;
    const Projection mode = parse_projection(a.get_or("projection", "approx"));
    const int nthreads = threads(a);
    BinaryStreamOutput out(a.get_or("output", "-"), "a point stream");
    InputFile in(a.positional().empty() ? "-" : a.positional()[0]);
    StreamReader reader(in.f, in.name);
    require_sample_stream(reader, in.name);
    reader.stop_at_segments();
    reader.read_meta();
    if (const auto isos = meta_isovalues(reader.meta())) {  // one segment per isovalue, each projected onto its own
        if (a.has("iso"))
            throw UsageError("--iso: " + in.name + " holds the samples of " + std::to_string(isos->size()) + " isovalues (" +
                             *reader.meta().get("isovalues") + "), each projected onto its own; drop --iso");
        const std::vector<ProjectionStats> s = project_sample_segments(reader, in.name, mode, out.f, out.name, a.has("compress"), nthreads);
        out.commit();
        if (a.has("stats"))
            for (const ProjectionStats& one : s) print_projection_stats(stderr, mode, one);
        return 0;
    }
    const double iso = stream_iso(a, reader.meta());
    const ProjectionStats s = project_sample_stream(reader, in.name, iso, mode, out.f, out.name, a.has("compress"), nthreads);
    out.commit();
    if (a.has("stats")) print_projection_stats(stderr, mode, s);
    return 0;
}

int cmd_write(int argc, char** argv) {
    Args a("write", "[INPUT|-] -o out.ply|out.vtp",
           "Writes a point stream (from `meshless project`) as a binary little-endian PLY with\n"
           "x y z nx ny nz radius value (and block, for multiblock points: the id of the block each point was\n"
           "seeded in; MeshLab, ParaView, VTK), or as VTK XML PolyData (.vtp: vertex cells, Normals, radius,\n"
           "value, block, zlib-compressed; ParaView and VTK open it as it is).");
    a.option("output", "o", "FILE", "output (required): .ply or .vtp ('-' = stdout, PLY unless --format vtp)")
        .option("colormap", "", "NAME", "--ply-color value: viridis | coolwarm | gray", "viridis")
        .option("range", "", "LO,HI", "--ply-color value: the colour map's value range (default: the volume's, as the stream records it)");
    add_geometry_format_option(a);
    add_ply_color_option(a);
    if (!a.parse(argc, argv, 2)) return 0;
    a.require("output");
    const GeometryOutput out = *geometry_output(a, "an oriented point set");
    InputFile in(a.positional().empty() ? "-" : a.positional()[0]);
    StreamReader reader(in.f, in.name);
    require_point_stream(reader, in.name);
    reader.read_meta();
    std::optional<ShadingParams> colors;
    if (out.ply_color)
        colors = point_file_colors(*out.ply_color, color_choice(a), reader.meta().get_double("value_min"),
                                   reader.meta().get_double("value_max"), in.name);
    PointFileSink sink(out.path, out.format, ply_comments(reader.meta()), vtp_options(a, 0), reader.has_blocks(), colors);
    write_point_stream(reader, sink);
    return 0;
}

}  // namespace meshless::cli
