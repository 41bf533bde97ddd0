#include "formats/point_set_writer.hpp"

#include <cstdio>
#include <cstring>
#include <filesystem>

#include "formats/atomic_file.hpp"
#include "formats/ply.hpp"
#include "formats/stored_type.hpp"
#include "formats/text_header.hpp"
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

void write_point_set(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments) {
    const std::string e = to_lower(std::filesystem::path(path).extension().string());
    if (e == ".ply") return write_point_set_ply(path, ps, comments);
    if (e == ".csv" || e == ".txt" || e == ".tsv" || path == "-") return write_point_set_csv(path, ps);
    throw InvalidArgument(path + ": unknown point-set output type (use .ply or .csv)");
}

}  // namespace meshless
