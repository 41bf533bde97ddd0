// The PLY header: parser, formatter, type names (formats/ply.hpp).
#include <charconv>
#include <cstdio>

#include "formats/ply.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr int kCountWidth = 20;  // digits of the largest uint64

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<std::string_view> words(std::string_view s) {
    std::vector<std::string_view> w;
    std::size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && is_space(s[i])) ++i;
        const std::size_t b = i;
        while (i < s.size() && !is_space(s[i])) ++i;
        if (i > b) w.push_back(s.substr(b, i - b));
    }
    return w;
}

std::string_view trim_ws(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

bool is_integer_type(StoredType t) { return t != StoredType::f32 && t != StoredType::f64; }

}  // namespace

bool PlyElement::has_lists() const {
    for (const auto& p : props)
        if (p.is_list) return true;
    return false;
}

std::size_t PlyElement::min_record_bytes() const {
    std::size_t n = 0;
    for (const auto& p : props) n += stored_size(p.is_list ? p.count_type : p.type);
    return n;
}

int PlyElement::find(std::string_view n) const {
    for (std::size_t p = 0; p < props.size(); ++p)
        if (props[p].name == n) return static_cast<int>(p);
    return -1;
}

int PlyHeader::find(std::string_view n) const {
    for (std::size_t e = 0; e < elements.size(); ++e)
        if (elements[e].name == n) return static_cast<int>(e);
    return -1;
}

const char* ply_type_name(StoredType t) {
    switch (t) {
        case StoredType::i8: return "char";
        case StoredType::u8: return "uchar";
        case StoredType::i16: return "short";
        case StoredType::u16: return "ushort";
        case StoredType::i32: return "int";
        case StoredType::u32: return "uint";
        case StoredType::f32: return "float";
        case StoredType::f64: return "double";
        default: return nullptr;
    }
}

std::optional<StoredType> ply_type(std::string_view t) {
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

std::string ply_escape(std::string_view b, std::size_t max) {
    std::string out;
    const std::size_t n = std::min(b.size(), max);
    for (std::size_t i = 0; i < n; ++i) {
        const auto c = static_cast<unsigned char>(b[i]);
        if (c >= 0x20 && c < 0x7f && c != '\\') {
            out += static_cast<char>(c);
        } else {
            char x[8];
            std::snprintf(x, sizeof x, "\\x%02x", c);
            out += x;
        }
    }
    if (b.size() > max) out += "...";
    return out;
}

PlyHeader parse_ply_header(std::string_view bytes, const std::string& name) {
    PlyHeader h;
    std::size_t pos = 0, line_no = 0;
    bool ended = false, have_format = false;
    auto fail = [&](const std::string& what) -> FormatError {
        return FormatError(name + ": line " + std::to_string(line_no) + ": " + what);
    };
    while (pos < bytes.size()) {
        std::size_t nl = bytes.find('\n', pos);
        const bool last = nl == std::string_view::npos;
        if (last) nl = bytes.size();
        std::string_view line = bytes.substr(pos, nl - pos);
        pos = last ? nl : nl + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (line_no == 1) {
            if (line != "ply")
                throw FormatError(name + ": not a PLY file (missing 'ply' magic; starts with '" +
                                  ply_escape(bytes.substr(0, 16)) + "')");
            continue;
        }
        if (last && line != "end_header") break;  // a cut line: truncated header
        const auto w = words(line);
        if (w.empty()) continue;
        const std::string_view kw = w[0];
        if (kw == "end_header") {
            if (w.size() != 1) throw fail("malformed PLY header line '" + ply_escape(line) + "'");
            ended = true;
            break;
        }
        if (kw == "comment" || kw == "obj_info") {
            const std::string_view rest = trim_ws(line.substr(kw.size()));
            if (!rest.empty()) (kw == "comment" ? h.comments : h.obj_info).emplace_back(rest);
        } else if (kw == "format") {
            if (have_format) throw fail("second PLY format line");
            if (w.size() != 3) throw fail("malformed PLY format line '" + ply_escape(line) + "'");
            if (w[1] == "ascii") h.encoding = PlyEncoding::ascii;
            else if (w[1] == "binary_little_endian") h.encoding = PlyEncoding::binary_little_endian;
            else if (w[1] == "binary_big_endian") h.encoding = PlyEncoding::binary_big_endian;
            else throw fail("unknown PLY format '" + ply_escape(w[1]) + "'");
            if (w[2] != "1.0") throw fail("unsupported PLY version '" + ply_escape(w[2]) + "' (expected 1.0)");
            have_format = true;
        } else if (kw == "element") {
            if (w.size() != 3) throw fail("malformed PLY element line '" + ply_escape(line) + "'");
            PlyElement e;
            e.name = std::string(w[1]);
            e.line = line_no;
            const std::string_view c = w[2];
            const auto r = std::from_chars(c.data(), c.data() + c.size(), e.count);
            if (r.ec != std::errc() || r.ptr != c.data() + c.size())
                throw fail("bad PLY element count '" + ply_escape(c) + "' (expected 0 .. 18446744073709551615)");
            if (h.find(e.name) >= 0) throw fail("second PLY element named '" + ply_escape(e.name) + "'");
            h.elements.push_back(std::move(e));
        } else if (kw == "property") {
            if (h.elements.empty()) throw fail("PLY property before any element: '" + ply_escape(line) + "'");
            PlyProperty p;
            if (w.size() == 5 && w[1] == "list") {
                const auto ct = ply_type(w[2]), it = ply_type(w[3]);
                if (!ct || !it) throw fail("unknown PLY property type in '" + ply_escape(line) + "'");
                if (!is_integer_type(*ct)) throw fail("PLY list length type must be an integer type: '" + ply_escape(line) + "'");
                p.is_list = true, p.count_type = *ct, p.type = *it, p.name = std::string(w[4]);
            } else if (w.size() == 3) {
                const auto t = ply_type(w[1]);
                if (!t) throw fail("unknown PLY property type '" + ply_escape(w[1]) + "'");
                p.type = *t, p.name = std::string(w[2]);
            } else {
                throw fail("malformed PLY property line '" + ply_escape(line) + "'");
            }
            PlyElement& e = h.elements.back();
            if (e.find(p.name) >= 0)
                throw fail("second property '" + ply_escape(p.name) + "' in PLY element '" + ply_escape(e.name) + "'");
            e.props.push_back(std::move(p));
        } else {
            throw fail("malformed PLY header line '" + ply_escape(line) + "'");
        }
    }
    if (line_no == 0) throw FormatError(name + ": not a PLY file (empty)");
    if (!ended) {
        if (bytes.size() >= kPlyMaxHeaderBytes)
            throw FormatError(name + ": no PLY end_header in the first " + std::to_string(kPlyMaxHeaderBytes) + " bytes");
        throw FormatError(name + ": truncated PLY header (no end_header)");
    }
    if (!have_format) throw FormatError(name + ": PLY header has no format line");
    for (const auto& e : h.elements)
        if (e.count > 0 && e.props.empty())
            throw FormatError(name + ": line " + std::to_string(e.line) + ": PLY element '" + ply_escape(e.name) + "' has " +
                              std::to_string(e.count) + " records but no properties");
    h.header_bytes = pos;
    h.header_lines = line_no;
    return h;
}

std::string ply_count_lines(const std::string& element, std::uint64_t n) {
    const std::string digits = std::to_string(n);
    return "element " + element + " " + digits + "\ncomment" + std::string(kCountWidth - digits.size(), ' ') + "\n";
}

std::string format_ply_header(const PlyHeader& h, bool pad_counts) {
    std::string s = "ply\nformat ";
    s += h.encoding == PlyEncoding::ascii                  ? "ascii"
         : h.encoding == PlyEncoding::binary_little_endian ? "binary_little_endian"
                                                           : "binary_big_endian";
    s += " 1.0\n";
    // (a line break inside a comment, a file name's, would end the line: escaped)
    for (const auto& c : h.comments) s += "comment " + line_breaks_escaped(c) + "\n";
    for (const auto& c : h.obj_info) s += "obj_info " + line_breaks_escaped(c) + "\n";
    for (const auto& e : h.elements) {
        s += pad_counts ? ply_count_lines(e.name, e.count) : "element " + e.name + " " + std::to_string(e.count) + "\n";
        for (const auto& p : e.props) {
            if (p.is_list)
                s += std::string("property list ") + ply_type_name(p.count_type) + " " + ply_type_name(p.type) + " " + p.name + "\n";
            else
                s += std::string("property ") + ply_type_name(p.type) + " " + p.name + "\n";
        }
    }
    s += "end_header\n";
    return s;
}

}  // namespace meshless
