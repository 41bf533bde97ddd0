#include "formats/npy_header.hpp"

#include <cstring>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr std::size_t kMaxHeader = std::size_t{1} << 20;  // NumPy's own readers refuse longer headers

// The value of 'key' in the dict literal `h` (a quoted string, a tuple or a bare word), as written.
std::string dict_value(const std::string& h, const char* key, const std::string& path) {
    std::size_t k = h.find(std::string("'") + key + "'");
    if (k == std::string::npos) k = h.find(std::string("\"") + key + "\"");
    if (k == std::string::npos) throw FormatError(path + ": malformed .npy header (no '" + key + "')");
    std::size_t c = h.find(':', k);
    if (c == std::string::npos) throw FormatError(path + ": malformed .npy header (no value for '" + key + "')");
    ++c;
    while (c < h.size() && (h[c] == ' ' || h[c] == '\t')) ++c;
    if (c >= h.size()) throw FormatError(path + ": malformed .npy header (no value for '" + key + "')");
    std::size_t e = std::string::npos;
    if (h[c] == '(' || h[c] == '[') {
        e = h.find(h[c] == '(' ? ')' : ']', c);
        if (e != std::string::npos) ++e;
    } else if (h[c] == '\'' || h[c] == '"') {
        e = h.find(h[c], c + 1);
        if (e != std::string::npos) ++e;
    } else {
        e = c;
        while (e < h.size() && h[e] != ',' && h[e] != '}') ++e;
    }
    if (e == std::string::npos) throw FormatError(path + ": malformed .npy header (unterminated value of '" + key + "')");
    return h.substr(c, e - c);
}

}  // namespace

std::string npy_shape_text(const std::vector<std::int64_t>& shape) {
    std::string s = "(";
    for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
    return s + (shape.size() == 1 ? ",)" : ")");
}

NpyHeader parse_npy_header(std::string_view bytes, const std::string& path) {
    if (bytes.size() < 10 || std::memcmp(bytes.data(), "\x93NUMPY", 6) != 0)
        throw FormatError(path + ": not a NumPy .npy file (missing \\x93NUMPY magic)");
    const unsigned major = static_cast<unsigned char>(bytes[6]);
    std::uint64_t hlen = 0, hstart = 0;
    if (major == 1) {
        hlen = static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned>(static_cast<unsigned char>(bytes[9])) << 8);
        hstart = 10;
    } else if (major == 2 || major == 3) {
        if (bytes.size() < 12) throw FormatError(path + ": truncated .npy header");
        for (int b = 3; b >= 0; --b) hlen = (hlen << 8) | static_cast<unsigned char>(bytes[8 + b]);
        hstart = 12;
    } else {
        throw FormatError(path + ": unsupported .npy version " + std::to_string(major));
    }
    if (hlen > kMaxHeader) throw FormatError(path + ": .npy header length " + std::to_string(hlen) + " beyond 1 MiB");
    if (hstart + hlen > bytes.size())
        throw FormatError(path + ": truncated .npy header (" + std::to_string(hlen) + " bytes claimed, " +
                          std::to_string(bytes.size() - hstart) + " present)");
    const std::string h(bytes.data() + hstart, hlen);
    NpyHeader r;
    r.data_offset = hstart + hlen;
    const std::string descr = dict_value(h, "descr", path);
    const std::string fortran = dict_value(h, "fortran_order", path);
    const std::string shape = dict_value(h, "shape", path);
    if (descr.size() < 2 || (descr.front() != '\'' && descr.front() != '"'))
        throw FormatError(path + ": unsupported .npy dtype " + escape_field(descr) +
                          " (structured dtypes are not read; a plain numeric dtype is needed)");
    r.descr = descr.substr(1, descr.size() - 2);
    std::string code = r.descr;
    char order = '=';
    if (!code.empty() && (code[0] == '<' || code[0] == '>' || code[0] == '|' || code[0] == '=')) {
        order = code[0];
        code = code.substr(1);
    }
    r.big_endian = order == '>' || (order == '=' && !host_is_little_endian());
    if (code == "u1" || code == "b1" || code == "B" || code == "?") r.type = StoredType::u8;
    else if (code == "i1" || code == "b") r.type = StoredType::i8;
    else if (code == "u2") r.type = StoredType::u16;
    else if (code == "i2") r.type = StoredType::i16;
    else if (code == "u4") r.type = StoredType::u32;
    else if (code == "i4") r.type = StoredType::i32;
    else if (code == "u8") r.type = StoredType::u64;
    else if (code == "i8") r.type = StoredType::i64;
    else if (code == "f4") r.type = StoredType::f32;
    else if (code == "f8") r.type = StoredType::f64;
    else if (code == "O")
        throw FormatError(path + ": .npy holds an object array (dtype 'O', Python objects), not numbers");
    else
        throw FormatError(path + ": unsupported .npy dtype '" + escape_field(r.descr) +
                          "' (u1 i1 u2 i2 u4 i4 u8 i8 f4 f8 are read)");
    if (fortran == "True") r.fortran_order = true;
    else if (fortran != "False")
        throw FormatError(path + ": malformed .npy header (fortran_order " + escape_field(fortran) + ")");
    if (shape.size() < 2 || shape.front() != '(' || shape.back() != ')')
        throw FormatError(path + ": .npy shape " + escape_field(shape) + " is not a tuple");
    std::string s = shape.substr(1, shape.size() - 2);
    for (char& c : s)
        if (c == ',') c = ' ';
    for (const auto& t : split_ws(s)) {
        const std::int64_t v = parse_int(t, path, ".npy shape");
        if (v < 0) throw FormatError(path + ": .npy shape " + escape_field(shape) + " has a negative size");
        r.shape.push_back(v);
        if (r.shape.size() > 32) throw FormatError(path + ": .npy shape " + escape_field(shape) + " has more than 32 dimensions");
    }
    return r;
}

NpyHeader read_npy_header(const std::string& path) {
    return parse_npy_header(read_file_prefix(path, kMaxHeader + 12), path);
}

int npy_ndim(const std::string& path) {
    try {
        return static_cast<int>(read_npy_header(path).shape.size());
    } catch (const std::exception&) {
        return -1;
    }
}

}  // namespace meshless
