#include "cli/stream_output.hpp"
#include "cli/common.hpp"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <string_view>

#include "cli/errors.hpp"

namespace meshless::cli {

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
    throw UsageError("-o '" + path + "': this output is " + what + " (meshless's binary stream), not a ." + ext +
                     " file: give it another name (point streams are .mlp by convention), or make a point file with "
                     "`meshless write -o out.ply`");
}

BinaryStreamOutput::BinaryStreamOutput(const std::string& path, const char* what) : name(path) {
    check_stream_output_name(path, what);
    refuse_binary_to_terminal(path, "a binary stream");
    file = std::make_unique<AtomicFile>(path);
    f = file->handle();
}

}  // namespace meshless::cli
