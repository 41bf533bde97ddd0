// meshless isosurface: paradigm (C) iso-splatting in one process (dissertation chapter 3).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <optional>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/field_cli.hpp"
#include "cli/multiblock_isosurface.hpp"
#include "cli/progress_meter.hpp"
#include "cli/scattered_isosurface.hpp"
#include "formats/atomic_file.hpp"
#include "formats/multiblock_reader.hpp"
#include "kernels/errors.hpp"
#include "stream/isosplat_mpi.hpp"
#include "stream/mpi_session.hpp"
#include "stream/progress_stage.hpp"
#include "stream/sample_store_source.hpp"

namespace meshless::cli {

namespace {

/// The picture of points whose metadata records their volume: its patient axes for the default
/// camera (unless --up) and, without --range, its value range for --color value — what splat of
/// the same points' PLY or stream draws.
void picture_from_meta(const Args& a, const StreamMeta& meta, bool range_given, double iso, RenderSettings& rs) {
    if (const auto f = meta_patient_axes(meta)) apply_anatomical_frame(a, *f, rs.camera);
    if (!range_given) {
        rs.shading.value_lo = meta.get_double("value_min").value_or(iso);
        rs.shading.value_hi = meta.get_double("value_max").value_or(iso);
    }
}

/// A sample store (.mls) input: paradigm (A) in one process (section 3.5, Table 3.1): the store's
/// candidate rows, recomputed from its .mlb, projected; the same points as from the .mlb.
int isosurface_sample_store(const Args& a, double iso, Projection mode, const SamplingParams& sp,
                            RenderSettings rs, bool range_given, int nthreads) {
    const std::string path = a.positional()[0];
    const auto store = SampleStore::open(path);
    warn_if_iso_outside(iso, {store->info().value_lo, store->info().value_hi}, path);
    StreamMeta meta = sample_store_meta(*store, iso, a.command_line());
    meta.set("projection", to_string(mode));
    picture_from_meta(a, meta, range_given, iso, rs);
    SampleStoreSource source(*store, iso, sp);
    IsoSplatResult r;
    const std::size_t points = run_to_outputs(geometry_output(a, kPointsWhat), a.get("png"), meta, rs, nthreads, [&](const Stage* draw, Sink& sink) {
        return run_isosplat_sample_store(source, iso, mode, sink, {nthreads}, PipelineShape::two_stage, {nullptr, draw});
    }, r);
    if (a.has("stats")) print_isosplat_stats(stderr, path, iso, mode, r, points, nthreads, 1);
    return 0;
}

/// `mpirun -np N meshless isosurface vol.mlb ...` (stream/isosplat_mpi.hpp): rank 0 writes through the
/// outputs of one process, with the volume's camera and range; a failing rank ends the job.
MpiIsosurfaceResult isosurface_mpi(const Args& a, int argc, char** argv, double iso, Projection mode, const SamplingParams& sp,
                                   int nthreads, const RenderSettings& rs, bool range_given) {
    MpiSession mpi(&argc, &argv);
    try {
        VolumeInput in = open_volume_input(a);
        return run_isosplat_mpi(mpi, in, iso, mode, sp, nthreads, a.command_line(),
                                [&](const StreamMeta& meta, const std::function<void(Sink&)>& produce) {
                                    warn_if_iso_outside(iso, in.value_range(), in.path);
                                    RenderSettings root_rs = rs;
                                    picture_from_meta(a, meta, range_given, iso, root_rs);
                                    IsoSplatResult unused;
                                    return run_to_outputs(geometry_output(a, kPointsWhat), a.get("png"), meta, root_rs, nthreads,
                                                          [&](const Stage*, Sink& sink) {
                                                              produce(sink);
                                                              return IsoSplatResult{};
                                                          }, unused, /*parallel_draw=*/false);
                                });
    } catch (const std::exception& e) {
        end_mpi_job(mpi, "isosurface", e);
    }
}

}  // namespace

namespace {

/// BLOCKS (chapter 4) and POINTS (chapter 5) have their own graphs and options: their command's exit
/// code when the positionals name such an input (`a`: the volume command's options, declared),
/// else nullopt (a volume).
std::optional<int> isosurface_of_blocks_or_points(const Args& a, int argc, char** argv) {
    // multiblock / AMR inputs (chapter 4) have their own graph and options
    Args blocks("isosurface", "", "");
    add_field_options(blocks);
    add_camera_options(blocks);
    add_color_options(blocks);
    add_geometry_format_option(blocks);
    add_ply_color_option(blocks);
    blocks.option("samples", "", "", "").option("tolerance", "", "", "").option("max-iterations", "", "", "")
        .option("max-travel", "", "", "");
    blocks.option("max-cells", "", "", "").option("max-level", "", "", "").option("dedup", "", "", "").option("reg-gap", "", "", "");
    const auto positionals = scan_positionals(argc, argv, 2, {&a, &blocks});
    // the placeholders of the help text itself ("meshless isosurface POINTS --help"), when no
    // such file exists, name the input kind
    std::error_code ec;
    if (positionals.size() == 1 && !std::filesystem::exists(positionals[0], ec)) {
        if (positionals[0] == "BLOCKS") return isosurface_blocks(argc, argv);
        if (positionals[0] == "POINTS") return isosurface_scattered(argc, argv);
    }
    if (blocks_invocation(positionals)) return isosurface_blocks(argc, argv);
    // scattered point sets (chapter 5)
    if (scattered_invocation(positionals, argc, argv)) return isosurface_scattered(argc, argv);
    return std::nullopt;
}

}  // namespace

int cmd_isosurface(int argc, char** argv) {
    Args a("isosurface", "VOLUME --iso V -o out.ply|out.vtp [--png out.png] [options]",
           "Paradigm (C) iso-splatting: one sample per active cell (cell centre), value and gradient by\n"
           "trilinear interpolation, projected onto the isosurface; writes an oriented point set\n"
           "(binary PLY: x y z nx ny nz radius value, or VTK XML PolyData .vtp with vertex cells, Normals,\n"
           "radius, value) and/or a surface-splatted picture.\n"
           "VOLUME: raw (name_XxYxZ_type.raw or --dims/--type), NRRD (.nrrd/.nhdr), MetaImage (.mhd/.mha),\n"
           "VTK legacy (.vtk), VTK XML image (.vti), vtk-js (index.json), SLC, NIfTI, or a brick store (.mlb,\n"
           "see meshless convert), read brick by brick: only bricks the isosurface crosses, within --memory,\n"
           "or a paradigm (A) sample store (.mls, see meshless generate --all): only its candidate cell rows.");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "point set output (.ply binary PLY, .vtp VTK XML PolyData; '-' for stdout)")
        .option("png", "", "FILE", "also render the points to this PNG")
        .option("projection", "", "MODE", "approx (one Newton step, Eq. 3.5) | exact (ray-trilinear cubic, Eq. 3.3) | none", "approx")
        .flag("stats", "print counts (active cells, discarded samples) and timing to stderr");
    add_geometry_format_option(a);
    add_ply_color_option(a);
    add_sampling_options(a);
    add_volume_options(a);
    add_memory_option(a);
    add_thread_option(a);
    add_quiet_option(a);
    add_camera_options(a);
    add_color_options(a);
    a.epilog("BLOCKS (PLOT3D, .vts pieces, .vtm/.vthb, or several files): the multiblock/AMR isosurface of chapter 4\n"
             "          (meshless isosurface BLOCKS... --help for its options).\n"
             "POINTS (scattered: CSV/TSV, PLY, VTP, raw records, .npy, point stores .mlc): the isosurface of chapter 5\n"
             "          (meshless isosurface POINTS --help for its options).\n"
             "examples: meshless isosurface ../shared/data/fuel/fuel_64x64x64_uint8.raw --iso 20.5 -o fuel.ply --png fuel.png\n"
             "          meshless isosurface vol.mlb --iso 100.5 --memory 256M -o out.ply\n"
             "          mpirun -np 4 meshless isosurface vol.mlb --iso 100.5 -o out.ply   (ranks split the active bricks)\n");
    if (const auto other = isosurface_of_blocks_or_points(a, argc, argv)) return *other;
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = parse_finite(a.require("iso"), "--iso");
    const auto png = point_outputs_png(a);
    const Projection mode = parse_projection(a.get_or("projection", "approx"));
    const SamplingParams sp = sampling_params(a);
    RenderSettings rs = render_settings(a);
    const ColorChoice cc = color_choice(a);
    const int nthreads = threads(a);
    // Colours: the points of an isosurface all carry the isovalue, so the default is the uniform
    // surface colour; --color value maps it within --range, else within the volume's value range.
    // (block colours need points seeded in blocks: multiblock input, Batch::point_block)
    const bool multiblock_input = !a.positional().empty() && looks_like_multiblock(a.positional()[0]);
    if (cc.request == ColorRequest::block && !multiblock_input)
        throw UsageError((a.positional().empty() ? std::string("the input") : a.positional()[0]) +
                         ": a volume has no blocks; --color block needs multiblock points");
    // (the range without --range: the volume's, set below once it is read; the MPI and sample-store
    // paths map the isovalue to the middle of the colour map)
    apply_color(rs, color_by(cc, ColorBy::none), cc, cc.range ? *cc.range : std::array<double, 2>{iso, iso});

    if (launched_world_size() > 1) {
        if (!a.positional().empty() && is_sample_store(a.positional()[0]))
            throw UsageError(a.positional()[0] + ": MPI runs need a brick store (.mlb); a sample store (.mls) runs in one "
                             "process (meshless isosurface STORE.mls, or its .mlb under mpirun)");
        const MpiIsosurfaceResult m = isosurface_mpi(a, argc, argv, iso, mode, sp, nthreads, rs, cc.range.has_value());
        if (m.root && a.has("stats")) print_isosplat_stats(stderr, m.path, iso, mode, m.result, m.points, nthreads, m.ranks);
        return 0;
    }
    if (!a.positional().empty() && is_sample_store(a.positional()[0]))
        return isosurface_sample_store(a, iso, mode, sp, rs, cc.range.has_value(), nthreads);

    VolumeInput in = open_volume_input(a, /*stream=*/true);
    if (png) apply_anatomical_default(a, in, rs.camera);  // head up, face to the viewer, where the header says
    StreamMeta meta = volume_meta(in, iso, a.command_line());  // value range and surface bounds, one pass
    if (!cc.range) {
        rs.shading.value_lo = meta.get_double("value_min").value_or(iso);
        rs.shading.value_hi = meta.get_double("value_max").value_or(iso);
    }
    warn_if_iso_outside(iso, {meta.get_double("value_min").value_or(NAN), meta.get_double("value_max").value_or(NAN)},
                        in.path);
    meta.set("projection", to_string(mode));

    IsoSplatResult r;
    ProgressMeter meter = ProgressMeter::of(a, "cell rows", isosurface_work(in, iso));
    const ProgressStage progress([&](double n) { meter.add(n); }, work_units);
    const std::size_t points = run_to_outputs(geometry_output(a, kPointsWhat), a.get("png"), meta, rs, nthreads, [&](const Stage* draw, Sink& sink) {
        return run_isosplat_input(in, iso, mode, sp, sink, nthreads, PipelineShape::fused, {&progress, draw});
    }, r);
    meter.done();
    if (a.has("stats")) print_isosplat_stats(stderr, in.path, iso, mode, r, points, nthreads, 1);
    return 0;
}

}  // namespace meshless::cli
