#include "cli/common.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <thread>

#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"

namespace meshless::cli {

void add_volume_options(Args& a) {
    a.option("dims", "", "X,Y,Z", "raw volumes: samples along x, y, z")
        .option("type", "", "T", "raw volumes: uint8 | int16 | uint16 | float32")
        .option("endian", "", "little|big", "raw volumes: byte order of the samples", "little")
        .option("spacing", "", "SX,SY,SZ", "raw volumes: voxel spacing in world units", "1,1,1");
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
            if (!(x > 0)) throw UsageError("--spacing: spacings must be positive");
        raw.spacing = *s;
    }
    return raw;
}

Volume load_volume(const Args& a) {
    if (a.positional().empty()) throw UsageError(a.command() + ": missing VOLUME argument (see meshless " + a.command() + " --help)");
    return read_volume(a.positional()[0], raw_options(a));
}

void add_sampling_options(Args& a) {
    a.option("radius-scale", "", "S", "splat radius = S * half the cell diagonal", "1");
}

SamplingParams sampling_params(const Args& a) {
    SamplingParams sp;
    sp.radius_scale = a.get_double_or("radius-scale", 1.0);
    if (!(sp.radius_scale > 0)) throw UsageError("--radius-scale: must be positive");
    return sp;
}

void add_thread_option(Args& a) {
    a.option("threads", "j", "N", "worker threads (0 = all cores); output bytes do not depend on it", "1");
}

int threads(const Args& a) {
    const long long n = a.get_int_or("threads", 1);
    if (n < 0 || n > 1024) throw UsageError("--threads: expected 0..1024");
    return n == 0 ? static_cast<int>(std::max(1u, std::thread::hardware_concurrency())) : static_cast<int>(n);
}

void add_camera_options(Args& a) {
    a.option("size", "", "WxH", "image size in pixels", "800x800")
        .option("azimuth", "", "DEG", "camera rotation about the y axis", "30")
        .option("elevation", "", "DEG", "camera elevation", "20")
        .option("zoom", "", "Z", "zoom factor (1 frames the whole volume)", "1")
        .option("kernel", "", "quad|ewa", "splat kernel: quadrilateral or elliptical (EWA)", "ewa")
        .flag("ortho", "orthographic instead of perspective projection");
}

Camera camera_from(const Args& a) {
    Camera c;
    const std::string size = a.get_or("size", "800x800");
    const auto x = size.find('x');
    if (x == std::string::npos) throw UsageError("--size: expected WxH, got '" + size + "'");
    c.width = static_cast<int>(parse_int(size.substr(0, x), "--size width"));
    c.height = static_cast<int>(parse_int(size.substr(x + 1), "--size height"));
    if (c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384)
        throw UsageError("--size: width and height must be 1..16384");
    c.azimuth_deg = a.get_double_or("azimuth", 30);
    c.elevation_deg = a.get_double_or("elevation", 20);
    c.zoom = a.get_double_or("zoom", 1);
    if (!(c.zoom > 0)) throw UsageError("--zoom: must be positive");
    c.perspective = !a.has("ortho");
    return c;
}

SplatKernel kernel_from(const Args& a) {
    const std::string k = a.get_or("kernel", "ewa");
    if (k == "quad") return SplatKernel::quad;
    if (k == "ewa") return SplatKernel::ewa;
    throw UsageError("--kernel: expected quad or ewa, got '" + k + "'");
}

namespace {
std::string triple(double a, double b, double c) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g", a, b, c);
    return buf;
}
std::optional<Vec3> parse_triple_meta(const StreamMeta& m, const std::string& key) {
    auto s = m.get(key);
    if (!s) return std::nullopt;
    double v[3];
    if (std::sscanf(s->c_str(), "%lf,%lf,%lf", &v[0], &v[1], &v[2]) != 3)
        throw FormatError("stream metadata: '" + key + "' is not three numbers: " + *s);
    return Vec3{v[0], v[1], v[2]};
}
}  // namespace

StreamMeta volume_meta(const std::string& source, const Volume& v, double iso, const std::string& producer) {
    StreamMeta m;
    const GridSpec& g = v.grid;
    m.set("source", std::filesystem::path(source).filename().string());
    m.set("iso", iso);
    m.set("grid_dims", std::to_string(g.dims[0]) + "," + std::to_string(g.dims[1]) + "," + std::to_string(g.dims[2]));
    m.set("grid_origin", triple(g.origin[0], g.origin[1], g.origin[2]));
    m.set("grid_spacing", triple(g.spacing[0], g.spacing[1], g.spacing[2]));
    m.set("bounds_lo", triple(g.origin[0], g.origin[1], g.origin[2]));
    m.set("bounds_hi", triple(g.origin[0] + (g.dims[0] - 1) * g.spacing[0], g.origin[1] + (g.dims[1] - 1) * g.spacing[1],
                              g.origin[2] + (g.dims[2] - 1) * g.spacing[2]));
    const auto r = v.value_range();
    m.set("value_min", r[0]);
    m.set("value_max", r[1]);
    m.set("sample_type", to_string(v.type));
    m.set("producer", producer);
    return m;
}

std::vector<std::string> ply_comments(const StreamMeta& m) {
    std::vector<std::string> c{"meshless oriented point set: x y z, unit normal, splat radius, value"};
    for (const char* k : {"source", "iso", "projection", "grid_dims", "grid_spacing"})
        if (auto v = m.get(k)) c.push_back(std::string(k) + " " + *v);
    return c;
}

std::optional<std::array<Vec3, 2>> meta_bounds(const StreamMeta& m) {
    auto lo = parse_triple_meta(m, "bounds_lo"), hi = parse_triple_meta(m, "bounds_hi");
    if (!lo || !hi) return std::nullopt;
    return std::array<Vec3, 2>{*lo, *hi};
}

void warn_if_iso_outside(double iso, const std::array<double, 2>& range, const std::string& source) {
    if (iso < range[0] || iso > range[1])
        std::fprintf(stderr, "meshless: warning: %s: isovalue %g is outside the data range [%g, %g]; the outputs will be empty\n",
                     source.c_str(), iso, range[0], range[1]);
}

InputFile::InputFile(const std::string& path) : name(path) {
    if (path == "-") {
        f = stdin;
        return;
    }
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a file");
    f = std::fopen(path.c_str(), "rb");
    if (!f) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
}

InputFile::~InputFile() {
    if (f && f != stdin) std::fclose(f);
}

bool stderr_is_tty() { return ::isatty(2) == 1; }

}  // namespace meshless::cli
