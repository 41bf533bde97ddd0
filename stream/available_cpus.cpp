#include "stream/available_cpus.hpp"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "stream/cgroup_limit.hpp"

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

/// The CPU quota of this process's cgroup: v2 cpu.max, v1 cpu.cfs_quota_us / cpu.cfs_period_us
/// of the "cpu" controller (stream/cgroup_limit.hpp walks the hierarchies).
std::optional<int> cgroup_cpu_limit() {
    const auto as_u64 = [](std::optional<int> v) { return v ? std::optional<std::uint64_t>(*v) : std::nullopt; };
    const auto lim = cgroup_limit(
        [&](const std::string& d) { return as_u64(cpu_quota_limit(read_small_file(d + "/cpu.max"))); }, "cpu",
        {"/sys/fs/cgroup/cpu", "/sys/fs/cgroup/cpu,cpuacct"}, [&](const std::string& d) {
            const std::string q = read_small_file(d + "/cpu.cfs_quota_us");
            const std::string p = read_small_file(d + "/cpu.cfs_period_us");
            if (q.empty() || p.empty()) return std::optional<std::uint64_t>();
            return as_u64(cpu_quota_limit(q + " " + p));
        });
    if (!lim) return std::nullopt;
    return static_cast<int>(std::min<std::uint64_t>(*lim, 1 << 20));
}

}  // namespace

int available_cpus() {
    int n = 0;
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) n = CPU_COUNT(&set);
    if (n <= 0) n = static_cast<int>(std::thread::hardware_concurrency());
    if (auto lim = cgroup_cpu_limit()) n = std::min(n, *lim);
    return std::max(1, n);
}

}  // namespace meshless
