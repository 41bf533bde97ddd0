#include "cli/render_output.hpp"

#include <cstdio>

namespace meshless::cli {

std::string frame_path(const std::string& path, int i) {
    char num[16];
    std::snprintf(num, sizeof num, "_%03d", i);
    const auto dot = path.rfind('.');
    const auto slash = path.rfind('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + num + ".png";
    return path.substr(0, dot) + num + path.substr(dot);
}

}  // namespace meshless::cli
