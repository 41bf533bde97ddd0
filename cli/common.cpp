#include "cli/common.hpp"
#include "formats/binary_file.hpp"
#include "formats/point_set_writer.hpp"
#include "formats/stdin_spool.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "cli/errors.hpp"

#include "formats/atomic_file.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/anatomical_view.hpp"
#include "kernels/errors.hpp"
#include "stream/available_cpus.hpp"
#include "stream/available_memory.hpp"
#include "formats/stored_type.hpp"
#include "formats/text_header.hpp"

namespace meshless::cli {

void add_volume_options(Args& a) {
    a.option("dims", "", "X,Y,Z", "raw volumes: samples along x, y, z")
        .option("type", "", "T", "raw volumes: uint8 | int16 | uint16 | float32")
        .option("endian", "", "little|big", "raw volumes: byte order of the samples", "little")
        .option("spacing", "", "SX,SY,SZ", "raw volumes: voxel spacing, world units, 1.2e-38..3.4e38", "1,1,1")
        .option("series", "", "UID|N", "DICOM: the series to read from a folder holding several (its UID, or N in their listing)")
        .option("resolution-level", "", "N", "OME-Zarr images: the multiscale level to read, 0..64 (at most the image's levels - 1, "
                                             "which meshless info shows), 0 the full resolution", "0");
    add_array_option(a);
}

void add_array_option(Args& a) {
    a.option("array", "", "NAME", kArrayOptionHelp);
}

RawOptions raw_options(const Args& a) {
    RawOptions raw;
    if (auto d = a.get_triple("dims")) {
        std::array<std::int64_t, 3> dims{};
        for (int i = 0; i < 3; ++i) {
            if ((*d)[i] < 1 || (*d)[i] != static_cast<double>(static_cast<std::int64_t>((*d)[i])))
                throw UsageError("--dims: expected three positive integers");
            dims[i] = static_cast<std::int64_t>((*d)[i]);
        }
        raw.dims = dims;
    }
    if (auto t = a.get("type")) {
        auto st = parse_sample_type(*t);
        if (!st) throw UsageError("--type: unknown sample type '" + *t + "' (uint8, int16, uint16, float32)");
        raw.type = *st;
    }
    const std::string endian = a.get_or("endian", "little");
    if (endian != "little" && endian != "big") throw UsageError("--endian: expected little or big, got '" + endian + "'");
    raw.big_endian = endian == "big";
    if (auto s = a.get_triple("spacing")) {
        for (double x : *s)
            // finite, and within the normal float32 range points are written in; the positions the
            // spacing gives are checked once the volume's dimensions are known (validate_given_spacing)
            if (!(x >= 1.1754943508222875e-38) || !(x <= 3.4028234663852886e38))
                throw UsageError("--spacing: spacings must be at least 1.2e-38 and at most 3.4e38 (the float32 range), got " +
                                 a.get_or("spacing", ""));
        raw.spacing = *s;
    }
    if (auto s = a.get("series")) {
        if (s->empty()) throw UsageError("--series: expected a Series Instance UID or a series number");
        raw.series = *s;
    }
    if (auto n = a.get("array")) {
        if (n->empty()) throw UsageError("--array: expected the name of a point array (meshless info lists them)");
        raw.array = *n;
    }
    if (a.declared("resolution-level")) {
        const long long level = a.get_int_or("resolution-level", 0);
        if (level < 0 || level > 64) throw UsageError("--resolution-level: expected a level in 0..64, got " + std::to_string(level));
        raw.resolution_level = static_cast<int>(level);
    }
    return raw;
}

void add_crop_option(Args& a) {
    a.option("crop", "", "X0,Y0,Z0,X1,Y1,Z1",
             "only the samples inside this box, world units, corners included (at least 2 along each axis); "
             "a brick store reads only the bricks it touches")
        .validate([](const std::string& v) {
            if (parse_finite_list(v, "--crop", 6).size() != 6) throw UsageError("--crop: expected X0,Y0,Z0,X1,Y1,Z1, got '" + v + "'");
        });
}

VolumeOpenOptions volume_open_options(const Args& a, bool stream) {
    VolumeOpenOptions o;
    o.raw = raw_options(a);
    if (a.declared("crop") && a.has("crop")) {
        const std::vector<double> c = parse_finite_list(*a.get("crop"), "--crop", 6);
        o.crop = std::array<double, 6>{c[0], c[1], c[2], c[3], c[4], c[5]};
    }
    o.raw_given = a.has("dims") || a.has("type") || a.has("endian") || a.has("spacing");
    o.stream = stream;
    if (a.declared("memory") && a.has("memory")) o.memory = parse_memory_size(*a.get("memory"));
    o.threads = threads(a);
    o.warn = [command = a.command()](const std::string& line) {
        std::fprintf(stderr, "meshless %s: %s\n", command.c_str(), line.c_str());
    };
    return o;
}

namespace {
const std::string& volume_arg(const Args& a) {
    if (a.positional().empty()) throw UsageError("missing VOLUME argument (see meshless " + a.command() + " --help)");
    return a.positional()[0];
}
}  // namespace

void check_volume_fits(const Args& a, const std::string& path, const VolumeInfo& vi, bool map) {
    check_volume_fits(path, vi, map, volume_open_options(a, false).memory);
}

void check_option_fits(const Args& a, const std::string& option, const std::string& what, std::uint64_t need,
                       const std::string& hint) {
    (void)a;
    const std::uint64_t budget = available_memory();
    if (need <= budget) return;
    throw UsageError(option + ": " + what + " would take " + byte_size_text(need) + ", more than the " + byte_size_text(budget) +
                     " this process may use (physical memory, cgroup limit, ulimit -v)" + (hint.empty() ? "" : "; " + hint));
}

std::uint64_t image_bytes(int width, int height, std::uint64_t bytes_per_pixel) {
    return static_cast<std::uint64_t>(std::max(width, 0)) * static_cast<std::uint64_t>(std::max(height, 0)) * bytes_per_pixel;
}

Volume load_volume(const Args& a) { return load_volume(volume_arg(a), volume_open_options(a, false)); }

void add_sampling_options(Args& a) {
    a.option("radius-scale", "", "S", "splat radius = S * half the cell diagonal, 0 < S <= 1000", "1");
}

SamplingParams sampling_params(const Args& a) {
    SamplingParams sp;
    sp.radius_scale = a.get_double_or("radius-scale", 1.0);
    if (!(sp.radius_scale > 0 && sp.radius_scale <= 1000))  // beyond, a splat covers the whole volume
        throw UsageError("--radius-scale: expected 0 < S <= 1000, got " + a.get_or("radius-scale", ""));
    return sp;
}

void add_memory_option(Args& a) {
    a.option("memory", "", "BYTES",
             "brick stores (.mlb): brick cache budget, e.g. 256M, 2G; the EWA picture's footprints then keep at most an eighth of it in memory (else 64 MiB), the rest on disk",
             "256M")
        .validate([](const std::string& v) { (void)parse_memory_size(v); });
}

VolumeInput open_volume_input(const Args& a, bool stream) {
    const std::string& path = volume_arg(a);
    return open_volume_input(path, volume_open_options(a, stream));
}

void add_thread_option(Args& a) {
    a.option("threads", "j", "N",
             "worker threads, 0..1024, 0 = every CPU this process may use (affinity mask, cgroup quota); "
             "output bytes do not depend on it", "0");
}

int threads(const Args& a) {
    const long long n = a.get_int_or("threads", 0);
    if (n < 0 || n > 1024) throw UsageError("--threads: expected 0..1024");
    return n == 0 ? available_cpus() : static_cast<int>(n);
}

void add_orbit_options(Args& a, const char* default_size) {
    a.option("size", "", "WxH", "image size in pixels, 1..16384 per side; its buffers (19 bytes a pixel at least) must fit "
                                "in memory", default_size)
        .option("azimuth", "", "DEG", "camera rotation about the up axis (a volume whose header gives the patient's axes: about superior, from the face-on view)", "30")
        .option("elevation", "", "DEG", "camera elevation above the plane normal to the up axis (from the face-on view, as --azimuth)", "20")
        .option("up", "", "AXIS", "the world axis that points up in the picture: x, y, z, -x, -y or -z (superior, unless given, for a volume whose header gives the patient's axes)", "y")
        .option("view", "", "NAME", "a named view instead of --azimuth/--elevation: +x -x +y -y +z -z (the camera looks "
                                    "along that axis) or iso (looks along -1,-1,-1)")
        .option("zoom", "", "Z", "zoom factor in (0, 1e6] (1 frames the subject: the surface's bounds recorded in the stream or PLY, or the active bricks/blocks; render: the data's box or --bounds)", "1")
        .validate(in_range("--zoom", 0, false, 1e6))
        .flag("ortho", "orthographic instead of perspective projection");
}

void add_camera_options(Args& a) {
    add_orbit_options(a, "800x800");
    a.option("kernel", "", "quad|ewa", "splat kernel: quadrilateral or elliptical (EWA)", "ewa")
        .option("shading", "", "phong|lambert", "lighting of the splats (a headlight)", "phong");
}

void add_color_options(Args& a) {
    a.option("color", "", "MODE",
             "splat colours: value (colour map of the points' values) | block (a categorical palette of the block\n                            "
             "ids of multiblock points) | normal (RGB = (n + 1) / 2 of the unit normal) | none (the uniform surface\n                            "
             "colour); all lit by the headlight. Default: value when the points' values vary and the input is not an\n                            "
             "isosurface (a PLY/stream that records an isovalue: its points all carry that value), else none",
             "auto")
        .option("colormap", "", "NAME", "--color value: viridis (perceptually uniform) | coolwarm | gray", "viridis")
        .option("range", "", "LO,HI", "--color value: the colour map's value range (default: the points' min,max;\n                            "
                                     "isosurface: the volume's)")
        .flag("colorbar", "draw a legend into the picture: a colour bar with the value range (--color value; titled\n"
                          "                            with the array's name where the points record one: isosurface --color-by) or\n"
                          "                            the block palette's swatches with their ids (--color block)")
        .flag("axes", "draw the world axes (x red, y green, z blue, from the bottom left corner, as the camera sees\n"
                      "                            them) and a scale bar of a round length in world units (1, 2 or 5 x 10^k, at the\n"
                      "                            depth of the framed centre) into the picture; drawn by default, the bar labelled\n"
                      "                            with the unit, when the volume's file states its length unit (DICOM, NIfTI,\n"
                      "                            NRRD space units, OME-Zarr axes; a brick store or the points' PLY records it)")
        .flag("no-axes", "draw no axes or scale bar, even where the length unit is known");
}


ColorChoice color_choice(const Args& a) {
    ColorChoice c;
    c.request = parse_color_request(a.get_or("color", "auto"));
    if (!parse_colormap(a.get_or("colormap", "viridis"), c.colormap))
        throw UsageError("--colormap: expected viridis, coolwarm or gray, got '" + a.get_or("colormap", "") + "'");
    if (auto r = a.get("range")) {
        const auto comma = r->find(',');
        if (comma == std::string::npos) throw UsageError("--range: expected LO,HI, got '" + *r + "'");
        const double lo = parse_finite(r->substr(0, comma), "--range"), hi = parse_finite(r->substr(comma + 1), "--range");
        if (!(lo < hi)) throw UsageError("--range: LO must be less than HI, got '" + *r + "'");
        c.range = std::array<double, 2>{lo, hi};
    }
    c.colorbar = a.has("colorbar");
    return c;
}

void apply_color(RenderSettings& rs, ColorBy by, const ColorChoice& c, const std::array<double, 2>& range) {
    meshless::apply_color(rs, by, c, range, [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); });
}

CameraRequest camera_request(const Args& a, const char* default_size) {
    CameraRequest r;
    const std::string size = a.get_or("size", default_size);
    const auto wh = parse_size(size, "--size", 1, 16384);
    r.width = wh[0];
    r.height = wh[1];
    if (a.has("azimuth")) r.azimuth = parse_finite(*a.get("azimuth"), "--azimuth");
    if (a.has("elevation")) r.elevation = parse_finite(*a.get("elevation"), "--elevation");
    if (a.declared("up") && a.has("up")) r.up = a.get("up");
    if (a.declared("view")) r.view = a.get("view");
    r.zoom = parse_finite(a.get_or("zoom", "1"), "--zoom");
    r.ortho = a.has("ortho");
    return r;
}

namespace {
void camera_warning(const std::string& line) { std::fprintf(stderr, "meshless: warning: %s\n", line.c_str()); }
}  // namespace

Camera camera_from(const Args& a, const char* default_size) {
    const CameraRequest r = camera_request(a, default_size);
    // before any work: the picture's buffers (splat: two depth-key buffers of 8 bytes a pixel and the
    // RGB image; render: RGBA floats and the RGB image), at least 19 bytes a pixel
    check_option_fits(a, "--size " + a.get_or("size", default_size), "the image buffers (at least 19 bytes a pixel)",
                      image_bytes(r.width, r.height, 19), "give a smaller --size");
    // (without --up, a volume's header may still choose the up axis: apply_anatomical_default warns then)
    return request_camera(r, camera_warning);
}

void apply_anatomical_frame(const Args& a, const AnatomicalFrame& f, Camera& c) {
    apply_anatomical_camera(camera_request(a, "1x1"), f, c, camera_warning);
}

std::optional<AnatomicalFrame> apply_anatomical_default(const Args& a, const VolumeInput& in, Camera& c) {
    if (a.declared("up") && a.has("up")) return std::nullopt;
    if (in.frame) apply_anatomical_frame(a, *in.frame, c);
    else no_patient_axes_hint(a, in.path);
    return in.frame;
}

void no_patient_axes_hint(const Args& a, const std::string& volume) {
    if (!stderr_is_tty() || (a.declared("view") && a.has("view"))) return;
    std::fprintf(stderr,
                 "meshless %s: note: %s says nothing of the patient's axes (as NIfTI, NRRD, MetaImage and DICOM headers do): "
                 "the picture shows its x, y, z as they are; --up, --view, --azimuth and --elevation turn the camera\n",
                 a.command().c_str(), terminal_safe(volume).c_str());
}


AxesChoice axes_choice(const Args& a) {
    if (!a.declared("axes")) return AxesChoice::off;
    if (a.has("axes") && a.has("no-axes")) throw UsageError("--axes and --no-axes: give one");
    if (a.has("axes")) return AxesChoice::on;
    return a.has("no-axes") ? AxesChoice::off : AxesChoice::when_unit_known;
}

RenderSettings render_settings(const Args& a) {
    RenderSettings rs;
    rs.camera = camera_from(a, "800x800");
    rs.kernel = parse_splat_kernel(a.get_or("kernel", "ewa"));
    rs.shading = parse_shading(a.get_or("shading", "phong"));
    // --memory bounds the process: the EWA picture's footprints take an eighth of it at most
    if (a.declared("memory") && a.has("memory"))
        rs.spool_memory = std::min<std::uint64_t>(SplatSink::kSpoolMemory, parse_memory_size(*a.get("memory")) / 8);
    rs.axes = axes_choice(a);
    return rs;
}

Projection parse_projection(const std::string& s) {
    if (s == "none") return Projection::none;
    if (s == "approx") return Projection::approx;
    if (s == "exact") return Projection::exact;
    throw UsageError("--projection: expected none, approx or exact, got '" + s + "'");
}

double stream_iso(const Args& a, const StreamMeta& m) {
    const auto given = a.get("iso");
    const auto recorded = m.get_finite("iso");
    if (!given) {
        if (!recorded) throw UsageError("the stream records no isovalue; give --iso V");
        return *recorded;
    }
    const double iso = parse_finite(*given, "--iso");
    if (recorded && *recorded != iso)
        std::fprintf(stderr,
                     "meshless %s: warning: --iso %g differs from the stream's isovalue %g: the samples are the cells "
                     "active for %g, so the surface for %g may be incomplete\n",
                     a.command().c_str(), iso, *recorded, *recorded, iso);
    return iso;
}

void add_geometry_format_option(Args& a) {
    a.option("format", "", "ply|vtp",
             "format of -o when its name does not end in .ply or .vtp ('-' for stdout: default ply); "
             "vtp = VTK XML PolyData (zlib-compressed, ParaView/VTK)")
        .option("vtp-compression", "", "zlib|none",
                "VTP output: zlib-compressed arrays (smaller, VTK's vtkZLibDataCompressor) or raw (faster to write)", "zlib");
}

VtpOptions vtp_options(const Args& a, int threads) {
    VtpOptions o;
    o.threads = threads;
    const std::string c = a.get_or("vtp-compression", "zlib");
    if (c == "none") o.compression = VtpCompression::none;
    else if (c != "zlib") throw UsageError("--vtp-compression: expected zlib or none, got '" + c + "'");
    return o;
}

GeometryFormat geometry_output_format(const Args& a, const std::string& path, const char* what) {
    return meshless::geometry_output_format(path, a.get("format"), what);
}

void add_ply_color_option(Args& a) {
    a.option("ply-color", "", "value|block|normal",
             "PLY output: also write red green blue per point (the colour map of --colormap/--range over the values, the "
             "block palette, or (n + 1) / 2 of the normal), for readers that drop other properties (vtkPLYReader)");
}

std::optional<GeometryOutput> geometry_output(const Args& a, const char* what) {
    const auto out = a.get("output");
    if (!out) return std::nullopt;
    GeometryOutput g{*out, geometry_output_format(a, *out, what), vtp_options(a, 0), std::nullopt};
    if (auto c = a.get("ply-color")) {
        if (*c == "value") g.ply_color = ColorBy::value;
        else if (*c == "block") g.ply_color = ColorBy::block;
        else if (*c == "normal") g.ply_color = ColorBy::normal;
        else throw UsageError("--ply-color: expected value, block or normal, got '" + *c + "'");
        if (g.format != GeometryFormat::ply)
            throw UsageError("--ply-color: colours are for PLY output; VTP carries the arrays themselves (colour by them in ParaView)");
    }
    return g;
}

void add_fail_empty_option(Args& a) {
    a.flag("fail-empty", "an empty result (isovalue outside the data, or crossing no cell) exits 4 instead of 0 "
                         "(the empty outputs are still written; with several isovalues, when every surface is empty: "
                         "each empty one is warned of)");
}

std::vector<double> isovalue_list(const Args& a) { return parse_finite_list(a.require("iso"), "--iso", 256); }

double single_iso(const Args& a, const std::string& what) {
    const std::string v = a.require("iso");
    if (v.find(',') != std::string::npos)
        throw UsageError("--iso: " + what + " take one isovalue a run (several, comma-separated, are for isosurface, mc and generate "
                         "of a volume or a store, in one process), got '" + v + "'");
    return parse_finite(v, "--iso");
}

int empty_result_exit(const Args& a, std::uint64_t count, const char* what, double iso, const std::string& source,
                      bool warned) {
    if (count > 0) return 0;
    if (!warned)
        std::fprintf(stderr, "meshless: warning: %s: the isosurface at %g is empty (no %s); the outputs are empty\n",
                     terminal_safe(source).c_str(), iso, what);
    return a.has("fail-empty") ? kExitEmpty : 0;
}

bool stderr_is_tty() { return ::isatty(2) == 1; }

}  // namespace meshless::cli
