#include "stream/cgroup_limit.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

namespace meshless {

std::string read_small_file(const std::string& path) {
    std::ifstream f(path);
    std::ostringstream s;
    if (f) s << f.rdbuf();
    return s.str();
}

namespace {

std::optional<std::uint64_t> min_limit(std::optional<std::uint64_t> a, std::optional<std::uint64_t> b) {
    if (a && b) return std::min(*a, *b);
    return a ? a : b;
}

/// The smallest limit over a cgroup directory and its ancestors up to `root`.
std::optional<std::uint64_t> walk_up(const std::string& root, std::string dir, const CgroupReader& read) {
    std::optional<std::uint64_t> best;
    for (;;) {
        best = min_limit(best, read(root + (dir == "/" ? std::string() : dir)));
        if (dir.empty() || dir == "/") break;
        const auto slash = dir.find_last_of('/');
        dir = slash == std::string::npos || slash == 0 ? std::string() : dir.substr(0, slash);
    }
    return best;
}

}  // namespace

std::optional<std::uint64_t> cgroup_limit(const CgroupReader& v2, const std::string& v1_controller,
                                          std::initializer_list<const char*> v1_roots, const CgroupReader& v1) {
    std::optional<std::uint64_t> best;
    std::istringstream lines(read_small_file("/proc/self/cgroup"));
    const std::string wanted = "," + v1_controller + ",";
    for (std::string line; std::getline(lines, line);) {
        const auto c1 = line.find(':'), c2 = c1 == std::string::npos ? c1 : line.find(':', c1 + 1);
        if (c2 == std::string::npos) continue;
        const std::string controllers = "," + line.substr(c1 + 1, c2 - c1 - 1) + ",", path = line.substr(c2 + 1);
        if (line.rfind("0::", 0) == 0) {
            for (const char* root : {"/sys/fs/cgroup", "/sys/fs/cgroup/unified"}) best = min_limit(best, walk_up(root, path, v2));
        } else if (controllers.find(wanted) != std::string::npos) {
            for (const char* root : v1_roots) best = min_limit(best, walk_up(root, path, v1));
        }
    }
    return best;
}

}  // namespace meshless
