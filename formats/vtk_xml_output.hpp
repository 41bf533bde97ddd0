// Pieces shared by the VTK XML writers (formats/vts_writer.hpp, formats/vtm_writer.hpp,
// formats/vthb_writer.hpp): attribute escaping, appended raw records, the <VTKFile> prologue, the
// atomic write of a finished document, and the folder that holds a collection file's pieces.
//
// Layout: VTK XML LittleEndian, header_type UInt64, appended data encoding="raw" (per array a UInt64
// byte count, then the bytes), no compressor. Files are written atomically (formats/atomic_file.hpp).
// Throws IoError naming the path. Thread-safety: reentrant (no shared state).
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace meshless {

/// XML attribute value escaping shared by the VTK XML writers: & < > " ' as entities, control bytes
/// (< 0x20, 0x7f) as '?'.
std::string vtk_xml_escape(std::string_view s);

/// Appends one raw appended-data record (UInt64 little-endian byte count, then the bytes) to `out`.
void vtk_xml_append_raw(std::string& out, const void* data, std::size_t bytes);

/// `<?xml version="1.0"?>` and the opening `<VTKFile type=TYPE version=VERSION byte_order="LittleEndian"
/// header_type="UInt64">`, each followed by a newline.
std::string vtk_xml_prologue(std::string_view type, std::string_view version);

/// Writes `xml` (a complete document) to `path` atomically.
void write_vtk_xml(const std::string& path, const std::string& xml);

/// Writes `head` (the document up to its last element before the appended data), then
/// `<AppendedData encoding="raw">` with the records `appended` (vtk_xml_append_raw) and the closing
/// tags, to `path` atomically.
void write_vtk_xml_appended(const std::string& path, const std::string& head, const std::string& appended);

/// The folder of a collection file's pieces: for DIR/PREFIX.ext, the folder DIR/PREFIX (created by
/// the constructor; IoError when it cannot be) holding PREFIX/PREFIX_<n><piece_ext>.
class VtkPieceFolder {
public:
    explicit VtkPieceFolder(const std::string& collection_path);
    /// Name of piece n relative to the collection file's folder: "PREFIX/PREFIX_<n><piece_ext>".
    std::string relative(std::size_t n, std::string_view piece_ext) const;
    /// Path of a piece from its relative name.
    std::string path_of(const std::string& relative) const;

private:
    std::string parent_;
    std::string stem_;
};

}  // namespace meshless
