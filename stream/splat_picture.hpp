// The splat picture recipe (dissertation section 3.6): oriented points from a PLY point set (read in
// place) or a point/sample stream (projected at render time: paradigms B and D of Table 3.1) drawn by
// the splat sink, quad or EWA kernels; a turntable of N frames replaying a point spool; and a
// triangle mesh PLY (meshless mc) drawn as its triangles (kernels/triangle_rasterizer.hpp). The
// graph: source -> [project] -> draw (parallel) -> splat sink; points are drawn as they arrive
// (memory: the image buffers and a batch) unless the frame or the colours need them all first, when
// they go once to a point spool (an unlinked file in $TMPDIR) that is replayed.
// Units: world units; pictures are 8-bit RGB PNGs of the camera's size, written atomically (or handed
// to SplatRequest::picture).
// Throws InvalidArgument for a request the input cannot satisfy (an isovalue for points, colour by
// value of a mesh, colour by block of points without block ids, unprojected seeds), FormatError for
// bad files, IoError when a picture cannot be written. The bytes do not depend on the thread count.
#pragma once
#include <cstdio>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>

#include "formats/anatomical_frame.hpp"
#include "formats/point_stream.hpp"
#include "kernels/project_sample.hpp"
#include "stream/render_settings.hpp"

namespace meshless {

/// What is splatted, where to, and how.
struct SplatRequest {
    std::string input;        ///< a .ply (points or a triangle mesh) or a point/sample stream ("-": stdin)
    std::string png;          ///< the picture, or the name of a turntable's frames (frame_path)
    long long frames = 0;     ///< turntable frames, 360/frames degrees apart (0: one picture)
    int threads = 1;
    ColorChoice color;
    bool iso_given = false;   ///< the caller gave an isovalue: refused unless the input is a sample stream
    /// A sample stream's isovalue (from its metadata or the caller's choice, with its warnings) and
    /// projection; asked only of sample streams.
    std::function<std::pair<double, Projection>(const StreamMeta&)> sample_projection;
    /// The default camera of points whose volume recorded the patient's axes (may be empty).
    std::function<void(const AnatomicalFrame&, Camera&)> anatomical_camera;
    std::function<void(const std::string&)> warn;  ///< one-line warnings (may be empty)
    std::function<void()> frame_written;           ///< a turntable frame was written (may be empty)
    /// One picture (frames == 0): when set, receives the finished picture (legend drawn) instead of
    /// its being written to `png` (front ends that keep pictures in memory: the Python module).
    std::function<void(Image&&)> picture;
};

/// What was drawn and how long it took.
struct SplatReport {
    bool mesh = false;             ///< triangles rather than points
    std::uint64_t drawn = 0;       ///< triangles of the mesh, or points splatted
    long long triangles_drawn = 0, fragments = 0;  ///< a mesh picture's rasteriser counts
    int frames = 0;                ///< turntable frames written (0: one picture)
    double mean_seconds = 0, min_seconds = 0, max_seconds = 0;  ///< per turntable frame
    double seconds = 0;            ///< one picture: the drawing's wall time
    Camera camera;                 ///< the camera used (the anatomical default applied)
};

/// Draws the picture(s) of `r` with the settings `rs` (camera, kernel, shading; the colours are
/// resolved here against the input from r.color) and writes them.
SplatReport splat_picture(RenderSettings rs, const SplatRequest& r);

/// The report line of splat_picture to `out` (prefixed `splat: `): a turntable's frames and times
/// per frame, or one picture's points (with the kernel and `threads`) or triangles, its time and rate.
void print_splat_report(std::FILE* out, const SplatReport& rep, SplatKernel kernel, int threads);

}  // namespace meshless
