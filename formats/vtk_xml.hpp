// Shared machinery of the VTK XML readers (.vti ImageData, .vtp PolyData, .vts StructuredGrid):
// a minimal tag/attribute scanner and the DataArray payload decoder.
//
// Data formats: ascii, binary (inline base64) and appended (raw or base64); compressor
// vtkZLibDataCompressor or none; header_type UInt32 (default) or UInt64; byte_order
// LittleEndian or BigEndian (headers and data). Compressed layout: header [nblocks, blocksize,
// last_blocksize, csize_0..csize_{n-1}], then the zlib blocks.
// Units: byte offsets in the document. Throws FormatError naming `path` (unterminated tags, bad
// attributes, truncated or corrupt payloads, size mismatches). Thread-safety: pure, reentrant.
// Dissertation: input plumbing (chapter 3 volumes, chapters 4-5 scattered and multiblock data).
#pragma once
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "formats/stored_type.hpp"

namespace meshless {

struct VtkXmlTag {
    std::size_t begin = std::string::npos;  ///< offset of '<' (npos: not found)
    std::size_t end = 0;                    ///< offset after '>'
    std::map<std::string, std::string> attrs;
    bool self_closing = false;
    bool found() const { return begin != std::string::npos; }
    std::string attr(const char* k, const std::string& def = "") const {
        const auto it = attrs.find(k);
        return it == attrs.end() ? def : it->second;
    }
};

/// Finds the next <name ...> at or after `from` (before `limit`) and parses its attributes.
VtkXmlTag vtk_xml_find_tag(std::string_view doc, std::string_view name, std::size_t from, std::size_t limit,
                           const std::string& path);

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

/// Parses <VTKFile> (and locates <AppendedData> when `find_appended`). FormatError when the
/// document has no <VTKFile>, or an unsupported byte_order/header_type/compressor/encoding.
VtkXmlFile vtk_xml_file(std::string_view doc, const std::string& path, bool find_appended = true);

/// Decodes [header][data] laid out in `bin` (raw bytes) into `expected` payload bytes (file byte
/// order). `what` names the array in messages (e.g. "64x64x64 float32").
std::vector<std::byte> vtk_xml_decode_binary(const std::byte* bin, std::size_t n, const VtkXmlFile& f,
                                             std::uint64_t expected, const std::string& path, const std::string& what);
/// The same checks and decoding as vtk_xml_decode_binary without keeping the payload: compressed
/// blocks are inflated one at a time into one block-sized buffer (`meshless info`'s proof).
void vtk_xml_prove_binary(const std::byte* bin, std::size_t n, const VtkXmlFile& f, std::uint64_t expected,
                          const std::string& path, const std::string& what);

/// The payload of one DataArray (any format) as `count` values of its stored type, converted to
/// double. `doc` is the whole file. FormatError on unsupported formats or size mismatches.
std::vector<double> vtk_xml_read_array(std::string_view doc, const VtkXmlFile& f, const VtkXmlTag& array,
                                       std::uint64_t count, const std::string& path);

/// The numbers of an attribute value `text` (separated by spaces, tabs, newlines or commas), exactly
/// n of them. T: double or std::int64_t. FormatError "path: bad <what> '<text>'" (escaped) on a
/// non-number or a count other than n.
template <class T>
std::vector<T> vtk_xml_numbers(const std::string& text, std::size_t n, const std::string& path, const std::string& what);

}  // namespace meshless
