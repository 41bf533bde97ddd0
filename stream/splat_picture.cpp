#include "stream/splat_picture.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "formats/file_names.hpp"
#include "formats/input_file.hpp"
#include "formats/oriented_points_vtp.hpp"
#include "formats/ply.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/png_writer.hpp"
#include "formats/terminal_safe.hpp"
#include "kernels/errors.hpp"
#include "kernels/triangle_rasterizer.hpp"
#include "stream/ply_source.hpp"
#include "stream/point_spool.hpp"
#include "stream/project_stage.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/runner.hpp"
#include "stream/splat_sink.hpp"
#include "stream/stream_endpoints.hpp"
#include "stream/stream_metadata.hpp"
#include "stream/turntable.hpp"
#include "stream/seconds_since.hpp"

namespace meshless {

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

/// A triangle mesh: the triangles, rasterised with the splat camera, shading and colours
/// (kernels/triangle_rasterizer.hpp); single-threaded, so every thread count gives the same bytes.
SplatReport splat_mesh(RenderSettings rs, const SplatRequest& r) {
    const std::string& input = r.input;
    const ColorChoice& cc = r.color;
    if (r.iso_given) throw InvalidArgument("--iso applies to sample streams; " + input + " holds a triangle mesh");
    if (cc.request == ColorRequest::value)
        throw InvalidArgument(input + ": a triangle mesh carries no per-vertex values; --color value needs points "
                              "(use --color none, normal or block)");
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh mesh = read_ply_mesh(input);
    if (cc.request == ColorRequest::block && mesh.block.empty())
        throw InvalidArgument(input + ": the triangles carry no block ids (no face property 'block'); --color block needs "
                              "a multiblock mesh");
    const ColorBy by = color_by(cc, ColorBy::none);
    apply_color(rs, by, cc, cc.range ? *cc.range : std::array<double, 2>{0, 1}, r.warn);
    if (by == ColorBy::block)
        rs.legend_blocks = mesh.block.empty() ? 0 : *std::max_element(mesh.block.begin(), mesh.block.end()) + 1;
    const std::array<Vec3, 2> bounds = mesh_bounds(mesh);
    const Camera& cam = rs.camera;
    SplatReport rep;
    rep.mesh = true;
    rep.drawn = mesh.triangle_count();
    rep.camera = cam;
    if (r.frames > 0) {
        double sum = 0, lo = 1e300, hi = 0;
        for (long long i = 0; i < r.frames; ++i) {
            Camera c = cam;
            c.azimuth_deg = cam.azimuth_deg + 360.0 * static_cast<double>(i) / static_cast<double>(r.frames);
            const auto f0 = std::chrono::steady_clock::now();
            Image img = render_triangles(mesh, c, rs.shading, bounds);
            const double s = seconds_since(f0);
            sum += s;
            lo = std::min(lo, s);
            hi = std::max(hi, s);
            const ViewTransform view = make_view(c, bounds[0], bounds[1]);
            decorate_picture(rs, img, &view);
            write_png(img, frame_path(r.png, static_cast<int>(i)));
            if (r.frame_written) r.frame_written();
        }
        rep.frames = static_cast<int>(r.frames);
        rep.mean_seconds = sum / static_cast<double>(r.frames);
        rep.min_seconds = lo;
        rep.max_seconds = hi;
        return rep;
    }
    TriangleStats st;
    Image picture = render_triangles(mesh, cam, rs.shading, bounds, &st);
    const ViewTransform view = make_view(cam, bounds[0], bounds[1]);
    decorate_picture(rs, picture, &view);
    if (r.picture) r.picture(std::move(picture));
    else write_png(picture, r.png);
    rep.triangles_drawn = static_cast<long long>(st.triangles_drawn);
    rep.fragments = static_cast<long long>(st.fragments);
    rep.seconds = seconds_since(t0);
    return rep;
}

/// What is drawn: a PLY point set (read in place) or a point/sample stream, with what it records.
struct SplatInput {
    std::unique_ptr<InputFile> file;       ///< a stream's file (stdin for -)
    std::unique_ptr<StreamReader> reader;  ///< a stream's reader
    std::unique_ptr<Source> source;
    std::optional<std::array<Vec3, 2>> bounds;  ///< the frame the input records (the surface's)
    std::unique_ptr<ProjectStage> project;      ///< sample streams: projection at render time
    StreamMeta recorded;                        ///< the PLY comments or the stream's metadata
    PlySource* ply = nullptr;                   ///< a PLY's source (source): it counts the points it drops
};

SplatInput open_splat_input(const SplatRequest& r, bool is_ply) {
    const std::string& input = r.input;
    SplatInput in;
    if (ends_with_ci(input, ".vtp")) {  // read whole: 32 bytes a point
        if (r.iso_given) throw InvalidArgument("--iso applies to sample streams; " + input + " holds projected points");
        OrientedPointsVtp vtp = read_oriented_points_vtp(input);
        if (vtp.dropped > 0 && r.warn)
            r.warn("meshless splat: warning: " + terminal_safe(input) + ": " + std::to_string(vtp.dropped) +
                   " points with a non-finite position, normal, radius or value (or a zero normal or radius) dropped");
        in.bounds = ply_picture_bounds(vtp.comments);  // the metadata the writer records, as a PLY's comments
        in.recorded = ply_comments_meta(vtp.comments);
        in.source = std::make_unique<RecordVectorSource>(std::move(vtp.points));
        return in;
    }
    if (is_ply) {
        if (r.iso_given) throw InvalidArgument("--iso applies to sample streams; " + input + " holds projected points");
        auto ply = std::make_unique<PlySource>(input, /*drop_undrawable=*/true);  // as the VTP reader drops them
        in.ply = ply.get();
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
        throw InvalidArgument(in.file->name +
                              ": holds unprojected multiblock seeds; project them first: meshless project --field KIND BLOCKS...");
    in.source = std::make_unique<StreamSource>(*in.reader);
    if (in.reader->kind() == RecordKind::sample) {
        // paradigms (B)/(D): projection at render time
        if (const auto list = in.reader->meta().get("isovalues"))
            throw InvalidArgument(in.file->name + ": holds the samples of several isovalues (" + *list +
                                  "); project them first: meshless project | meshless splat");
        const auto [iso, mode] = r.sample_projection(in.reader->meta());
        in.project = std::make_unique<ProjectStage>(iso, mode);
    } else if (r.iso_given) {
        throw InvalidArgument("--iso applies to sample streams; this stream holds projected points");
    }
    in.recorded = in.reader->meta();
    return in;
}

/// Point files meshless writes that splat does not draw: a FormatError that says what to write instead.
void refuse_unsplattable_point_file(const std::string& input) {
    for (const char* other : {".csv", ".tsv", ".txt"})
        if (ends_with_ci(input, other))
            throw FormatError(input + ": splat draws oriented points (.ply, .vtp, meshless point streams), not " + (other + 1) +
                              " files (meshless isosurface ... -o points.ply writes them)");
}

/// A turntable: every frame replays the spool.
SplatReport splat_turntable(PointSpool& spool, const std::array<Vec3, 2>& bounds, const RenderSettings& rs,
                            const SplatRequest& r) {
    const Camera& cam = rs.camera;
    const auto t = render_turntable(spool, bounds, cam, rs.kernel, rs.shading, static_cast<int>(r.frames), r.threads,
                                    [&](int i, const Image& img) {
                                        Image framed = img;
                                        Camera c = cam;
                                        c.azimuth_deg = cam.azimuth_deg + 360.0 * i / static_cast<double>(r.frames);
                                        const ViewTransform view = make_view(c, bounds[0], bounds[1]);
                                        decorate_picture(rs, framed, &view);
                                        write_png(framed, frame_path(r.png, i));
                                        if (r.frame_written) r.frame_written();
                                    });
    SplatReport rep;
    rep.drawn = spool.size();
    rep.frames = t.frames;
    rep.mean_seconds = t.mean_seconds;
    rep.min_seconds = t.min_seconds;
    rep.max_seconds = t.max_seconds;
    rep.camera = cam;
    return rep;
}

}  // namespace

SplatReport splat_picture(RenderSettings rs, const SplatRequest& r) {
    const std::string& input = r.input;
    const ColorChoice& cc = r.color;
    const bool is_ply = input.size() > 4 && input.substr(input.size() - 4) == ".ply";
    if (is_ply && ply_has_faces(input)) return splat_mesh(std::move(rs), r);
    refuse_unsplattable_point_file(input);
    std::optional<PointSpool> spool;  // see below; outlives the source that may replay it
    SplatInput in = open_splat_input(r, is_ply);
    if (rs.length_unit.empty()) rs.length_unit = meta_length_unit(in.recorded);  // (isosurface's points record their volume's)
    std::unique_ptr<Source>& source = in.source;
    std::optional<std::array<Vec3, 2>>& bounds = in.bounds;
    std::vector<const Stage*> stages;
    if (in.project) stages.push_back(in.project.get());
    // a PLY's points that cannot be drawn, counted by its source: said once, as the VTP reader's
    bool warned = false;
    const auto warn_dropped = [&] {
        if (warned || !in.ply || in.ply->dropped() == 0 || !r.warn) return;
        warned = true;
        r.warn("meshless splat: warning: " + terminal_safe(input) + ": " + std::to_string(in.ply->dropped()) +
               " points with a non-finite position, normal, radius or value (or a zero normal or radius) dropped");
    };
    // Colours: an isosurface (the input records its isovalue) is not coloured by value by default;
    // colour by value maps it within the data's value range where the input records one (as
    // isosurface --png does: its points all hold the isovalue), and a block legend lists the blocks
    // it records.
    const StreamMeta& recorded = in.recorded;
    // an isosurface coloured by another array (isosurface --color-by) records the array's name: its
    // values vary, within the range it records, and name the legend
    const std::optional<std::string> value_name = recorded.get("value_name");
    const bool isosurface_input = recorded.get("iso").has_value() && !value_name;
    std::optional<std::array<double, 2>> data_range;
    if (const auto lo = recorded.get_double("value_min"), hi = recorded.get_double("value_max");
        (isosurface_input || value_name) && lo && hi && std::isfinite(*lo) && std::isfinite(*hi) && *lo < *hi)
        data_range = std::array<double, 2>{*lo, *hi};
    if (value_name) rs.legend_title = *value_name;
    else if (const auto unit = recorded.get("value_unit")) rs.legend_title = *unit;  // (the volume's values, e.g. HU)
    // the patient's axes of the volume the points came from: the picture isosurface --png draws
    // (head up, face to the viewer) unless the caller says otherwise
    if (const auto f = meta_patient_axes(recorded); f && r.anatomical_camera) r.anatomical_camera(*f, rs.camera);
    std::optional<std::uint32_t> recorded_blocks;
    if (const auto nb = recorded.get_double("blocks"); nb && *nb >= 1 && *nb <= 4294967295.0 && *nb == std::floor(*nb))
        recorded_blocks = static_cast<std::uint32_t>(*nb);
    if (cc.request == ColorRequest::block && is_ply && !ply_has_vertex_property(input, "block"))
        throw InvalidArgument(input + ": the points carry no block ids (no vertex property 'block'); --color block needs "
                              "multiblock points");
    const bool color_pass = (cc.request == ColorRequest::value && !cc.range && !data_range) ||
                            (cc.request == ColorRequest::automatic && !isosurface_input) ||
                            (cc.request == ColorRequest::block && !is_ply);
    // A turntable draws every point once per frame, and a picture without recorded bounds needs all
    // the points before its first one is drawn: the points (projected) go once to a point spool,
    // which is then replayed; memory stays a few batches.
    if (r.frames > 0 || !bounds || color_pass) {
        // a PLY file of PointRecords is its own spool (read once here, replayed from the file)
        if (is_ply && PointSpool::can_be_in_place(input)) spool.emplace(PointSpool::InPlace{}, input, r.threads);
        // points that cannot be drawn are dropped, counted and said: such a file is spooled through its filter
        if (spool && spool->undrawable() > 0) spool.reset();
        if (!spool) {
            spool.emplace("splat-spool");
            run_pipeline(*source, stages, *spool, {r.threads});
        }
        if (!bounds) bounds = spool->bounds();
        warn_dropped();
        if (cc.request == ColorRequest::block && spool->size() > 0 && !spool->has_blocks())
            throw InvalidArgument(input + ": the points carry no block ids; --color block needs multiblock points");
    }
    {
        const std::optional<std::array<double, 2>> seen = spool ? spool->value_range() : std::nullopt;
        const ColorBy by = color_by(cc, !isosurface_input && seen && (*seen)[0] < (*seen)[1] ? ColorBy::value : ColorBy::none);
        apply_color(rs, by, cc, cc.range ? *cc.range : data_range ? *data_range : seen ? *seen : std::array<double, 2>{0, 1},
                    r.warn);
        if (spool) rs.legend_blocks = spool->block_count();
        else if (recorded_blocks) rs.legend_blocks = *recorded_blocks;
    }
    if (spool) {
        if (r.frames > 0) return splat_turntable(*spool, *bounds, rs, r);
        source = std::make_unique<PointSpoolSource>(*spool);  // the PLY's source (and its count, said above) is gone
        in.ply = nullptr;
        stages.clear();  // projected already
    }
    const Camera& cam = rs.camera;
    const auto t0 = std::chrono::steady_clock::now();
    SplatSink sink(cam, rs.kernel, rs.shading, *bounds, r.threads, spool ? &*spool : nullptr);
    stages.push_back(&sink.stage());
    run_pipeline(*source, stages, sink, {r.threads});
    warn_dropped();
    Image picture = sink.image();
    decorate_picture(rs, picture, &sink.frame().view());
    if (r.picture) r.picture(std::move(picture));
    else write_png(picture, r.png);
    SplatReport rep;
    rep.drawn = sink.points();
    rep.seconds = seconds_since(t0);
    rep.camera = cam;
    return rep;
}

void print_splat_report(std::FILE* out, const SplatReport& rep, SplatKernel kernel, int threads) {
    const Camera& cam = rep.camera;
    if (rep.frames > 0)
        std::fprintf(out, "splat: turntable of %d frames, %llu %s, %dx%d%s: %.2f ms/frame (min %.2f, max %.2f)\n",
                     rep.frames, static_cast<unsigned long long>(rep.drawn), rep.mesh ? "triangles" : "points", cam.width,
                     cam.height, rep.mesh ? "" : kernel == SplatKernel::quad ? " quad" : " ewa", 1e3 * rep.mean_seconds,
                     1e3 * rep.min_seconds, 1e3 * rep.max_seconds);
    else {
        if (rep.mesh)
            std::fprintf(out, "splat: %llu triangles (%lld drawn, %lld fragments), %dx%d: %.3f s\n",
                         static_cast<unsigned long long>(rep.drawn), rep.triangles_drawn, rep.fragments, cam.width,
                         cam.height, rep.seconds);
        else
            std::fprintf(out, "splat: %llu points, %dx%d %s, %d thread(s): %.3f s (%.2f M points/s)\n",
                         static_cast<unsigned long long>(rep.drawn), cam.width, cam.height,
                         kernel == SplatKernel::quad ? "quad" : "ewa", threads, rep.seconds,
                         1e-6 * static_cast<double>(rep.drawn) / std::max(1e-9, rep.seconds));
    }
}

}  // namespace meshless
