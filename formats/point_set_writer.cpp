#include "formats/point_set_writer.hpp"

#include <cstdio>
#include <algorithm>
#include <cstring>
#include <filesystem>

#include "formats/atomic_file.hpp"
#include "formats/ply.hpp"
#include "formats/stored_type.hpp"
#include "formats/text_header.hpp"
#include "formats/vtp_writer.hpp"
#include "kernels/errors.hpp"

namespace meshless {

void write_point_set_ply(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments) {
    PlyHeader h;
    h.encoding = PlyEncoding::binary_little_endian;
    h.comments = comments;
    if (ps.has_values && !ps.value_name.empty()) h.comments.push_back("value_name " + ps.value_name);
    PlyElement v{"vertex", ps.size(), {}, 0};
    for (const char* n : {"x", "y", "z"}) v.props.push_back({n, StoredType::f64, false, StoredType::u8});
    if (ps.has_values) v.props.push_back({"value", StoredType::f64, false, StoredType::u8});
    h.elements.push_back(std::move(v));
    PlyWriter f(path, std::move(h), PlyCounts::declared);
    const std::size_t per = ps.has_values ? 4 : 3;
    std::vector<double> buf;
    buf.reserve(per * 4096);
    for (std::size_t i = 0; i < ps.size(); ++i) {
        buf.push_back(ps.pos[i].x);
        buf.push_back(ps.pos[i].y);
        buf.push_back(ps.pos[i].z);
        if (ps.has_values) buf.push_back(ps.value[i]);
        if (buf.size() >= per * 4096) {
            f.append(buf.data(), buf.size() * sizeof(double));
            buf.clear();
        }
    }
    f.append(buf.data(), buf.size() * sizeof(double));
    f.commit();
}

void write_point_set_csv(const std::string& path, const PointSet& ps) {
    AtomicFile f(path);
    std::string out = ps.has_values ? "x,y,z,value\n" : "x,y,z\n";
    char line[128];
    for (std::size_t i = 0; i < ps.size(); ++i) {
        const int n = ps.has_values
                          ? std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g\n", ps.pos[i].x, ps.pos[i].y, ps.pos[i].z, ps.value[i])
                          : std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g\n", ps.pos[i].x, ps.pos[i].y, ps.pos[i].z);
        out.append(line, static_cast<std::size_t>(n));
        if (out.size() > (1u << 20)) {
            f.write(out);
            out.clear();
        }
    }
    f.write(out);
    f.commit();
}

namespace {
void write_point_set_vtp(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments) {
    VtpOptions vo;
    vo.oriented = false;  // samples, not splats: no normal, no radius
    VtpPointWriter w(path, comments, vo);
    std::vector<PointRecord> recs;
    recs.reserve(std::min<std::size_t>(ps.size(), 65536));
    for (std::size_t i = 0; i < ps.size(); ++i) {
        PointRecord q{};
        q.pos[0] = static_cast<float>(ps.pos[i].x);
        q.pos[1] = static_cast<float>(ps.pos[i].y);
        q.pos[2] = static_cast<float>(ps.pos[i].z);
        q.value = ps.has_values ? static_cast<float>(ps.value[i]) : 0.0f;
        recs.push_back(q);
        if (recs.size() == 65536) {
            w.append(recs);
            recs.clear();
        }
    }
    w.append(recs);
    w.commit();
}
}  // namespace

bool point_set_output_name(const std::string& path) {
    const std::string e = to_lower(std::filesystem::path(path).extension().string());
    return path == "-" || e == ".ply" || e == ".csv" || e == ".vtp";
}

void write_point_set(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments) {
    const std::string e = to_lower(std::filesystem::path(path).extension().string());
    if (path == "-" || e == ".csv") return write_point_set_csv(path, ps);
    if (e == ".ply") return write_point_set_ply(path, ps, comments);
    if (e == ".vtp") return write_point_set_vtp(path, ps, comments);
    throw InvalidArgument("-o '" + path + "': this output is a point set with values, written to a .ply (binary PLY), .csv or .vtp "
                          "(VTK XML PolyData) file (outputs are chosen by extension; '-' for CSV on stdout)");
}

}  // namespace meshless
