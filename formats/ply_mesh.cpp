#include "formats/ply_mesh.hpp"

#include <bit>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "formats/atomic_file.hpp"
#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"

namespace meshless {
namespace {

template <class T>
void put_le(std::vector<unsigned char>& buf, T v) {
    unsigned char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if constexpr (std::endian::native == std::endian::big)
        for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
    buf.insert(buf.end(), b, b + sizeof(T));
}

enum class PlyType { i8, u8, i16, u16, i32, u32, f32, f64 };

std::size_t type_size(PlyType t) {
    switch (t) {
        case PlyType::i8:
        case PlyType::u8: return 1;
        case PlyType::i16:
        case PlyType::u16: return 2;
        case PlyType::i32:
        case PlyType::u32:
        case PlyType::f32: return 4;
        case PlyType::f64: return 8;
    }
    return 0;
}

bool parse_type(const std::string& s, PlyType& t) {
    if (s == "char" || s == "int8") t = PlyType::i8;
    else if (s == "uchar" || s == "uint8") t = PlyType::u8;
    else if (s == "short" || s == "int16") t = PlyType::i16;
    else if (s == "ushort" || s == "uint16") t = PlyType::u16;
    else if (s == "int" || s == "int32") t = PlyType::i32;
    else if (s == "uint" || s == "uint32") t = PlyType::u32;
    else if (s == "float" || s == "float32") t = PlyType::f32;
    else if (s == "double" || s == "float64") t = PlyType::f64;
    else return false;
    return true;
}

struct Property {
    std::string name;
    PlyType type = PlyType::f32;
    bool is_list = false;
    PlyType count_type = PlyType::u8;
};

struct Element {
    std::string name;
    std::int64_t count = 0;
    std::vector<Property> props;
};

/// Reads values from the body, binary little endian or ASCII tokens.
class BodyReader {
public:
    BodyReader(const std::string& path, const std::byte* p, std::size_t n, bool ascii)
        : path_(path), p_(p), n_(n), ascii_(ascii) {}

    double read(PlyType t, const char* what) {
        if (ascii_) return read_ascii(t, what);
        const std::size_t s = type_size(t);
        if (n_ - pos_ < s)
            throw FormatError(path_ + ": truncated: body ends inside " + what + " at byte " +
                              std::to_string(pos_));
        unsigned char b[8];
        std::memcpy(b, p_ + pos_, s);
        if constexpr (std::endian::native == std::endian::big)
            for (std::size_t i = 0; i < s / 2; ++i) std::swap(b[i], b[s - 1 - i]);
        pos_ += s;
        switch (t) {
            case PlyType::i8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
            case PlyType::u8: { std::uint8_t v; std::memcpy(&v, b, 1); return v; }
            case PlyType::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
            case PlyType::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
            case PlyType::f32: { float v; std::memcpy(&v, b, 4); return v; }
            case PlyType::f64: { double v; std::memcpy(&v, b, 8); return v; }
        }
        return 0;
    }

private:
    double read_ascii(PlyType t, const char* what) {
        const char* c = reinterpret_cast<const char*>(p_);
        while (pos_ < n_ && std::isspace(static_cast<unsigned char>(c[pos_]))) ++pos_;
        if (pos_ >= n_)
            throw FormatError(path_ + ": truncated: ASCII body ends before " + what);
        const std::size_t start = pos_;
        while (pos_ < n_ && !std::isspace(static_cast<unsigned char>(c[pos_]))) ++pos_;
        const std::string tok(c + start, pos_ - start);
        char* end = nullptr;
        const double v = std::strtod(tok.c_str(), &end);
        if (end != tok.c_str() + tok.size() || tok.empty())
            throw FormatError(path_ + ": bad number '" + tok + "' in " + what);
        if (t != PlyType::f32 && t != PlyType::f64 && v != std::floor(v))
            throw FormatError(path_ + ": non-integer '" + tok + "' for an integer property in " + what);
        return v;
    }

    const std::string& path_;
    const std::byte* p_;
    std::size_t n_;
    std::size_t pos_ = 0;
    bool ascii_;
};

}  // namespace

void write_ply_mesh(const Mesh& mesh, const std::string& path) {
    if (mesh.xyz.size() % 3 != 0 || mesh.tri.size() % 3 != 0)
        throw std::invalid_argument(path + ": mesh arrays are not multiples of 3");
    const bool normals = !mesh.normals.empty();
    if (normals && mesh.normals.size() != mesh.xyz.size())
        throw std::invalid_argument(path + ": mesh has " + std::to_string(mesh.normals.size()) +
                                    " normal floats for " + std::to_string(mesh.xyz.size()) + " position floats");
    const std::size_t nv = mesh.vertex_count(), nf = mesh.triangle_count();
    if (nv > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
        throw std::length_error(path + ": more than 2^31-1 vertices do not fit PLY int indices");
    for (std::uint32_t i : mesh.tri)
        if (i >= nv)
            throw std::invalid_argument(path + ": triangle index " + std::to_string(i) +
                                        " out of range (" + std::to_string(nv) + " vertices)");

    std::string header = "ply\nformat binary_little_endian 1.0\ncomment meshless marching cubes\n";
    header += "element vertex " + std::to_string(nv) + "\n";
    header += "property float x\nproperty float y\nproperty float z\n";
    if (normals) header += "property float nx\nproperty float ny\nproperty float nz\n";
    header += "element face " + std::to_string(nf) + "\n";
    header += "property list uchar int vertex_indices\nend_header\n";

    AtomicFile out(path);
    out.write(header);
    std::vector<unsigned char> buf;
    constexpr std::size_t kChunk = 1 << 16;
    buf.reserve(kChunk * 24 + 64);
    for (std::size_t v = 0; v < nv; ++v) {
        for (int d = 0; d < 3; ++d) put_le(buf, mesh.xyz[3 * v + d]);
        if (normals)
            for (int d = 0; d < 3; ++d) put_le(buf, mesh.normals[3 * v + d]);
        if (buf.size() >= kChunk * 24) {
            out.write(buf.data(), buf.size());
            buf.clear();
        }
    }
    for (std::size_t f = 0; f < nf; ++f) {
        buf.push_back(3);
        for (int d = 0; d < 3; ++d) put_le(buf, static_cast<std::int32_t>(mesh.tri[3 * f + d]));
        if (buf.size() >= kChunk * 24) {
            out.write(buf.data(), buf.size());
            buf.clear();
        }
    }
    out.write(buf.data(), buf.size());
    out.commit();
}

Mesh read_ply_mesh(const std::string& path) {
    const std::vector<std::byte> bytes = read_file_bytes(path);
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    if (text.substr(0, 4) != "ply\n" && text.substr(0, 5) != "ply\r\n")
        throw FormatError(path + ": not a PLY file (missing 'ply' magic line)");
    std::size_t end = std::string_view::npos;
    std::size_t body = 0;
    for (std::size_t pos = 0; pos < text.size();) {
        std::size_t nl = text.find('\n', pos);
        if (nl == std::string_view::npos) break;
        std::string_view line = text.substr(pos, nl - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line == "end_header") {
            end = pos;
            body = nl + 1;
            break;
        }
        pos = nl + 1;
    }
    if (end == std::string_view::npos) throw FormatError(path + ": PLY header has no end_header line");

    bool ascii = false, have_format = false;
    std::vector<Element> elements;
    const std::vector<std::string> lines = split_lines(text.substr(0, end));
    for (std::size_t li = 1; li < lines.size(); ++li) {
        const std::vector<std::string> w = split_ws(lines[li]);
        if (w.empty() || w[0] == "comment" || w[0] == "obj_info") continue;
        if (w[0] == "format") {
            if (w.size() != 3 || w[2] != "1.0")
                throw FormatError(path + ": bad PLY format line '" + lines[li] + "'");
            if (w[1] == "ascii") ascii = true;
            else if (w[1] == "binary_little_endian") ascii = false;
            else
                throw FormatError(path + ": PLY format '" + w[1] +
                                  "' not supported (expected ascii or binary_little_endian)");
            have_format = true;
        } else if (w[0] == "element") {
            if (w.size() != 3) throw FormatError(path + ": bad PLY element line '" + lines[li] + "'");
            Element e;
            e.name = w[1];
            e.count = parse_int(w[2], path, "element count");
            if (e.count < 0) throw FormatError(path + ": negative count for element " + e.name);
            elements.push_back(e);
        } else if (w[0] == "property") {
            if (elements.empty()) throw FormatError(path + ": PLY property before any element");
            Property p;
            if (w.size() == 5 && w[1] == "list") {
                p.is_list = true;
                if (!parse_type(w[2], p.count_type) || !parse_type(w[3], p.type))
                    throw FormatError(path + ": bad PLY list property '" + lines[li] + "'");
                p.name = w[4];
            } else if (w.size() == 3) {
                if (!parse_type(w[1], p.type))
                    throw FormatError(path + ": unknown PLY property type '" + w[1] + "'");
                p.name = w[2];
            } else {
                throw FormatError(path + ": bad PLY property line '" + lines[li] + "'");
            }
            elements.back().props.push_back(p);
        } else {
            throw FormatError(path + ": unknown PLY header keyword '" + w[0] + "'");
        }
    }
    if (!have_format) throw FormatError(path + ": PLY header has no format line");

    Mesh mesh;
    BodyReader rd(path, bytes.data() + body, bytes.size() - body, ascii);
    bool have_vertices = false;
    std::int64_t nv = 0;
    for (const Element& e : elements) {
        if (e.props.empty()) continue;
        const bool is_vertex = e.name == "vertex";
        const bool is_face = e.name == "face";
        int slot[6] = {-1, -1, -1, -1, -1, -1};
        int list_prop = -1;
        if (is_vertex) {
            const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
            for (std::size_t p = 0; p < e.props.size(); ++p)
                for (int s = 0; s < 6; ++s)
                    if (e.props[p].name == names[s] && !e.props[p].is_list) slot[s] = static_cast<int>(p);
            if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0)
                throw FormatError(path + ": PLY vertex element lacks x, y or z");
            const int nn = (slot[3] >= 0) + (slot[4] >= 0) + (slot[5] >= 0);
            if (nn != 0 && nn != 3) throw FormatError(path + ": PLY vertex has some but not all of nx ny nz");
            have_vertices = true;
            nv = e.count;
        } else if (is_face) {
            for (std::size_t p = 0; p < e.props.size(); ++p)
                if (e.props[p].is_list &&
                    (e.props[p].name == "vertex_indices" || e.props[p].name == "vertex_index"))
                    list_prop = static_cast<int>(p);
            if (list_prop < 0) throw FormatError(path + ": PLY face element lacks vertex_indices");
            if (!have_vertices) throw FormatError(path + ": PLY face element before the vertex element");
        }
        const std::string what = "element " + e.name;
        for (std::int64_t r = 0; r < e.count; ++r) {
            float vals[6] = {0, 0, 0, 0, 0, 0};
            for (std::size_t p = 0; p < e.props.size(); ++p) {
                const Property& pr = e.props[p];
                if (!pr.is_list) {
                    const double v = rd.read(pr.type, what.c_str());
                    if (is_vertex)
                        for (int s = 0; s < 6; ++s)
                            if (slot[s] == static_cast<int>(p)) vals[s] = static_cast<float>(v);
                    continue;
                }
                const double cnt = rd.read(pr.count_type, what.c_str());
                if (cnt < 0 || cnt > 1e6)
                    throw FormatError(path + ": bad list length " + std::to_string(cnt) + " in " + what);
                const auto c = static_cast<std::int64_t>(cnt);
                if (is_face && static_cast<int>(p) == list_prop) {
                    if (c < 3)
                        throw FormatError(path + ": face " + std::to_string(r) + " has fewer than 3 vertices");
                    std::uint32_t first = 0, prev = 0;
                    for (std::int64_t q = 0; q < c; ++q) {
                        const double iv = rd.read(pr.type, what.c_str());
                        if (!(iv >= 0 && iv < static_cast<double>(nv)) || iv != std::floor(iv))
                            throw FormatError(path + ": face " + std::to_string(r) + " vertex index " +
                                              std::to_string(iv) + " out of range (" +
                                              std::to_string(nv) + " vertices)");
                        const auto idx = static_cast<std::uint32_t>(iv);
                        if (q == 0) first = idx;
                        else if (q >= 2) {
                            mesh.tri.push_back(first);
                            mesh.tri.push_back(prev);
                            mesh.tri.push_back(idx);
                        }
                        prev = idx;
                    }
                } else {
                    for (std::int64_t q = 0; q < c; ++q) rd.read(pr.type, what.c_str());
                }
            }
            if (is_vertex) {
                mesh.xyz.insert(mesh.xyz.end(), vals, vals + 3);
                if (slot[3] >= 0) mesh.normals.insert(mesh.normals.end(), vals + 3, vals + 6);
            }
        }
    }
    if (!have_vertices) throw FormatError(path + ": PLY file has no vertex element");
    return mesh;
}

}  // namespace meshless
