#include "formats/vtk_xml.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cstring>
#include <map>

#include "formats/base64.hpp"
#include "formats/gzip.hpp"
#include "formats/ply.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

namespace meshless {

std::string VtkXmlElement::name() const { return pugi::xml_node(node_).name(); }

std::string VtkXmlElement::attr(const char* k, const std::string& def) const {
    const pugi::xml_attribute a = pugi::xml_node(node_).attribute(k);
    return a ? std::string(a.value()) : def;
}

bool VtkXmlElement::has_attr(const char* k) const { return static_cast<bool>(pugi::xml_node(node_).attribute(k)); }

VtkXmlElement VtkXmlElement::child(const char* name) const {
    return VtkXmlElement(pugi::xml_node(node_).child(name).internal_object());
}

std::vector<VtkXmlElement> VtkXmlElement::children(const char* name) const {
    std::vector<VtkXmlElement> out;
    for (const pugi::xml_node c : pugi::xml_node(node_).children(name)) out.push_back(VtkXmlElement(c.internal_object()));
    return out;
}

std::vector<VtkXmlElement> VtkXmlElement::descendants(const char* name) const {
    std::vector<VtkXmlElement> out;
    const pugi::xml_node top(node_);
    pugi::xml_node n = top.first_child();
    while (n && n != top) {  // pre-order walk without recursion (the nesting depth is the file's choice)
        if (n.type() == pugi::node_element && std::strcmp(n.name(), name) == 0) out.push_back(VtkXmlElement(n.internal_object()));
        if (n.first_child()) {
            n = n.first_child();
            continue;
        }
        while (n != top && !n.next_sibling()) n = n.parent();
        if (n != top) n = n.next_sibling();
    }
    return out;
}

std::string_view VtkXmlElement::text() const { return pugi::xml_node(node_).child_value(); }

bool VtkXmlElement::empty() const { return !pugi::xml_node(node_).first_child(); }

struct VtkXmlDocument::Impl {
    pugi::xml_document xml;
    std::string_view bytes;
    VtkXmlFile file;
    pugi::xml_node root;
};

VtkXmlDocument::~VtkXmlDocument() = default;
VtkXmlDocument::VtkXmlDocument(VtkXmlDocument&&) noexcept = default;
VtkXmlDocument& VtkXmlDocument::operator=(VtkXmlDocument&&) noexcept = default;
const VtkXmlFile& VtkXmlDocument::file() const { return impl_->file; }
VtkXmlElement VtkXmlDocument::root() const { return VtkXmlElement(impl_->root.internal_object()); }
std::string_view VtkXmlDocument::bytes() const { return impl_->bytes; }

VtkXmlDocument::VtkXmlDocument(std::string_view doc, const std::string& path) : impl_(std::make_unique<Impl>()) {
    impl_->bytes = doc;
    if (doc.find("<VTKFile") == std::string_view::npos)
        throw FormatError(path + ": not a VTK XML file (no <VTKFile> element)");
    // the markup ends at <AppendedData>'s '_' marker: the binary after it is not XML
    std::size_t cut = doc.size();
    if (const std::size_t app = doc.find("<AppendedData"); app != std::string_view::npos)
        if (const std::size_t gt = doc.find('>', app); gt != std::string_view::npos)
            if (const std::size_t us = doc.find('_', gt); us != std::string_view::npos) cut = us;
    const pugi::xml_parse_result r =
        impl_->xml.load_buffer(doc.data(), cut, pugi::parse_default, pugi::encoding_utf8);
    // cut at the marker, the elements around the appended data are closed only after it
    // (pugixml reports the mismatch at the last byte it was given)
    const bool open_at_cut = r.status == pugi::status_end_element_mismatch && cut < doc.size() &&
                             static_cast<std::size_t>(r.offset) + 1 >= cut;
    if (!r && !open_at_cut) {
        const std::size_t at = std::min(static_cast<std::size_t>(r.offset), doc.size());
        throw FormatError(path + ": malformed XML at offset " + std::to_string(at) + " (" + r.description() + ") near '" +
                          ply_escape(doc.substr(at, 24), 24) + "'");
    }
    impl_->root = impl_->xml.document_element();
    if (std::string_view(impl_->root.name()) != "VTKFile")
        throw FormatError(path + ": not a VTK XML file (no <VTKFile> element)");
    const VtkXmlElement file = root();
    VtkXmlFile& f = impl_->file;
    f.type = file.attr("type");
    const std::string bo = file.attr("byte_order", "LittleEndian");
    if (bo == "BigEndian")
        f.big_endian = true;
    else if (bo != "LittleEndian")
        throw FormatError(path + ": bad byte_order '" + ply_escape(bo) + "' in <VTKFile>");
    const std::string ht = file.attr("header_type", "UInt32");
    if (ht == "UInt64")
        f.header64 = true;
    else if (ht != "UInt32")
        throw FormatError(path + ": unsupported header_type '" + ply_escape(ht) + "' in <VTKFile>");
    const std::string comp = file.attr("compressor");
    if (comp == "vtkZLibDataCompressor")
        f.compressed = true;
    else if (!comp.empty())
        throw FormatError(path + ": unsupported compressor '" + ply_escape(comp) + "' (vtkZLibDataCompressor supported)");
    const VtkXmlElement app = file.child("AppendedData");
    if (app.found()) {
        const std::string enc = app.attr("encoding", "raw");
        if (enc == "base64")
            f.appended_base64 = true;
        else if (enc != "raw")
            throw FormatError(path + ": unsupported AppendedData encoding '" + ply_escape(enc) + "'");
        if (cut == doc.size()) throw FormatError(path + ": <AppendedData> without the '_' marker");
        f.appended_begin = cut + 1;
    }
}

std::optional<StoredType> vtk_xml_type(const std::string& t) {
    static const std::map<std::string, StoredType> m = {
        {"Int8", StoredType::i8},   {"UInt8", StoredType::u8},   {"Int16", StoredType::i16},
        {"UInt16", StoredType::u16}, {"Int32", StoredType::i32}, {"UInt32", StoredType::u32},
        {"Int64", StoredType::i64}, {"UInt64", StoredType::u64}, {"Float32", StoredType::f32},
        {"Float64", StoredType::f64}, {"Char", StoredType::i8}, {"UnsignedChar", StoredType::u8}};
    const auto it = m.find(t);
    if (it == m.end()) return std::nullopt;
    return it->second;
}

namespace {

std::uint64_t read_uint(const std::byte* p, bool header64, bool big) {
    if (header64) {
        std::uint64_t v;
        std::memcpy(&v, p, 8);
        if (big == host_is_little_endian()) v = __builtin_bswap64(v);
        return v;
    }
    std::uint32_t v;
    std::memcpy(&v, p, 4);
    if (big == host_is_little_endian()) v = __builtin_bswap32(v);
    return v;
}

template <class T>
void widen(const std::byte* src, std::size_t n, double* dst) {
    for (std::size_t i = 0; i < n; ++i) {
        T v;
        std::memcpy(&v, src + i * sizeof(T), sizeof(T));
        dst[i] = static_cast<double>(v);
    }
}

}  // namespace

namespace {
// The layout of [header][data] after every check that needs no decoding: sizes against `expected`,
// blocks against the bytes present and deflate's largest expansion (nothing allocated yet).
struct BinaryLayout {
    std::size_t hs = 4;
    std::uint64_t nblocks = 0, bsize = 0, last = 0, total = 0;
    std::size_t header_bytes = 0;
    std::uint64_t block_raw(std::uint64_t b) const { return (b + 1 == nblocks && last != 0) ? last : bsize; }
};

BinaryLayout check_binary(const std::byte* bin, std::size_t n, const VtkXmlFile& f, std::uint64_t expected,
                          const std::string& path, const std::string& what) {
    BinaryLayout L;
    L.hs = f.header64 ? 8 : 4;
    const std::size_t hs = L.hs;
    if (!f.compressed) {
        if (n < hs) throw FormatError(path + ": truncated DataArray header");
        const std::uint64_t nbytes = read_uint(bin, f.header64, f.big_endian);
        if (nbytes != expected)
            throw FormatError(path + ": DataArray holds " + std::to_string(nbytes) + " bytes, expected " +
                              std::to_string(expected) + " for " + what);
        if (n - hs < nbytes)
            throw FormatError(path + ": truncated DataArray: " + std::to_string(n - hs) + " of " + std::to_string(nbytes) + " bytes");
        L.total = nbytes;
        L.header_bytes = hs;
        return L;
    }
    if (n < 3 * hs) throw FormatError(path + ": truncated compressed DataArray header");
    L.nblocks = read_uint(bin, f.header64, f.big_endian);
    L.bsize = read_uint(bin + hs, f.header64, f.big_endian);
    L.last = read_uint(bin + 2 * hs, f.header64, f.big_endian);
    if (L.nblocks > (n / hs) || (L.nblocks > 0 && L.bsize == 0) || (L.last > L.bsize))
        throw FormatError(path + ": bad compressed DataArray header (" + std::to_string(L.nblocks) + " blocks of " +
                          std::to_string(L.bsize) + " bytes, last " + std::to_string(L.last) + ")");
    const std::string ctx = path + ": compressed DataArray header";
    L.total = L.nblocks == 0 ? 0 : checked_add(checked_mul(L.nblocks - 1, L.bsize, ctx), L.last == 0 ? L.bsize : L.last, ctx);
    if (L.total != expected)
        throw FormatError(path + ": DataArray holds " + std::to_string(L.total) + " bytes, expected " + std::to_string(expected) +
                          " for " + what);
    L.header_bytes = static_cast<std::size_t>((3 + L.nblocks) * hs);
    if (n < L.header_bytes) throw FormatError(path + ": truncated compressed DataArray header");
    // every block's compressed size, checked against the bytes present and deflate's largest
    // expansion before the output is allocated (a small file cannot claim a huge array)
    std::uint64_t in = L.header_bytes;
    for (std::uint64_t b = 0; b < L.nblocks; ++b) {
        const std::uint64_t cs = read_uint(bin + (3 + b) * hs, f.header64, f.big_endian);
        const std::uint64_t us = L.block_raw(b);
        if (cs > n - in)
            throw FormatError(path + ": truncated compressed block " + std::to_string(b) + " (" + std::to_string(cs) +
                              " bytes at offset " + std::to_string(in) + ", have " + std::to_string(n - in) + ")");
        if (us / kMaxDeflateRatio > cs + 64)
            throw FormatError(path + ": compressed block " + std::to_string(b) + " claims " + std::to_string(us) +
                              " bytes, more than its " + std::to_string(cs) + " compressed bytes can hold");
        in += cs;
    }
    return L;
}

// Inflates every block of a checked layout; block b goes to dst(b) (us bytes).
template <class Dst>
void inflate_blocks(const std::byte* bin, const VtkXmlFile& f, const BinaryLayout& L, const std::string& path, Dst&& dst) {
    std::uint64_t in_pos = L.header_bytes;
    for (std::uint64_t b = 0; b < L.nblocks; ++b) {
        const std::uint64_t cs = read_uint(bin + (3 + b) * L.hs, f.header64, f.big_endian);
        const std::uint64_t us = L.block_raw(b);
        inflate_into(bin + in_pos, static_cast<std::size_t>(cs), dst(b), static_cast<std::size_t>(us), path);
        in_pos += cs;
    }
}
}  // namespace

std::vector<std::byte> vtk_xml_decode_binary(const std::byte* bin, std::size_t n, const VtkXmlFile& f,
                                             std::uint64_t expected, const std::string& path, const std::string& what) {
    const BinaryLayout L = check_binary(bin, n, f, expected, path, what);
    if (!f.compressed) return std::vector<std::byte>(bin + L.hs, bin + L.hs + L.total);
    std::vector<std::byte> out(static_cast<std::size_t>(L.total));
    inflate_blocks(bin, f, L, path, [&](std::uint64_t b) { return out.data() + b * L.bsize; });
    return out;
}

void vtk_xml_prove_binary(const std::byte* bin, std::size_t n, const VtkXmlFile& f, std::uint64_t expected,
                          const std::string& path, const std::string& what) {
    const BinaryLayout L = check_binary(bin, n, f, expected, path, what);
    if (!f.compressed || L.nblocks == 0) return;
    // one block at a time (bsize is bounded by its compressed bytes, checked above)
    std::vector<std::byte> scratch(static_cast<std::size_t>(L.bsize));
    inflate_blocks(bin, f, L, path, [&](std::uint64_t) { return scratch.data(); });
}

std::vector<double> vtk_xml_read_array(const VtkXmlDocument& d, const VtkXmlElement& a, std::uint64_t count,
                                       const std::string& path) {
    const VtkXmlFile& f = d.file();
    const std::string_view doc = d.bytes();
    const std::string name = ply_escape(a.attr("Name", "(unnamed)"));
    const std::string tname = a.attr("type");
    const auto st = vtk_xml_type(tname);
    if (!st) throw FormatError(path + ": DataArray '" + name + "' has unsupported type '" + ply_escape(tname) + "'");
    const std::string format = a.attr("format");
    const std::size_t es = stored_size(*st);
    const std::uint64_t expected = checked_mul(count, es, path + ": DataArray size");
    const std::string what = "DataArray '" + name + "' (" + std::to_string(count) + " " + to_string(*st) + ")";
    std::vector<std::byte> payload;
    if (format == "ascii" || format == "binary") {
        if (a.empty()) throw FormatError(path + ": empty DataArray '" + name + "'");
        // the content ends at the first child element (VTK writes nested <InformationKey> elements)
        const std::string_view text = a.text();
        if (format == "ascii") {
            const auto toks = split_ws(text);
            if (toks.size() != count)
                throw FormatError(path + ": " + what + " has " + std::to_string(toks.size()) + " ascii values, expected " +
                                  std::to_string(count));
            std::vector<double> out(count);
            for (std::size_t i = 0; i < count; ++i) out[i] = parse_double(toks[i], path, "DataArray value");
            return out;
        }
        const auto bin = base64_decode(text, path);
        payload = vtk_xml_decode_binary(bin.data(), bin.size(), f, expected, path, what);
    } else if (format == "appended") {
        if (f.appended_begin == std::string::npos)
            throw FormatError(path + ": format=\"appended\" without <AppendedData>");
        const auto off = static_cast<std::uint64_t>(parse_int(a.attr("offset", "0"), path, "offset"));
        if (f.appended_begin + off > doc.size())
            throw FormatError(path + ": appended offset " + std::to_string(off) + " past the end of the file");
        const std::size_t start = static_cast<std::size_t>(f.appended_begin + off);
        if (f.appended_base64) {
            const auto bin = base64_decode(doc.substr(start), path, true);
            payload = vtk_xml_decode_binary(bin.data(), bin.size(), f, expected, path, what);
        } else {
            payload = vtk_xml_decode_binary(reinterpret_cast<const std::byte*>(doc.data()) + start, doc.size() - start, f,
                                            expected, path, what);
        }
    } else {
        throw FormatError(path + ": unsupported DataArray format '" + ply_escape(format) + "'");
    }
    if (f.big_endian != !host_is_little_endian()) byte_swap_in_place(payload.data(), payload.size(), es);
    std::vector<double> out(static_cast<std::size_t>(count));
    const std::byte* p = payload.data();
    switch (*st) {
        case StoredType::u8: widen<std::uint8_t>(p, count, out.data()); break;
        case StoredType::i8: widen<std::int8_t>(p, count, out.data()); break;
        case StoredType::u16: widen<std::uint16_t>(p, count, out.data()); break;
        case StoredType::i16: widen<std::int16_t>(p, count, out.data()); break;
        case StoredType::u32: widen<std::uint32_t>(p, count, out.data()); break;
        case StoredType::i32: widen<std::int32_t>(p, count, out.data()); break;
        case StoredType::u64: widen<std::uint64_t>(p, count, out.data()); break;
        case StoredType::i64: widen<std::int64_t>(p, count, out.data()); break;
        case StoredType::f32: widen<float>(p, count, out.data()); break;
        case StoredType::f64: widen<double>(p, count, out.data()); break;
    }
    return out;
}

template <class T>
std::vector<T> vtk_xml_numbers(const std::string& text, std::size_t n, const std::string& path, const std::string& what) {
    std::vector<T> out;
    const char* p = text.data();
    const char* e = text.data() + text.size();
    auto sep = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ','; };
    for (;;) {
        while (p < e && sep(*p)) ++p;
        if (p == e) break;
        T v{};
        auto r = std::from_chars(p, e, v);
        if (r.ec != std::errc() || (r.ptr < e && !sep(*r.ptr)))
            throw FormatError(path + ": bad " + what + " '" + ply_escape(text, 96) + "'");
        out.push_back(v);
        p = r.ptr;
        if (out.size() > n) break;
    }
    if (out.size() != n)
        throw FormatError(path + ": bad " + what + " '" + ply_escape(text, 96) + "': expected " + std::to_string(n) + " numbers");
    return out;
}

VtkPieceExtent vtk_piece_extent(const std::string& text, const std::string& path, int piece_no) {
    const std::string where = "piece " + std::to_string(piece_no);
    const auto ext = vtk_xml_numbers<std::int64_t>(text, 6, path, where + " Extent");
    VtkPieceExtent e;
    for (int a = 0; a < 3; ++a) {
        const std::int64_t lo = ext[2 * a], hi = ext[2 * a + 1];
        if (hi < lo || lo < -(std::int64_t(1) << 40) || hi > (std::int64_t(1) << 40))
            throw FormatError(path + ": " + where + ": bad Extent '" + ply_escape(text, 96) + "'");
        e.extent[2 * a] = lo, e.extent[2 * a + 1] = hi;
        e.dims[a] = hi - lo + 1;
        e.cells[a] = e.dims[a] > 1 ? e.dims[a] - 1 : 1;
        if (__builtin_mul_overflow(e.points, static_cast<std::uint64_t>(e.dims[a]), &e.points) ||
            __builtin_mul_overflow(e.cell_count, static_cast<std::uint64_t>(e.cells[a]), &e.cell_count))
            throw FormatError(path + ": " + where + ": Extent '" + ply_escape(text, 96) + "' overflows");
    }
    return e;
}

template std::vector<double> vtk_xml_numbers<double>(const std::string&, std::size_t, const std::string&, const std::string&);
template std::vector<std::int64_t> vtk_xml_numbers<std::int64_t>(const std::string&, std::size_t, const std::string&,
                                                                 const std::string&);

}  // namespace meshless
