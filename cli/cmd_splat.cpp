// meshless splat: software surface splatting of a point stream or PLY (section 3.6).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

#include "cli/commands.hpp"
#include "formats/binary_file.hpp"
#include "cli/common.hpp"
#include "cli/render_output.hpp"
#include "formats/ply.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/png_writer.hpp"
#include "kernels/errors.hpp"
#include "kernels/triangle_rasterizer.hpp"
#include "stream/ply_source.hpp"
#include "stream/point_spool.hpp"
#include "stream/project_stage.hpp"
#include "stream/runner.hpp"
#include "stream/splat_sink.hpp"
#include "stream/stream_endpoints.hpp"
#include "stream/turntable.hpp"
#include "cli/progress_meter.hpp"

namespace meshless::cli {

namespace {


bool ply_has_vertex_property(const std::string& path, const char* name) {
    PlyReader r(path);
    const int v = r.header().find("vertex");
    return v >= 0 && r.header().elements[static_cast<std::size_t>(v)].find(name) >= 0;
}

/// True when the PLY has a non-empty face element: a mesh (meshless mc), drawn as its triangles.
bool ply_has_faces(const std::string& path) {
    PlyReader r(path);
    const int f = r.header().find("face");
    return f >= 0 && r.header().elements[static_cast<std::size_t>(f)].count > 0;
}

/// splat MESH.ply: the triangles, rasterised with the splat camera, shading and colours
/// (kernels/triangle_rasterizer.hpp); single-threaded, so every --threads gives the same bytes.
int splat_mesh(const Args& a, const std::string& input, const std::string& png, RenderSettings rs,
               const ColorChoice& cc, long long frames) {
    if (a.has("iso")) throw UsageError("--iso applies to sample streams; " + input + " holds a triangle mesh");
    if (cc.request == ColorRequest::value)
        throw UsageError(input + ": a triangle mesh carries no per-vertex values; --color value needs points "
                         "(use --color none, normal or block)");
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh mesh = read_ply_mesh(input);
    if (cc.request == ColorRequest::block && mesh.block.empty())
        throw UsageError(input + ": the triangles carry no block ids (no face property 'block'); --color block needs "
                         "a multiblock mesh");
    const ColorBy by = color_by(cc, ColorBy::none);
    apply_color(rs, by, cc, cc.range ? *cc.range : std::array<double, 2>{0, 1});
    if (by == ColorBy::block)
        rs.legend_blocks = mesh.block.empty() ? 0 : *std::max_element(mesh.block.begin(), mesh.block.end()) + 1;
    const std::array<Vec3, 2> bounds = mesh_bounds(mesh);
    const Camera& cam = rs.camera;
    if (frames > 0) {
        ProgressMeter meter = ProgressMeter::of(a, "frames", static_cast<double>(frames));
        double sum = 0, lo = 1e300, hi = 0;
        for (long long i = 0; i < frames; ++i) {
            Camera c = cam;
            c.azimuth_deg = cam.azimuth_deg + 360.0 * static_cast<double>(i) / static_cast<double>(frames);
            const auto f0 = std::chrono::steady_clock::now();
            Image img = render_triangles(mesh, c, rs.shading, bounds);
            const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - f0).count();
            sum += s;
            lo = std::min(lo, s);
            hi = std::max(hi, s);
            decorate_picture(rs, img);
            write_png(img, frame_path(png, static_cast<int>(i)));
            meter.add(1);
        }
        meter.done();
        std::fprintf(stderr, "splat: turntable of %lld frames, %zu triangles, %dx%d: %.2f ms/frame (min %.2f, max %.2f)\n",
                     frames, mesh.triangle_count(), cam.width, cam.height, 1e3 * sum / static_cast<double>(frames),
                     1e3 * lo, 1e3 * hi);
        return 0;
    }
    TriangleStats st;
    Image picture = render_triangles(mesh, cam, rs.shading, bounds, &st);
    decorate_picture(rs, picture);
    write_png(picture, png);
    if (stderr_is_tty() || a.has("stats"))
        std::fprintf(stderr, "splat: %zu triangles (%lld drawn, %lld fragments), %dx%d: %.3f s\n", mesh.triangle_count(),
                     static_cast<long long>(st.triangles_drawn), static_cast<long long>(st.fragments), cam.width, cam.height,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return 0;
}

/// What splat draws: a PLY point set (read in place) or a point/sample stream, with what it records.
struct SplatInput {
    std::unique_ptr<InputFile> file;       ///< a stream's file (stdin for -)
    std::unique_ptr<StreamReader> reader;  ///< a stream's reader
    std::unique_ptr<Source> source;
    std::optional<std::array<Vec3, 2>> bounds;  ///< the frame the input records (the surface's)
    std::unique_ptr<ProjectStage> project;      ///< sample streams: projection at render time
    StreamMeta recorded;                        ///< the PLY comments or the stream's metadata
};

SplatInput open_splat_input(const Args& a, const std::string& input, bool is_ply) {
    SplatInput in;
    if (is_ply) {
        if (a.has("iso")) throw UsageError("--iso applies to sample streams; " + input + " holds projected points");
        auto ply = std::make_unique<PlySource>(input);
        in.bounds = ply_picture_bounds(ply->comments());  // the surface bounds recorded by isosurface/write
        in.recorded = ply_comments_meta(ply->comments());
        in.source = std::move(ply);
        return in;
    }
    in.file = std::make_unique<InputFile>(input);
    in.reader = std::make_unique<StreamReader>(in.file->f, in.file->name);
    in.reader->read_meta();
    in.bounds = picture_bounds(in.reader->meta());
    if (in.reader->kind() == RecordKind::seed)
        throw UsageError(in.file->name + ": holds unprojected multiblock seeds; project them first: meshless project --field KIND BLOCKS...");
    in.source = std::make_unique<StreamSource>(*in.reader);
    if (in.reader->kind() == RecordKind::sample) {
        // paradigms (B)/(D): projection at render time
        in.project = std::make_unique<ProjectStage>(stream_iso(a, in.reader->meta()), parse_projection(a.get_or("projection", "approx")));
    } else if (a.has("iso")) {
        throw UsageError("--iso applies to sample streams; this stream holds projected points");
    }
    in.recorded = in.reader->meta();
    return in;
}

/// Point files meshless writes that splat does not draw: a FormatError that says what to write instead.
void refuse_other_point_files(const std::string& input) {
    for (const char* other : {".vtp", ".csv", ".tsv", ".txt"})
        if (ends_with_ci(input, other))
            throw FormatError(input + ": splat draws .ply point sets and meshless point streams, not " + (other + 1) +
                              " files (write the points as .ply: meshless isosurface ... -o points.ply)");
}

/// --turntable N: every frame replays the spool.
int splat_turntable(const Args& a, PointSpool& spool, const std::array<Vec3, 2>& bounds, const RenderSettings& rs,
                    long long frames, int nthreads, const std::string& png) {
    const Camera& cam = rs.camera;
    ProgressMeter meter = ProgressMeter::of(a, "frames", static_cast<double>(frames));
    const auto t = render_turntable(spool, bounds, cam, rs.kernel, rs.shading, static_cast<int>(frames), nthreads,
                                    [&](int i, const Image& img) {
                                        Image framed = img;
                                        decorate_picture(rs, framed);
                                        write_png(framed, frame_path(png, i));
                                        meter.add(1);
                                    });
    meter.done();
    std::fprintf(stderr, "splat: turntable of %d frames, %llu points, %dx%d %s: %.2f ms/frame (min %.2f, max %.2f)\n",
                 t.frames, static_cast<unsigned long long>(spool.size()), cam.width, cam.height,
                 rs.kernel == SplatKernel::quad ? "quad" : "ewa", 1e3 * t.mean_seconds, 1e3 * t.min_seconds,
                 1e3 * t.max_seconds);
    return 0;
}

}  // namespace

/// splat --help: what it draws and how.
constexpr const char* kSplatHelp =
           "Renders oriented points by surface splatting (software): quadrilateral (QSplat-style) or\n"
           "elliptical EWA kernels with depth-tested, normalised accumulation and Phong shading.\n"
           "INPUT is a point stream (stdin by default) or a .ply point set. Given a sample stream (from\n"
           "`meshless generate` or `meshless extract`), it projects at render time (paradigms B and D of\n"
           "Table 3.1): the isovalue comes from --iso or the stream. Points are drawn as they arrive (memory =\n"
           "the image buffers + one batch; the EWA kernel spools the points to an unlinked file in $TMPDIR\n"
           "for its second pass); the camera frames the surface bounds recorded in the stream or PLY.\n"
           "Input without recorded bounds, and --turntable, spool the points once to such a file (the\n"
           "frame is then known; each turntable frame replays the file): memory stays bounded. A binary\n"
           "PLY of the points `isosurface` writes is not copied: it is read in place, once to frame and\n"
           "colour the picture, then by each drawing pass (or turntable frame).\n"
           "Colours (--color): value, block (multiblock points' block ids), normal or none, lit by the\n"
           "headlight; by default value when the points' values vary and the input does not record an\n"
           "isovalue (an isosurface's points all carry it), else none (the uniform surface colour). Colouring\n"
           "by value without --range, by default, or by block from a stream first spools the points (their\n"
           "value range, block ids). --colorbar draws the value range as a legend bar (or the block colours\n"
           "with their ids) into the picture.\n"
           "A .ply with faces (a triangle mesh, `meshless mc`) is drawn as its triangles instead: z-buffered,\n"
           "the vertex normals interpolated (perspective-correct) and lit as the splats are, the camera\n"
           "framing the mesh's bounds; --kernel is ignored, --color takes none (default), normal or block\n"
           "(the faces' block ids; a mesh has no values for --color value); single-threaded.";

int cmd_splat(int argc, char** argv) {
    Args a("splat", "[INPUT|-|MESH.ply] -o img.png [--kernel quad|ewa] [--turntable N] [camera options]",
           kSplatHelp);
    a.option("output", "o", "FILE", "PNG output (required)")
        .option("iso", "", "V", "sample streams: isovalue to project onto (default: the stream's)")
        .option("projection", "", "MODE", "sample streams: approx | exact | none", "approx")
        .option("turntable", "", "N", "render N frames, 360/N degrees apart about the up axis (--up; y by default), as FILE_000.png ...; reports time per frame")
        .flag("stats", "print the point count, time and throughput to stderr");
    add_camera_options(a);
    add_color_options(a);
    add_thread_option(a);
    add_quiet_option(a);
    a.epilog("example: meshless generate vol.raw --iso 100.5 | meshless project | meshless splat -o img.png --turntable 36\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const std::string png = require_output_extension(a.require("output"), ".png", "-o", "a PNG image");
    RenderSettings rs = render_settings(a);
    const ColorChoice cc = color_choice(a);
    const Camera& cam = rs.camera;
    const long long frames = a.get_int_or("turntable", 0);
    if (a.has("turntable") && (frames < 1 || frames > 3600)) throw UsageError("--turntable: expected 1..3600 frames");
    if (frames > 0 && png == "-") throw UsageError("--turntable writes one file per frame: give -o NAME.png, not '-'");
    const std::string input = a.positional().empty() ? "-" : a.positional()[0];
    if (input != "-") require_regular_file(input);  // a FIFO would block the open: pipes come as -

    const int nthreads = threads(a);
    const bool is_ply = input.size() > 4 && input.substr(input.size() - 4) == ".ply";
    // The graph: PLY file or point/sample stream -> [project] -> draw (parallel) -> splat sink.
    if (is_ply && ply_has_faces(input)) return splat_mesh(a, input, png, rs, cc, frames);
    refuse_other_point_files(input);
    std::optional<PointSpool> spool;  // see below; outlives the source that may replay it
    SplatInput in = open_splat_input(a, input, is_ply);
    std::unique_ptr<Source>& source = in.source;
    std::optional<std::array<Vec3, 2>>& bounds = in.bounds;
    std::vector<const Stage*> stages;
    if (in.project) stages.push_back(in.project.get());

    // Colours: an isosurface (the input records its isovalue) is not coloured by value by default;
    // --color value maps it within the data's value range where the input records one (as
    // isosurface --png does: its points all hold the isovalue), and a block legend lists the blocks
    // it records.
    const StreamMeta& recorded = in.recorded;
    const bool isosurface_input = recorded.get("iso").has_value();
    std::optional<std::array<double, 2>> data_range;
    if (const auto lo = recorded.get_double("value_min"), hi = recorded.get_double("value_max");
        isosurface_input && lo && hi && std::isfinite(*lo) && std::isfinite(*hi) && *lo < *hi)
        data_range = std::array<double, 2>{*lo, *hi};
    // the patient's axes of the volume the points came from: the picture isosurface --png draws
    // (head up, face to the viewer) unless --up is given
    if (const auto f = meta_patient_axes(recorded)) apply_anatomical_frame(a, *f, rs.camera);
    std::optional<std::uint32_t> recorded_blocks;
    if (const auto nb = recorded.get_double("blocks"); nb && *nb >= 1 && *nb <= 4294967295.0 && *nb == std::floor(*nb))
        recorded_blocks = static_cast<std::uint32_t>(*nb);
    if (cc.request == ColorRequest::block && is_ply && !ply_has_vertex_property(input, "block"))
        throw UsageError(input + ": the points carry no block ids (no vertex property 'block'); --color block needs "
                         "multiblock points");
    const bool color_pass = (cc.request == ColorRequest::value && !cc.range && !data_range) ||
                            (cc.request == ColorRequest::automatic && !isosurface_input) ||
                            (cc.request == ColorRequest::block && !is_ply);

    // A turntable draws every point once per frame, and a picture without recorded bounds needs all
    // the points before its first one is drawn: the points (projected) go once to a point spool,
    // which is then replayed; memory stays a few batches.
    if (frames > 0 || !bounds || color_pass) {
        // a PLY file of PointRecords is its own spool (read once here, replayed from the file)
        if (is_ply && PointSpool::can_be_in_place(input)) spool.emplace(PointSpool::InPlace{}, input, nthreads);
        else {
            spool.emplace("splat-spool");
            run_pipeline(*source, stages, *spool, {nthreads});
        }
        if (!bounds) bounds = spool->bounds();
        if (cc.request == ColorRequest::block && spool->size() > 0 && !spool->has_blocks())
            throw UsageError(input + ": the points carry no block ids; --color block needs multiblock points");
    }
    {
        const std::optional<std::array<double, 2>> seen = spool ? spool->value_range() : std::nullopt;
        const ColorBy by = color_by(cc, !isosurface_input && seen && (*seen)[0] < (*seen)[1] ? ColorBy::value : ColorBy::none);
        apply_color(rs, by, cc, cc.range ? *cc.range : data_range ? *data_range : seen ? *seen : std::array<double, 2>{0, 1});
        if (spool) rs.legend_blocks = spool->block_count();
        else if (recorded_blocks) rs.legend_blocks = *recorded_blocks;
    }
    if (spool) {
        if (frames > 0) return splat_turntable(a, *spool, *bounds, rs, frames, nthreads, png);
        source = std::make_unique<PointSpoolSource>(*spool);
        stages.clear();  // projected already
    }
    const auto t0 = std::chrono::steady_clock::now();
    SplatSink sink(cam, rs.kernel, rs.shading, *bounds, nthreads, spool ? &*spool : nullptr);
    stages.push_back(&sink.stage());
    run_pipeline(*source, stages, sink, {nthreads});
    Image picture = sink.image();
    decorate_picture(rs, picture);
    write_png(picture, png);
    if (stderr_is_tty() || a.has("stats"))
        std::fprintf(stderr, "splat: %llu points, %dx%d %s, %d thread(s): %.3f s (%.2f M points/s)\n",
                     static_cast<unsigned long long>(sink.points()), cam.width, cam.height,
                     rs.kernel == SplatKernel::quad ? "quad" : "ewa", nthreads,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
                     1e-6 * sink.points() / std::max(1e-9, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()));
    return 0;
}

}  // namespace meshless::cli
