// meshless isosurface: paradigm (C) iso-splatting in one process (dissertation chapter 3).
#include <algorithm>
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
#include "formats/hdf5_volume.hpp"
#include "formats/atomic_file.hpp"
#include "formats/multiblock_reader.hpp"
#include "kernels/errors.hpp"
#include "stream/isosplat_job.hpp"
#include "stream/isosplat_mpi.hpp"
#include "stream/mpi_session.hpp"
#include "stream/progress_stage.hpp"
#include "stream/sample_store_source.hpp"

namespace meshless::cli {

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
    if (names_blocks(positionals)) return isosurface_blocks(argc, argv);
    // scattered point sets (chapter 5)
    if (scattered_invocation(positionals, argc, argv)) return isosurface_scattered(argc, argv);
    return std::nullopt;
}

/// The volume isosurface's options, help and examples.
void declare_isosurface_options(Args& a) {
    a.option("iso", "", "V[,V2...]", "isovalue (required); several, comma-separated: their surfaces one after another in the same outputs, coloured by isovalue")
        .option("output", "o", "FILE", "point set output (.ply binary PLY, .vtp VTK XML PolyData; '-' for stdout)")
        .option("png", "", "FILE", "also render the points to this PNG")
        .option("projection", "", "MODE", "approx (one Newton step, Eq. 3.5) | exact (ray-trilinear cubic, Eq. 3.3) | none", "approx")
        .option("color-by", "", "ARRAY",
                "colour by another array of the volume (of a .vti, VTK legacy or vtk.js file; an HDF5 dataset's path):\n"
                "each point's value becomes ARRAY's trilinear value at the point, written to the point set\n"
                "(its comments name the array) and mapped by --png over ARRAY's range (or --range); the\n"
                "array is read whole into memory. One process, a volume (not a sample store)")
        .flag("stats", "print counts (active cells, discarded samples) and timing to stderr");
    add_fail_empty_option(a);
    add_geometry_format_option(a);
    add_ply_color_option(a);
    add_sampling_options(a);
    add_volume_options(a);
    add_crop_option(a);
    add_memory_option(a);
    add_thread_option(a);
    add_quiet_option(a);
    add_camera_options(a);
    add_color_options(a);
    a.epilog("BLOCKS (PLOT3D, .vts pieces, .vtm/.vthb, or several files): the multiblock/AMR isosurface of chapter 4\n"
             "          (meshless isosurface BLOCKS... --help for its options).\n"
             "POINTS (scattered: CSV/TSV, PLY, VTP, VTU nodes, raw records, 2-D .npy, point stores .mlc): the isosurface of chapter 5\n"
             "          (meshless isosurface POINTS --help for its options).\n"
             "examples: meshless isosurface ../shared/data/fuel/fuel_64x64x64_uint8.raw --iso 20.5 -o fuel.ply --png fuel.png\n"
             "          meshless isosurface vol.mlb --iso 100.5 --memory 256M -o out.ply\n"
             "          mpirun -np 4 meshless isosurface vol.mlb --iso 100.5 -o out.ply   (ranks split the active bricks)\n");
}

/// Colours: the points of an isosurface all carry the isovalue, so the default is the uniform surface
/// colour; --color value maps it within --range, else within the volume's value range (set by the job
/// once it is read; the MPI and sample-store paths map the isovalue to the middle of the colour map).
/// Several isovalues: each surface its colour by default, the colour map spanning the isovalues.
/// --color-by: the array's values, mapped over its range (set by the job).
void apply_isosurface_colors(const Args& a, IsosplatJob& j) {
    const ColorChoice cc = color_choice(a);
    // (block colours need points seeded in blocks: multiblock input, Batch::point_block)
    const bool multiblock_input = !a.positional().empty() && looks_like_multiblock(a.positional()[0]);
    if (cc.request == ColorRequest::block && !multiblock_input)
        throw UsageError((a.positional().empty() ? std::string("the input") : a.positional()[0]) +
                         ": a volume has no blocks; --color block needs multiblock points");
    if (const auto name = a.get("color-by")) {
        if (name->empty()) throw UsageError("--color-by: expected the name of an array (meshless info lists them)");
        apply_color(j.rs, color_by(cc, ColorBy::value), cc, cc.range ? *cc.range : std::array<double, 2>{0, 1});
        j.range_given = cc.range.has_value();
    } else if (!j.isos.empty()) {
        const auto [lo, hi] = std::minmax_element(j.isos.begin(), j.isos.end());
        apply_color(j.rs, color_by(cc, ColorBy::value), cc, cc.range ? *cc.range : std::array<double, 2>{*lo, *hi});
        j.range_given = true;
    } else {
        apply_color(j.rs, color_by(cc, ColorBy::none), cc, cc.range ? *cc.range : std::array<double, 2>{j.iso, j.iso});
        j.range_given = cc.range.has_value();
    }
}

/// Under mpirun: rank 0 writes through the outputs of one process; a failing rank ends the job.
int isosurface_under_mpi(const Args& a, IsosplatJob& j, int& argc, char**& argv) {
    single_iso(a, "runs under mpirun");
    if (a.has("color-by")) throw UsageError("--color-by runs in one process, not under mpirun");
    if (!a.positional().empty() && is_sample_store(a.positional()[0]))
        throw UsageError(a.positional()[0] + ": MPI runs need a brick store (.mlb); a sample store (.mls) runs in one "
                         "process (meshless isosurface STORE.mls, or its .mlb under mpirun)");
    // the outputs' options checked on every rank before any talks (rank 0 alone opens them, later)
    const std::optional<GeometryOutput> out = geometry_output(a, kPointsWhat);
    j.out = [out] { return out; };
    MpiSession mpi(&argc, &argv);
    try {
        VolumeInput in = open_volume_input(a);
        run_isosplat_mpi_job(j, mpi, in);
    } catch (const std::exception& e) {
        return end_mpi_run(mpi, "isosurface", e);
    }
    return 0;
}

}  // namespace

int cmd_isosurface(int argc, char** argv) {
    Args a("isosurface", "VOLUME --iso V -o out.ply|out.vtp [--png out.png] [options]",
           "Paradigm (C) iso-splatting: one sample per active cell (cell centre), value and gradient by\n"
           "trilinear interpolation, projected onto the isosurface; writes an oriented point set\n"
           "(binary PLY: x y z nx ny nz radius value, or VTK XML PolyData .vtp with vertex cells, Normals,\n"
           "radius, value) and/or a surface-splatted picture.\n"
           "VOLUME: raw (name_XxYxZ_type.raw or --dims/--type), NRRD (.nrrd/.nhdr), MetaImage (.mhd/.mha),\n"
           "VTK legacy (.vtk), VTK XML image (.vti), vtk-js (index.json), SLC, NIfTI, a 3-D NumPy .npy (shape\n"
           "(nz, ny, nx), --spacing), a Zarr v2 store or OME-Zarr image (a folder, read chunk row by chunk row),\n"
           "an HDF5 dataset (FILE.h5:/PATH, or --array PATH), a DICOM series, or a brick store (.mlb,\n"
           "see meshless convert), read brick by brick: only bricks the isosurface crosses, within --memory,\n"
           "or a paradigm (A) sample store (.mls, see meshless generate --all): only its candidate cell rows.");
    declare_isosurface_options(a);
    if (const auto other = isosurface_of_blocks_or_points(a, argc, argv)) return *other;
    if (!a.parse(argc, argv, 2)) return 0;
    IsosplatJob j;
    j.isos = isovalue_list(a);
    j.iso = j.isos[0];
    if (j.isos.size() == 1) j.isos.clear();
    j.png = point_outputs_png(a);
    j.mode = parse_projection(a.get_or("projection", "approx"));
    j.sp = sampling_params(a);
    j.rs = render_settings(a);
    j.threads = threads(a);
    apply_isosurface_colors(a, j);
    j.producer = a.command_line();
    j.out = [&a] { return geometry_output(a, kPointsWhat); };
    j.anatomical_camera = [&a](const AnatomicalFrame& f, Camera& c) { apply_anatomical_frame(a, f, c); };
    j.no_axes_hint = [&a](const std::string& volume) { no_patient_axes_hint(a, volume); };
    j.up_given = a.has("up");
    j.progress = progress_counter(a);
    if (a.has("stats")) j.stats = stderr;
    bool warned = false;  // the run said its outputs will be empty (an isovalue outside the data)
    j.warned = &warned;

    if (launched_world_size() > 1) return isosurface_under_mpi(a, j, argc, argv);
    if (!a.positional().empty() && is_sample_store(a.positional()[0])) {
        if (a.has("color-by")) throw UsageError("--color-by: " + a.positional()[0] + " is a sample store, which holds one array (give the volume itself)");
        const std::size_t points = run_isosplat_sample_store_job(j, a.positional()[0]);
        return empty_result_exit(a, points, "points", j.iso, a.positional()[0], warned);
    }
    VolumeInput in = open_volume_input(a, /*stream=*/true);
    if (const auto name = a.get("color-by")) {
        VolumeOpenOptions o = volume_open_options(a, false);
        o.raw.array = *name;
        const auto h5 = hdf5_path(in.path);  // FILE.h5:/DATASET: the other array is another dataset of FILE
        j.color_by = std::make_shared<const ColorByArray>(ColorByArray{*name, load_volume(h5 && !h5->dataset.empty() ? h5->file : in.path, o)});
    }
    const std::size_t points = run_isosplat_job(j, in);
    return empty_result_exit(a, points, "points", j.iso, in.path, warned);
}

}  // namespace meshless::cli
