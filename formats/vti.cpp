#include "formats/vti.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <cstring>
#include <charconv>
#include <map>

#include "formats/base64.hpp"
#include "formats/binary_file.hpp"
#include "formats/gzip.hpp"
#include "formats/payload.hpp"
#include "formats/text_header.hpp"
#include "formats/vtk_xml.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"
#include "kernels/flip_axes.hpp"

namespace meshless {

namespace {

using Tag = VtkXmlElement;

std::string attr(const Tag& t, const char* k, const std::string& def = "") { return t.attr(k, def); }

struct VtiLayout {
    GridSpec grid;
    StoredType type = StoredType::u8;
    bool big_endian = false;
    bool compressed = false;
    bool header64 = false;
    std::array<bool, 3> flip{false, false, false};  // negative Spacing: samples reversed after reading
    std::string format;            // ascii | binary | appended
    std::string_view content;      // inline content (in the parsed document)
    std::size_t appended_begin = 0;  // first byte after '_'
    bool appended_base64 = false;
    std::uint64_t offset = 0;
    std::string encoding_name;
    std::vector<VolumeArray> arrays;  // every point DataArray
    std::size_t default_array = 0, read_array = 0;
};

VtiLayout parse_layout(const VtkXmlDocument& X, const std::string& path, const std::string& array) {
    const VtkXmlFile& F = X.file();
    VtiLayout L;
    if (F.type != "ImageData") throw FormatError(path + ": unsupported VTK XML type '" + escape_field(F.type) + "' (ImageData supported)");
    L.big_endian = F.big_endian;
    L.header64 = F.header64;
    L.compressed = F.compressed;

    const Tag image = X.root().child("ImageData");
    if (!image.found()) throw FormatError(path + ": missing <ImageData>");
    const std::vector<Tag> pieces = image.children("Piece");
    if (pieces.empty()) throw FormatError(path + ": missing <Piece>");
    if (pieces.size() > 1) throw FormatError(path + ": several <Piece> elements are not supported");
    const Tag piece = pieces.front();
    std::string extent = attr(piece, "Extent", attr(image, "WholeExtent"));
    const auto ext = parse_ints(extent, 6, path, "Extent");
    const auto sp = parse_doubles(attr(image, "Spacing", "1 1 1"), 3, path, "Spacing");
    const auto org = parse_doubles(attr(image, "Origin", "0 0 0"), 3, path, "Origin");
    for (int a = 0; a < 3; ++a) {
        L.grid.dims[a] = checked_extent(ext[2 * a], ext[2 * a + 1], path + ": Extent");
        if (sp[a] == 0 || !std::isfinite(sp[a])) throw FormatError(path + ": bad Spacing: zero or non-finite spacing");
        L.grid.origin[a] = org[a] + static_cast<double>(ext[2 * a]) * sp[a];
        honour_signed_spacing(L.grid, L.flip, a, sp[a]);
    }
    validate_grid(L.grid, path);

    const Tag pd = piece.child("PointData");
    if (!pd.found() || pd.empty()) throw FormatError(path + ": no <PointData> arrays");
    const std::string want = attr(pd, "Scalars");
    const std::vector<Tag> all = pd.children("DataArray");
    if (all.empty()) throw FormatError(path + ": no point DataArray");
    for (std::size_t k = 0; k < all.size(); ++k) {  // the default: the active scalars, else the first
        VolumeArray a;
        a.name = attr(all[k], "Name");
        const std::string tname = attr(all[k], "type");
        const auto t = vtk_xml_type(tname);
        a.type = t ? to_string(*t) : escape_field(tname);
        const std::string nc = attr(all[k], "NumberOfComponents", "1");
        a.components = 0;
        std::from_chars(nc.data(), nc.data() + nc.size(), a.components);
        L.arrays.push_back(std::move(a));
        if (!want.empty() && L.arrays[k].name == want && L.arrays[L.default_array].name != want) L.default_array = k;
    }
    L.read_array = choose_volume_array(L.arrays, L.default_array, array, path);
    const Tag chosen = all[L.read_array];
    const std::string ncomp = attr(chosen, "NumberOfComponents", "1");
    if (ncomp != "1") throw FormatError(path + ": unsupported DataArray with " + escape_field(ncomp) + " components");
    const std::string tname = attr(chosen, "type");
    const auto st = vtk_xml_type(tname);
    if (!st) throw FormatError(path + ": unsupported DataArray type '" + escape_field(tname) + "'");
    L.type = *st;
    L.format = attr(chosen, "format");
    if (L.format == "ascii" || L.format == "binary") {
        if (chosen.empty()) throw FormatError(path + ": empty DataArray");
        L.content = chosen.text();
        L.encoding_name = L.format == "ascii" ? "ascii" : (L.compressed ? "base64+zlib" : "base64");
    } else if (L.format == "appended") {
        L.offset = checked_count(parse_int(attr(chosen, "offset", "0"), path, "offset"), path + ": DataArray offset");
        if (F.appended_begin == std::string::npos) throw FormatError(path + ": format=\"appended\" without <AppendedData>");
        L.appended_base64 = F.appended_base64;
        L.appended_begin = F.appended_begin;
        L.encoding_name = std::string("appended-") + (L.appended_base64 ? "base64" : "raw") + (L.compressed ? "+zlib" : "");
    } else {
        throw FormatError(path + ": unsupported DataArray format '" + escape_field(L.format) + "'");
    }
    return L;
}

VtkXmlFile xml_file(const VtiLayout& L) {
    VtkXmlFile f;
    f.big_endian = L.big_endian;
    f.header64 = L.header64;
    f.compressed = L.compressed;
    return f;
}

// The chosen array's [header][data] bytes (binary and appended formats): base64 decoded into
// `owned`, or a view into the document (appended raw).
std::pair<const std::byte*, std::size_t> binary_bytes(std::string_view doc, const VtiLayout& L, const std::string& path,
                                                      std::vector<std::byte>& owned) {
    if (L.format == "binary") {
        owned = base64_decode(L.content, path);
        return {owned.data(), owned.size()};
    }
    if (L.appended_base64) {
        if (L.appended_begin + L.offset > doc.size()) throw FormatError(path + ": appended offset past the end of the file");
        owned = base64_decode(doc.substr(static_cast<std::size_t>(L.appended_begin + L.offset)), path, true);
        return {owned.data(), owned.size()};
    }
    const std::uint64_t start = L.appended_begin + L.offset;
    if (start > doc.size()) throw FormatError(path + ": appended offset " + std::to_string(L.offset) + " past the end of the file");
    return {reinterpret_cast<const std::byte*>(doc.data()) + start, static_cast<std::size_t>(doc.size() - start)};
}

}  // namespace

VolumeInfo probe_vti(const std::string& path, const std::string& array) {
    const std::uint64_t size = regular_file_size(path);
    // headers are at the front; the chosen array's content may be far away, but probing only
    // needs the tags: read up to 1 MiB, falling back to the whole file when tags straddle it
    std::string doc = read_file_prefix(path, static_cast<std::size_t>(std::min<std::uint64_t>(size, 1 << 20)));
    VtiLayout L;
    try {
        L = parse_layout(VtkXmlDocument(doc, path), path, array);
    } catch (const FormatError&) {
        if (doc.size() == size) throw;
        doc = read_file_prefix(path, static_cast<std::size_t>(size));
        L = parse_layout(VtkXmlDocument(doc, path), path, array);
    }
    VolumeInfo i;
    i.format = "vti";
    i.grid = L.grid;
    i.type = volume_type_for(L.type);
    i.encoding = L.encoding_name;
    i.data_files = {path};
    i.arrays = L.arrays;
    i.default_array = L.default_array;
    i.read_array = L.read_array;
    return i;
}

namespace {
// A .vti file read and its layout parsed: what read_vti and prove_vti share. Built in place (the
// document and the layout point into `bytes`), so neither copied nor moved.
struct VtiFile {
    const std::vector<std::byte> bytes;
    const std::string_view doc;
    const VtkXmlDocument xml;
    const VtiLayout L;
    const std::uint64_t count, expected;  // samples, payload bytes
    VtiFile(const std::string& path, const std::string& array)
        : bytes(read_file_bytes(path)),
          doc(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
          xml(doc, path),
          L(parse_layout(xml, path, array)),
          count(static_cast<std::uint64_t>(L.grid.voxel_count())),
          expected(checked_mul(count, stored_size(L.type), path + ": payload size")) {}
    VtiFile(const VtiFile&) = delete;
    VtiFile& operator=(const VtiFile&) = delete;
    std::string what() const { return dims_string(L.grid) + " " + to_string(L.type); }
};
}  // namespace

Volume read_vti(const std::string& path, const std::string& array) {
    const VtiFile F(path, array);
    const VtiLayout& L = F.L;
    if (L.format == "ascii") {
        Volume v = make_volume(parse_ascii_samples(L.content, L.type, static_cast<std::size_t>(F.count), path), L.type,
                               !host_is_little_endian(), L.grid, path);
        flip_axes(v, L.flip);
        return v;
    }
    std::vector<std::byte> owned;
    const auto [bin, n] = binary_bytes(F.doc, L, path, owned);
    Volume v = make_volume(vtk_xml_decode_binary(bin, n, xml_file(L), F.expected, path, F.what()), L.type, L.big_endian,
                           L.grid, path);
    flip_axes(v, L.flip);
    return v;
}

void prove_vti(const std::string& path, const std::string& array) {
    const VtiFile F(path, array);
    const VtiLayout& L = F.L;
    if (L.format == "ascii") {  // the values' count is bounded by the text: parsing keeps at most 4x its size
        parse_ascii_samples(L.content, L.type, static_cast<std::size_t>(F.count), path);
        return;
    }
    std::vector<std::byte> owned;
    const auto [bin, n] = binary_bytes(F.doc, L, path, owned);
    vtk_xml_prove_binary(bin, n, xml_file(L), F.expected, path, F.what());
}

}  // namespace meshless
