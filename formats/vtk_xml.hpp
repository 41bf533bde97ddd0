// Shared machinery of the VTK XML readers (.vti ImageData, .vtp PolyData, .vts StructuredGrid,
// .vtm/.vthb collections): the document's element structure, parsed by pugixml (kept inside
// vtk_xml.cpp, so this header stays light), and the DataArray payload decoder.
//
// Only the markup is parsed: a file with <AppendedData> is cut at its '_' marker, and the binary
// after it (often hundreds of MB) is never given to the XML parser; appended arrays are decoded
// from the file's bytes at their offsets. Data formats: ascii, binary (inline base64) and appended
// (raw or base64); compressor vtkZLibDataCompressor or none; header_type UInt32 (default) or
// UInt64; byte_order LittleEndian or BigEndian (headers and data). Compressed layout: header
// [nblocks, blocksize, last_blocksize, csize_0..csize_{n-1}], then the zlib blocks.
// Units: byte offsets in the file. Throws FormatError naming `path` (malformed XML with its offset
// and the bytes there escaped, bad attributes naming the element, truncated or corrupt payloads,
// size mismatches). Thread-safety: a parsed document is read-only; distinct documents are independent.
// Dissertation: input plumbing (chapter 3 volumes, chapters 4-5 scattered and multiblock data).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "formats/stored_type.hpp"

namespace pugi {
struct xml_node_struct;
}

namespace meshless {

/// An element of a parsed VTK XML document: a handle, valid while its VtkXmlDocument lives.
/// A default (not found) element has no attributes and no children.
class VtkXmlElement {
public:
    VtkXmlElement() = default;
    bool found() const { return node_ != nullptr; }
    std::string name() const;
    /// The attribute's value (entities decoded), or `def` when absent.
    std::string attr(const char* k, const std::string& def = "") const;
    bool has_attr(const char* k) const;
    /// The first child element called `name` (not found when there is none).
    VtkXmlElement child(const char* name) const;
    /// Every child element called `name`, in document order.
    std::vector<VtkXmlElement> children(const char* name) const;
    /// Every element called `name` below this one at any depth, in document order.
    std::vector<VtkXmlElement> descendants(const char* name) const;
    /// The character data before the first child element (inline DataArray content).
    std::string_view text() const;
    /// True when the element holds neither elements nor text (`<X/>` or `<X></X>`).
    bool empty() const;
    bool operator==(const VtkXmlElement& o) const { return node_ == o.node_; }

private:
    friend class VtkXmlDocument;
    explicit VtkXmlElement(pugi::xml_node_struct* n) : node_(n) {}
    pugi::xml_node_struct* node_ = nullptr;
};

/// VTK XML type name ("Float32", "UInt8", "Char", ...) -> stored type; nullopt if unknown.
std::optional<StoredType> vtk_xml_type(const std::string& t);

/// File-level settings from <VTKFile>.
struct VtkXmlFile {
    std::string type;          ///< "ImageData", "PolyData", "StructuredGrid", ...
    bool big_endian = false;
    bool header64 = false;
    bool compressed = false;
    // <AppendedData>: first byte after '_' (npos when absent) and its encoding
    std::size_t appended_begin = std::string::npos;
    bool appended_base64 = false;
};

/// A VTK XML file's markup, parsed. `bytes` is the whole file (or a prefix of it, for probing) and
/// must outlive the document: appended arrays are read from it.
class VtkXmlDocument {
public:
    /// FormatError when the bytes hold no <VTKFile> root element, the markup is malformed, or
    /// <VTKFile> has an unsupported byte_order/header_type/compressor or <AppendedData> an
    /// unsupported encoding or no '_' marker.
    VtkXmlDocument(std::string_view bytes, const std::string& path);
    ~VtkXmlDocument();
    VtkXmlDocument(VtkXmlDocument&&) noexcept;
    VtkXmlDocument& operator=(VtkXmlDocument&&) noexcept;

    const VtkXmlFile& file() const;
    /// <VTKFile>.
    VtkXmlElement root() const;
    /// The file's bytes.
    std::string_view bytes() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Decodes [header][data] laid out in `bin` (raw bytes) into `expected` payload bytes (file byte
/// order). `what` names the array in messages (e.g. "64x64x64 float32").
std::vector<std::byte> vtk_xml_decode_binary(const std::byte* bin, std::size_t n, const VtkXmlFile& f,
                                             std::uint64_t expected, const std::string& path, const std::string& what);
/// The same checks and decoding as vtk_xml_decode_binary without keeping the payload: compressed
/// blocks are inflated one at a time into one block-sized buffer (`meshless info`'s proof).
void vtk_xml_prove_binary(const std::byte* bin, std::size_t n, const VtkXmlFile& f, std::uint64_t expected,
                          const std::string& path, const std::string& what);

/// The payload of one DataArray element of `d` (any format) as `count` values of its stored
/// type, converted to double. FormatError on unsupported formats or size mismatches.
std::vector<double> vtk_xml_read_array(const VtkXmlDocument& d, const VtkXmlElement& array, std::uint64_t count,
                                       const std::string& path);

/// The numbers of an attribute value `text` (separated by spaces, tabs, newlines or commas), exactly
/// n of them. T: double or std::int64_t. FormatError "path: bad <what> '<text>'" (escaped) on a
/// non-number or a count other than n.
template <class T>
std::vector<T> vtk_xml_numbers(const std::string& text, std::size_t n, const std::string& path, const std::string& what);

/// The Extent of a piece of a StructuredGrid/RectilinearGrid file (the `whole` extent when the piece
/// has none): lo hi per axis, `dims` the points per axis, `cells` the cells per axis (a flat axis
/// counts one), `points` and `cell_count` their products. FormatError "PATH: piece N: bad Extent
/// '<text>'" when a number is missing or hi < lo or a bound lies beyond ±2^40, "... overflows" when
/// a product does not fit 64 bits. Both readers of such files (grid and points) call it, so they
/// refuse a piece with one message.
struct VtkPieceExtent {
    std::array<std::int64_t, 6> extent{};
    std::array<std::int64_t, 3> dims{}, cells{};
    std::uint64_t points = 1, cell_count = 1;
};
VtkPieceExtent vtk_piece_extent(const std::string& text, const std::string& path, int piece_no);

}  // namespace meshless
