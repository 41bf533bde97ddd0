#include "formats/output_names.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <string_view>

#include "formats/atomic_file.hpp"
#include "formats/point_set_writer.hpp"
#include "kernels/errors.hpp"

namespace meshless {

void refuse_binary_to_terminal(const std::string& path, const std::string& what) {
    if (path == "-" && ::isatty(1))
        throw InvalidArgument("refusing to write " + what + " to a terminal (pipe it or use -o FILE)");
}

const std::string& require_output_extension(const std::string& path, const char* ext, const char* option, const char* what,
                                            bool to_stdout) {
    if (std::string_view(ext) != ".csv") refuse_binary_to_terminal(path, what);
    if (path == "-" || is_streaming_output(path)) return path;
    const std::string e(ext);
    auto lower = [](char c) { return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c); };
    bool ok = path.size() > e.size();
    for (std::size_t i = 0; ok && i < e.size(); ++i) ok = lower(path[path.size() - e.size() + i]) == e[i];
    if (!ok)
        throw InvalidArgument(std::string(option) + " '" + path + "': this output is " + what + ", written to a " + e +
                              " file (outputs are chosen by extension" + (to_stdout ? "; '-' for stdout)" : ")"));
    return path;
}

void require_point_set_output(const std::string& path, const char* what) {
    if (!point_set_output_name(path))
        throw InvalidArgument("-o '" + path + "': this output is " + what + ", written to a .ply (binary PLY), .csv or .vtp "
                              "(VTK XML PolyData) file (outputs are chosen by extension; '-' for CSV on stdout)");
}

GeometryFormat geometry_output_format(const std::string& path, const std::optional<std::string>& format, const char* what) {
    refuse_binary_to_terminal(path, what);  // binary PLY, VTP's appended arrays
    const auto by_name = geometry_format_of(path);
    if (format) {
        const auto given = parse_geometry_format(*format);
        if (!given) throw InvalidArgument("--format: expected ply or vtp, got '" + *format + "'");
        if (by_name && *by_name != *given)
            throw InvalidArgument("-o '" + path + "': the name says " + to_string(*by_name) + " but --format says " + *format);
        return *given;
    }
    if (by_name) return *by_name;
    if (path == "-" || is_streaming_output(path)) return GeometryFormat::ply;
    throw InvalidArgument("-o '" + path + "': this output is " + what +
                          ", written to a .ply (binary PLY) or .vtp (VTK XML PolyData) file (outputs are chosen by extension; "
                          "--format ply|vtp for other names, '-' for stdout)");
}

void check_stream_output_name(const std::string& path, const char* what) {
    if (path == "-" || is_streaming_output(path)) return;
    const std::size_t slash = path.find_last_of('/'), dot = path.find_last_of('.');
    const std::size_t base = slash == std::string::npos ? 0 : slash + 1;
    if (dot == std::string::npos || dot <= base) return;  // no extension (".ply" alone is a hidden name)
    std::string ext = path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    // (.mls is allowed: "meshless samples", the sample store's extension and, in use, sample streams)
    static constexpr std::array<std::string_view, 26> kOther = {
        "ply", "vtp", "vts", "vtm", "vthb", "vti", "vtk", "vtu", "csv", "tsv", "txt", "json", "nrrd", "nhdr",
        "png", "jpg", "raw", "npy", "mhd", "mha", "nii", "gz", "mlb", "mlf", "mlh", "obj"};
    if (std::find(kOther.begin(), kOther.end(), ext) == kOther.end()) return;
    throw InvalidArgument("-o '" + path + "': this output is " + what + " (meshless's binary stream), not a ." + ext +
                          " file: give it another name (point streams are .mlp by convention), or make a point file with "
                          "`meshless write -o out.ply`");
}

}  // namespace meshless
