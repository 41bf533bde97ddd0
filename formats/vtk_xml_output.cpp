#include "formats/vtk_xml_output.hpp"

#include <bit>
#include <cstdint>
#include <filesystem>

#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

static_assert(std::endian::native == std::endian::little, "the VTK XML writers assume a little-endian host");

std::string vtk_xml_escape(std::string_view s) {
    std::string r;
    r.reserve(s.size());
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        switch (ch) {
            case '&': r += "&amp;"; break;
            case '<': r += "&lt;"; break;
            case '>': r += "&gt;"; break;
            case '"': r += "&quot;"; break;
            case '\'': r += "&apos;"; break;
            default: r += (c < 0x20 || c == 0x7f) ? '?' : ch;
        }
    }
    return r;
}

void vtk_xml_append_raw(std::string& out, const void* data, std::size_t bytes) {
    const std::uint64_t n = bytes;
    out.append(reinterpret_cast<const char*>(&n), sizeof n);
    if (bytes) out.append(static_cast<const char*>(data), bytes);
}

std::string vtk_xml_prologue(std::string_view type, std::string_view version) {
    return "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + std::string(type) + "\" version=\"" + std::string(version) +
           "\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
}

void write_vtk_xml(const std::string& path, const std::string& xml) {
    AtomicFile f(path);
    f.write(xml);
    f.commit();
}

void write_vtk_xml_appended(const std::string& path, const std::string& head, const std::string& appended) {
    AtomicFile f(path);
    f.write(head);
    f.write(std::string("  <AppendedData encoding=\"raw\">\n   _"));
    f.write(appended);
    f.write(std::string("\n  </AppendedData>\n</VTKFile>\n"));
    f.commit();
}

VtkPieceFolder::VtkPieceFolder(const std::string& collection_path) {
    namespace fs = std::filesystem;
    const fs::path p(collection_path);
    stem_ = p.stem().string();
    parent_ = p.parent_path().string();
    const fs::path dir = p.parent_path() / stem_;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir, ec)) throw IoError(dir.string() + ": cannot create the folder for the pieces");
}

std::string VtkPieceFolder::relative(std::size_t n, std::string_view piece_ext) const {
    return stem_ + "/" + stem_ + "_" + std::to_string(n) + std::string(piece_ext);
}

std::string VtkPieceFolder::path_of(const std::string& relative) const {
    return (std::filesystem::path(parent_) / relative).string();
}

}  // namespace meshless
