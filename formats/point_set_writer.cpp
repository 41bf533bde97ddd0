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

PointSetFormat point_set_output_format(const std::string& path) {
    const std::string e = to_lower(std::filesystem::path(path).extension().string());
    if (path == "-" || e == ".csv") return PointSetFormat::csv;
    if (e == ".ply") return PointSetFormat::ply;
    if (e == ".vtp") return PointSetFormat::vtp;
    throw InvalidArgument("-o '" + path + "': this output is a point set with values, written to a .ply (binary PLY), .csv or .vtp "
                          "(VTK XML PolyData) file (outputs are chosen by extension; '-' for CSV on stdout)");
}

namespace {

PlyHeader point_set_ply_header(std::uint64_t count, bool has_values, const std::string& value_name,
                               const std::vector<std::string>& comments) {
    PlyHeader h;
    h.encoding = PlyEncoding::binary_little_endian;
    h.comments = comments;
    if (has_values && !value_name.empty()) h.comments.push_back("value_name " + value_name);
    PlyElement v{"vertex", count, {}, 0};
    for (const char* n : {"x", "y", "z"}) v.props.push_back({n, StoredType::f64, false, StoredType::u8});
    if (has_values) v.props.push_back({"value", StoredType::f64, false, StoredType::u8});
    h.elements.push_back(std::move(v));
    return h;
}

}  // namespace

struct PointSetWriter::Impl {
    PointSetFormat format;
    bool has_values;
    std::uint64_t declared = 0, written = 0;
    std::unique_ptr<PlyWriter> ply;
    std::unique_ptr<AtomicFile> csv;
    std::unique_ptr<VtpPointWriter> vtp;
    std::vector<double> buf;
    std::string text;
    std::vector<PointRecord> recs;
};

PointSetWriter::PointSetWriter(const std::string& path, std::uint64_t count, bool has_values, const std::string& value_name,
                               const std::vector<std::string>& comments)
    : PointSetWriter(point_set_output_format(path), path, count, has_values, value_name, comments) {}

PointSetWriter::PointSetWriter(PointSetFormat format, const std::string& path, std::uint64_t count, bool has_values,
                               const std::string& value_name, const std::vector<std::string>& comments)
    : d_(std::make_unique<Impl>()) {
    d_->format = format;
    d_->has_values = has_values;
    d_->declared = count;
    switch (d_->format) {
    case PointSetFormat::ply:
        d_->ply = std::make_unique<PlyWriter>(path, point_set_ply_header(count, has_values, value_name, comments), PlyCounts::declared);
        break;
    case PointSetFormat::csv:
        d_->csv = std::make_unique<AtomicFile>(path);
        d_->csv->write(has_values ? "x,y,z,value\n" : "x,y,z\n");
        break;
    case PointSetFormat::vtp: {
        VtpOptions vo;
        vo.oriented = false;  // samples, not splats: no normal, no radius
        d_->vtp = std::make_unique<VtpPointWriter>(path, comments, vo);
        break;
    }
    }
}

PointSetWriter::~PointSetWriter() = default;

void PointSetWriter::append(std::span<const Vec3> pos, std::span<const double> value) {
    Impl& d = *d_;
    d.written += pos.size();
    const bool v = d.has_values;
    for (std::size_t at = 0; at < pos.size(); at += 4096) {  // (in pieces: the buffers stay small)
        const std::size_t end = std::min(pos.size(), at + 4096);
        switch (d.format) {
        case PointSetFormat::ply:
            d.buf.clear();
            for (std::size_t i = at; i < end; ++i) {
                d.buf.insert(d.buf.end(), {pos[i].x, pos[i].y, pos[i].z});
                if (v) d.buf.push_back(value[i]);
            }
            d.ply->append(d.buf.data(), d.buf.size() * sizeof(double));
            break;
        case PointSetFormat::csv: {
            char line[128];
            d.text.clear();
            for (std::size_t i = at; i < end; ++i) {
                const int n = v ? std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g\n", pos[i].x, pos[i].y, pos[i].z, value[i])
                                : std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g\n", pos[i].x, pos[i].y, pos[i].z);
                d.text.append(line, static_cast<std::size_t>(n));
            }
            d.csv->write(d.text);
            break;
        }
        case PointSetFormat::vtp:
            d.recs.clear();
            for (std::size_t i = at; i < end; ++i) {
                PointRecord q{};
                q.pos[0] = static_cast<float>(pos[i].x);
                q.pos[1] = static_cast<float>(pos[i].y);
                q.pos[2] = static_cast<float>(pos[i].z);
                q.value = v ? static_cast<float>(value[i]) : 0.0f;
                d.recs.push_back(q);
            }
            d.vtp->append(d.recs);
            break;
        }
    }
}

void PointSetWriter::commit() {
    Impl& d = *d_;
    if (d.ply) {
        if (d.written != d.declared)
            throw std::logic_error("PointSetWriter: " + std::to_string(d.written) + " points appended, " + std::to_string(d.declared) +
                                   " declared");
        d.ply->commit();
    }
    if (d.csv) d.csv->commit();
    if (d.vtp) d.vtp->commit();
}

namespace {
void write_whole(PointSetFormat format, const std::string& path, const PointSet& ps, const std::vector<std::string>& comments) {
    PointSetWriter w(format, path, ps.size(), ps.has_values, ps.value_name, comments);
    w.append(ps.pos, ps.has_values ? std::span<const double>(ps.value) : std::span<const double>());
    w.commit();
}
}  // namespace

void write_point_set_ply(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments) {
    write_whole(PointSetFormat::ply, path, ps, comments);
}

void write_point_set_csv(const std::string& path, const PointSet& ps) { write_whole(PointSetFormat::csv, path, ps, {}); }

bool point_set_output_name(const std::string& path) {
    const std::string e = to_lower(std::filesystem::path(path).extension().string());
    return path == "-" || e == ".ply" || e == ".csv" || e == ".vtp";
}

void write_point_set(const std::string& path, const PointSet& ps, const std::vector<std::string>& comments) {
    write_whole(point_set_output_format(path), path, ps, comments);
}

}  // namespace meshless
