#include "formats/multiblock_reader.hpp"

#include <filesystem>

#include "formats/plot3d.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

std::string lower_ext(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

}  // namespace

bool looks_like_multiblock(const std::string& path) {
    const std::string e = lower_ext(path);
    if (e == ".vts" || e == ".vtm" || e == ".vthb" || e == ".p3d" || e == ".xyz" || e == ".x") return true;
    if (e == ".bin") return looks_like_plot3d_xyz(path);
    return false;
}

// Interim reader: the point-set readers keep each block's dims; a block whose node count matches
// its dims is structured as is. Blanked/NaN nodes are dropped by those readers, which would break
// the lattice, so such files are refused here until the structured readers land.
Multiblock read_multiblock(const std::vector<std::string>& paths, const PointSetOptions& options) {
    if (paths.empty()) throw InvalidArgument("read_multiblock: no input files");
    Multiblock mb;
    for (const auto& path : paths) {
        PointSet ps = read_point_set(path, options);
        if (ps.dropped_blanked || ps.dropped_nonfinite)
            throw FormatError(path + ": blanked or non-finite nodes are not supported by the block reader yet");
        if (mb.value_name.empty()) mb.value_name = ps.value_name;
        mb.format = lower_ext(path).substr(1);
        for (const auto& b : ps.blocks) {
            StructuredBlock sb;
            sb.name = b.name;
            sb.dims = b.dims;
            if (sb.node_count() != static_cast<std::int64_t>(b.count))
                throw FormatError(path + ": block '" + b.name + "' has " + std::to_string(b.count) +
                                  " nodes, its dims imply " + std::to_string(sb.node_count()));
            sb.node.assign(ps.pos.begin() + static_cast<std::ptrdiff_t>(b.first),
                           ps.pos.begin() + static_cast<std::ptrdiff_t>(b.first + b.count));
            sb.value.assign(ps.value.begin() + static_cast<std::ptrdiff_t>(b.first),
                            ps.value.begin() + static_cast<std::ptrdiff_t>(b.first + b.count));
            mb.blocks.push_back(std::move(sb));
        }
    }
    return mb;
}

}  // namespace meshless
