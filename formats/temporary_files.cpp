#include "formats/temporary_files.hpp"

#include <fcntl.h>
#include <cstdlib>

#include "kernels/errors.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

namespace meshless {

namespace {

enum SlotState : int { kFree = 0, kFilling = 1, kLive = 2 };

struct Slot {
    std::atomic<int> state{kFree};
    char path[kMaxTemporaryPath]{};
};

struct Registry {
    Slot slots[kMaxLiveTemporaries];
    std::atomic<StaleTemporaryReporter> reporter{nullptr};
};

// Constant-initialised (constexpr constructors, trivial destructors): no guard, nothing runs, so
// the signal handler may touch it at any time.
Registry& registry() noexcept {
    static constinit Registry r;
    return r;
}

}  // namespace

int register_temporary(const std::string& path) noexcept {
    if (path.empty() || path.size() >= kMaxTemporaryPath) return -1;
    Registry& r = registry();
    for (std::size_t i = 0; i < kMaxLiveTemporaries; ++i) {
        int expected = kFree;
        if (!r.slots[i].state.compare_exchange_strong(expected, kFilling, std::memory_order_acquire)) continue;
        std::memcpy(r.slots[i].path, path.c_str(), path.size() + 1);
        r.slots[i].state.store(kLive, std::memory_order_release);
        return static_cast<int>(i);
    }
    return -1;
}

void unregister_temporary(int slot) noexcept {
    if (slot < 0 || static_cast<std::size_t>(slot) >= kMaxLiveTemporaries) return;
    registry().slots[slot].state.store(kFree, std::memory_order_release);
}

void remove_live_temporaries() noexcept {
    Registry& r = registry();
    for (std::size_t i = 0; i < kMaxLiveTemporaries; ++i)
        if (r.slots[i].state.load(std::memory_order_acquire) == kLive) ::unlink(r.slots[i].path);
}

void for_each_live_temporary(void (*fn)(const char* path)) noexcept {
    Registry& r = registry();
    for (std::size_t i = 0; i < kMaxLiveTemporaries; ++i)
        if (r.slots[i].state.load(std::memory_order_acquire) == kLive) fn(r.slots[i].path);
}

std::size_t live_temporary_count() noexcept {
    std::size_t n = 0;
    for (const Slot& s : registry().slots) n += s.state.load(std::memory_order_acquire) == kLive;
    return n;
}

void set_stale_temporary_reporter(StaleTemporaryReporter rep) noexcept { registry().reporter.store(rep); }

std::vector<std::string> remove_stale_temporaries(const std::string& out) noexcept {
    try {
        return remove_stale_temporaries(std::vector<std::string>{out}, true);
    } catch (...) {
        return {};  // out of memory before the sweep: it is best effort
    }
}

std::vector<std::string> remove_stale_temporaries(const std::vector<std::string>& outs, bool report) noexcept {
    namespace fs = std::filesystem;
    std::vector<std::string> removed;
    try {
        std::map<fs::path, std::set<std::string>> names;  // folder -> the outputs' file names in it
        for (const auto& out : outs) {
            const fs::path op(out);
            if (!op.filename().empty()) names[op.has_parent_path() ? op.parent_path() : fs::path(".")].insert(op.filename().string());
        }
        for (const auto& [dir, in_dir] : names) {
            std::error_code ec;
            for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
                const std::string name = it->path().filename().string();
                const auto t = name.rfind(".tmp-");  // the pid has no ".tmp-": the output's name ends here
                if (t == std::string::npos || !in_dir.count(name.substr(0, t))) continue;
                std::string rest = name.substr(t + 5);
                if (rest.size() > 6 && rest.compare(rest.size() - 6, 6, ".spool") == 0) rest.resize(rest.size() - 6);
                if (rest.empty() || rest.size() > 9 || rest.find_first_not_of("0123456789") != std::string::npos) continue;
                const long pid = std::stol(rest);
                if (pid <= 0 || pid == static_cast<long>(::getpid())) continue;
                if (::kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to judge
                std::error_code rec;
                if (!fs::remove(it->path(), rec)) continue;
                removed.push_back(it->path().string());
                if (auto rep = registry().reporter.load(); rep && report) rep(removed.back().c_str(), pid);
            }
        }
    } catch (...) {
        // out of memory while listing: the sweep is best effort
    }
    return removed;
}

std::FILE* unlinked_temporary(const std::string& purpose, std::string& name) {
    const char* dir = std::getenv("TMPDIR");
    std::string tmpl = std::string(dir && *dir ? dir : "/tmp") + "/meshless-" + purpose + "-XXXXXX";
    const int fd = ::mkstemp(tmpl.data());
    if (fd < 0) throw IoError(tmpl + ": cannot create a temporary file: " + std::strerror(errno));
    name = tmpl;
    ::unlink(name.c_str());  // unlinked: the space is freed whatever happens to the process
    std::FILE* f = ::fdopen(fd, "w+b");
    if (!f) {
        const int e = errno;
        ::close(fd);
        throw IoError(name + ": cannot open a temporary file: " + std::strerror(e));
    }
    return f;
}

}  // namespace meshless
