#include "formats/points_ply.hpp"

#include <algorithm>
#include <cstring>

#include "formats/binary_file.hpp"
#include "formats/stored_type.hpp"
#include "formats/text_header.hpp"

namespace meshless {

namespace {

std::optional<StoredType> ply_type(const std::string& t) {
    if (t == "char" || t == "int8") return StoredType::i8;
    if (t == "uchar" || t == "uint8") return StoredType::u8;
    if (t == "short" || t == "int16") return StoredType::i16;
    if (t == "ushort" || t == "uint16") return StoredType::u16;
    if (t == "int" || t == "int32") return StoredType::i32;
    if (t == "uint" || t == "uint32") return StoredType::u32;
    if (t == "float" || t == "float32") return StoredType::f32;
    if (t == "double" || t == "float64") return StoredType::f64;
    return std::nullopt;
}

double load(const std::byte* p, StoredType t, bool swap) {
    unsigned char b[8];
    const std::size_t n = stored_size(t);
    std::memcpy(b, p, n);
    if (swap) std::reverse(b, b + n);
    switch (t) {
        case StoredType::i8: return static_cast<signed char>(b[0]);
        case StoredType::u8: return b[0];
        case StoredType::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
        case StoredType::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
        case StoredType::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
        case StoredType::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
        case StoredType::f32: { float v; std::memcpy(&v, b, 4); return v; }
        default: { double v; std::memcpy(&v, b, 8); return v; }
    }
}

struct Prop {
    std::string name;
    StoredType type = StoredType::f32;
    bool list = false;
    StoredType count_type = StoredType::u8;
};
struct Element {
    std::string name;
    std::uint64_t count = 0;
    std::vector<Prop> props;
};

}  // namespace

PointSet read_points_ply(const std::string& path, const PointSetOptions& o, std::vector<std::string>* notes) {
    const auto bytes = read_file_bytes(path);
    if (bytes.empty()) throw FormatError(path + ": empty file");
    const std::string_view doc(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    std::size_t pos = 0;
    auto next_line = [&](std::string& line) -> bool {
        if (pos >= doc.size()) return false;
        std::size_t e = doc.find('\n', pos);
        if (e == std::string_view::npos) e = doc.size();
        line = std::string(doc.substr(pos, e - pos));
        if (!line.empty() && line.back() == '\r') line.pop_back();
        pos = e + 1;
        return true;
    };
    std::string line;
    if (!next_line(line) || line != "ply") throw FormatError(path + ": not a PLY file (missing 'ply' magic)");
    enum class Enc { none, ascii, le, be } enc = Enc::none;
    std::vector<Element> elements;
    for (;;) {
        if (!next_line(line)) throw FormatError(path + ": truncated PLY header (no end_header)");
        const auto t = split_ws(line);
        if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
        if (t[0] == "end_header") break;
        if (t[0] == "format") {
            if (t.size() != 3) throw FormatError(path + ": malformed PLY format line '" + line + "'");
            if (t[1] == "ascii") enc = Enc::ascii;
            else if (t[1] == "binary_little_endian") enc = Enc::le;
            else if (t[1] == "binary_big_endian") enc = Enc::be;
            else throw FormatError(path + ": unknown PLY format '" + t[1] + "'");
        } else if (t[0] == "element") {
            if (t.size() != 3) throw FormatError(path + ": malformed PLY element line '" + line + "'");
            Element e;
            e.name = t[1];
            const auto n = parse_int(t[2], path, "PLY element count");
            if (n < 0) throw FormatError(path + ": negative PLY element count '" + line + "'");
            e.count = static_cast<std::uint64_t>(n);
            elements.push_back(std::move(e));
        } else if (t[0] == "property") {
            if (elements.empty()) throw FormatError(path + ": PLY property before any element: '" + line + "'");
            Prop p;
            if (t.size() == 5 && t[1] == "list") {
                const auto ct = ply_type(t[2]);
                const auto it = ply_type(t[3]);
                if (!ct || !it) throw FormatError(path + ": unknown PLY property type in '" + line + "'");
                p.list = true, p.count_type = *ct, p.type = *it, p.name = t[4];
            } else if (t.size() == 3) {
                const auto ty = ply_type(t[1]);
                if (!ty) throw FormatError(path + ": unknown PLY property type '" + t[1] + "'");
                p.type = *ty, p.name = t[2];
            } else {
                throw FormatError(path + ": malformed PLY property line '" + line + "'");
            }
            elements.back().props.push_back(std::move(p));
        } else {
            throw FormatError(path + ": malformed PLY header line '" + line + "'");
        }
    }
    if (enc == Enc::none) throw FormatError(path + ": PLY header has no format line");
    std::size_t vi = elements.size();
    for (std::size_t i = 0; i < elements.size(); ++i)
        if (elements[i].name == "vertex") {
            vi = i;
            break;
        }
    if (vi == elements.size()) throw FormatError(path + ": PLY file has no vertex element");
    const Element& V = elements[vi];
    int ix[3] = {-1, -1, -1}, iv = -1;
    for (std::size_t p = 0; p < V.props.size(); ++p) {
        if (V.props[p].list) throw FormatError(path + ": list property '" + V.props[p].name + "' on PLY vertices is not supported");
        for (int a = 0; a < 3; ++a)
            if (V.props[p].name == std::string(1, static_cast<char>('x' + a))) ix[a] = static_cast<int>(p);
    }
    if (ix[0] < 0 || ix[1] < 0 || ix[2] < 0) throw FormatError(path + ": PLY vertices have no x y z properties");
    auto names = [&] {
        std::string s;
        for (const auto& p : V.props) s += (s.empty() ? "" : ", ") + p.name;
        return s;
    };
    if (!o.value_name.empty()) {
        for (std::size_t p = 0; p < V.props.size(); ++p)
            if (V.props[p].name == o.value_name) iv = static_cast<int>(p);
        if (iv < 0) throw FormatError(path + ": no vertex property '" + o.value_name + "' (properties: " + names() + ")");
    } else {
        for (std::size_t p = 0; p < V.props.size() && iv < 0; ++p)
            if (V.props[p].name == "value" || V.props[p].name == "scalar") iv = static_cast<int>(p);
        static const char* skip[] = {"x", "y", "z", "nx", "ny", "nz", "radius"};
        for (std::size_t p = 0; p < V.props.size() && iv < 0; ++p) {
            const auto& pr = V.props[p];
            if ((pr.type == StoredType::f32 || pr.type == StoredType::f64) &&
                std::none_of(std::begin(skip), std::end(skip), [&](const char* s) { return pr.name == s; }))
                iv = static_cast<int>(p);
        }
    }
    PointSetBuilder b(path, o);
    const std::uint64_t nvert = V.count;
    std::vector<double> vals(V.props.size());
    if (enc == Enc::ascii) {
        // element instances are one per line in ASCII PLY
        std::uint64_t line_no = static_cast<std::uint64_t>(std::count(doc.begin(), doc.begin() + std::min(pos, doc.size()), '\n'));
        std::vector<std::string> tok;
        auto next_data_line = [&](std::string& l) {
            for (;;) {
                if (!next_line(l)) return false;
                ++line_no;
                if (!trim(l).empty()) return true;
            }
        };
        for (std::size_t e = 0; e < vi; ++e)
            for (std::uint64_t i = 0; i < elements[e].count; ++i)
                if (!next_data_line(line)) throw FormatError(path + ": truncated PLY body in element '" + elements[e].name + "'");
        b.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(nvert, doc.size() / 2)));
        for (std::uint64_t v = 0; v < nvert; ++v) {
            if (!next_data_line(line))
                throw FormatError(path + ": truncated PLY body at vertex " + std::to_string(v) + " of " + std::to_string(nvert));
            tok = split_ws(line);
            if (tok.size() != V.props.size())
                throw FormatError(path + ": line " + std::to_string(line_no) + ": " + std::to_string(tok.size()) +
                                  " vertex fields, expected " + std::to_string(V.props.size()));
            for (std::size_t p = 0; p < tok.size(); ++p) vals[p] = parse_double(tok[p], path, "PLY vertex value");
            b.add(vals[ix[0]], vals[ix[1]], vals[ix[2]], iv >= 0 ? vals[iv] : 0.0, "line", line_no);
        }
    } else {
        const bool swap = (enc == Enc::be) == host_is_little_endian();
        const std::byte* base = bytes.data();
        std::size_t off = pos;
        auto need = [&](std::size_t n, const std::string& what) {
            if (n > bytes.size() - std::min(off, bytes.size()))
                throw FormatError(path + ": truncated PLY body in " + what);
        };
        for (std::size_t e = 0; e < vi; ++e) {
            const Element& E = elements[e];
            for (std::uint64_t i = 0; i < E.count; ++i)
                for (const auto& p : E.props) {
                    if (p.list) {
                        need(stored_size(p.count_type), "element '" + E.name + "'");
                        const double c = load(base + off, p.count_type, swap);
                        off += stored_size(p.count_type);
                        if (c < 0) throw FormatError(path + ": negative list count in element '" + E.name + "'");
                        const std::size_t n = static_cast<std::size_t>(c) * stored_size(p.type);
                        need(n, "element '" + E.name + "'");
                        off += n;
                    } else {
                        need(stored_size(p.type), "element '" + E.name + "'");
                        off += stored_size(p.type);
                    }
                }
        }
        std::size_t stride = 0;
        std::vector<std::size_t> at(V.props.size());
        for (std::size_t p = 0; p < V.props.size(); ++p) at[p] = stride, stride += stored_size(V.props[p].type);
        const std::uint64_t remaining = bytes.size() - std::min(off, bytes.size());
        if (stride && nvert > remaining / stride)
            throw FormatError(path + ": truncated PLY body: " + std::to_string(nvert) + " vertices of " + std::to_string(stride) +
                              " bytes need more than the " + std::to_string(remaining) + " bytes left");
        b.reserve(static_cast<std::size_t>(nvert));
        for (std::uint64_t v = 0; v < nvert; ++v) {
            const std::byte* r = base + off + v * stride;
            const double x = load(r + at[ix[0]], V.props[ix[0]].type, swap);
            const double y = load(r + at[ix[1]], V.props[ix[1]].type, swap);
            const double z = load(r + at[ix[2]], V.props[ix[2]].type, swap);
            const double s = iv >= 0 ? load(r + at[iv], V.props[iv].type, swap) : 0.0;
            b.add(x, y, z, s, "vertex", v);
        }
    }
    if (notes && iv >= 0 && o.value_name.empty()) notes->push_back("scalar: vertex property '" + V.props[iv].name + "'");
    return b.finish(iv >= 0 ? V.props[iv].name : "", iv >= 0);
}

}  // namespace meshless
