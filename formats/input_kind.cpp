#include "formats/input_kind.hpp"

#include <filesystem>

#include "formats/file_names.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/volume_reader.hpp"

namespace meshless {

bool names_blocks(const std::vector<std::string>& paths) {
    for (const auto& p : paths)
        if (looks_like_multiblock(p)) return true;
    // several inputs are blocks (pieces of a multiblock set) unless the first is a volume: then the
    // volume command reports the extra argument
    return paths.size() > 1 && !looks_like_volume(paths[0]);
}

bool names_scattered_points(const std::vector<std::string>& paths, bool raw_dims) {
    if (paths.empty() || names_blocks(paths)) return false;
    const std::string& p = paths[0];
    const std::string e = lower_extension(p);
    // a .raw without the name convention is a volume when its dimensions are given
    if (e == ".raw" && raw_dims) return false;
    if (looks_like_point_set(p)) return true;
    std::error_code ec;
    return e == ".ply" && std::filesystem::is_regular_file(p, ec) && !looks_like_volume(p);
}

}  // namespace meshless
