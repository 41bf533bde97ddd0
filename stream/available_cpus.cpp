#include "stream/available_cpus.hpp"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

namespace meshless {

std::optional<int> cpu_quota_limit(const std::string& text) {
    std::istringstream in(text);
    std::string quota;
    long long period = 0;
    if (!(in >> quota >> period) || period <= 0 || quota == "max") return std::nullopt;  // v1 says -1
    char* end = nullptr;
    const long long q = std::strtoll(quota.c_str(), &end, 10);
    if (end == quota.c_str() || *end != '\0' || q <= 0) return std::nullopt;
    return static_cast<int>(std::max<long long>(1, (q + period - 1) / period));
}

namespace {

std::string read_small(const std::string& path) {
    std::ifstream f(path);
    std::ostringstream s;
    if (f) s << f.rdbuf();
    return s.str();
}

std::optional<int> min_limit(std::optional<int> a, std::optional<int> b) {
    if (a && b) return std::min(*a, *b);
    return a ? a : b;
}

/// The smallest limit over a cgroup directory and its ancestors up to `root`.
template <class Read>
std::optional<int> walk_up(const std::string& root, std::string dir, Read&& read) {
    std::optional<int> best;
    for (;;) {
        best = min_limit(best, read(root + (dir == "/" ? std::string() : dir)));
        if (dir.empty() || dir == "/") break;
        const auto slash = dir.find_last_of('/');
        dir = slash == std::string::npos || slash == 0 ? std::string() : dir.substr(0, slash);
    }
    return best;
}

/// The CPU quota of this process's cgroup: v2 (cpu.max in the unified hierarchy, mounted at
/// /sys/fs/cgroup or, on hybrid systems, /sys/fs/cgroup/unified) and v1 (cpu.cfs_quota_us /
/// cpu.cfs_period_us of the "cpu" controller), each directory up to the root; the smallest wins.
std::optional<int> cgroup_limit() {
    std::optional<int> best;
    std::istringstream lines(read_small("/proc/self/cgroup"));
    for (std::string line; std::getline(lines, line);) {
        const auto c1 = line.find(':'), c2 = c1 == std::string::npos ? c1 : line.find(':', c1 + 1);
        if (c2 == std::string::npos) continue;
        const std::string controllers = "," + line.substr(c1 + 1, c2 - c1 - 1) + ",", path = line.substr(c2 + 1);
        if (line.rfind("0::", 0) == 0) {
            for (const char* root : {"/sys/fs/cgroup", "/sys/fs/cgroup/unified"})
                best = min_limit(best, walk_up(root, path, [](const std::string& d) {
                                     return cpu_quota_limit(read_small(d + "/cpu.max"));
                                 }));
        } else if (controllers.find(",cpu,") != std::string::npos) {
            for (const char* root : {"/sys/fs/cgroup/cpu", "/sys/fs/cgroup/cpu,cpuacct"})
                best = min_limit(best, walk_up(root, path, [](const std::string& d) {
                                     const std::string q = read_small(d + "/cpu.cfs_quota_us");
                                     const std::string p = read_small(d + "/cpu.cfs_period_us");
                                     if (q.empty() || p.empty()) return std::optional<int>();
                                     return cpu_quota_limit(q + " " + p);
                                 }));
        }
    }
    return best;
}

}  // namespace

int available_cpus() {
    int n = 0;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) n = CPU_COUNT(&set);
    if (n <= 0) n = static_cast<int>(std::thread::hardware_concurrency());
    if (auto lim = cgroup_limit()) n = std::min(n, *lim);
    return std::max(1, n);
}

}  // namespace meshless
