#include "stream/available_memory.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>

#include "stream/cgroup_limit.hpp"

namespace meshless {

std::optional<std::uint64_t> memory_limit_value(const std::string& text) {
    std::string t = text;
    while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
    if (t.empty() || t == "max" || t[0] < '0' || t[0] > '9') return std::nullopt;
    char* end = nullptr;
    errno = 0;
    const unsigned long long v = std::strtoull(t.c_str(), &end, 10);
    if (*end != '\0' || errno == ERANGE) return std::nullopt;
    return static_cast<std::uint64_t>(v);
}

std::uint64_t available_memory() {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    const std::uint64_t page_bytes = page > 0 ? static_cast<std::uint64_t>(page) : 4096;
    std::uint64_t bytes = pages > 0 ? static_cast<std::uint64_t>(pages) * page_bytes : UINT64_MAX;
    // (v1 writes "no limit" as the largest page-aligned long, far above any machine: the min ignores it)
    const auto read = [](const char* file) {
        return [file](const std::string& d) { return memory_limit_value(read_small_file(d + "/" + file)); };
    };
    if (const auto lim = cgroup_limit(read("memory.max"), "memory", {"/sys/fs/cgroup/memory"}, read("memory.limit_in_bytes")))
        bytes = std::min(bytes, *lim);
    // the address-space limit (ulimit -v): no allocation beyond it can succeed
    if (rlimit as{}; ::getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
        bytes = std::min(bytes, static_cast<std::uint64_t>(as.rlim_cur));
    return std::max(bytes, page_bytes);
}

}  // namespace meshless
