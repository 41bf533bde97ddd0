// The temporary files this process is writing ("<out>.tmp-<pid>", "<out>.tmp-<pid>.spool"), so a
// signal handler can remove them, and the sweep that removes those of processes that are gone.
//
// Registry: a fixed table of kMaxLiveTemporaries paths (each below kMaxTemporaryPath bytes) owned
// by the process. It is a function-local static with constant initialisation (no constructor runs,
// no guard, nothing allocated): the one exception to the no-globals rule, because a signal handler
// can reach nothing else. register/unregister are thread-safe (atomic slot states);
// remove_live_temporaries() is async-signal-safe (it only reads the table and calls unlink(2)), so
// cli/signals.cpp calls it from its handler before _exit(128 + signal). A path that does not fit
// (too long, table full) is not registered: it is still removed on every normal exit path, only
// a signal would leave it behind. Library code that creates a temporary registers it (AtomicFile,
// the brick converter's spool); nothing else is needed for it to be cleaned up on a signal.
//
// Stale sweep: remove_stale_temporaries(out) removes "<out>.tmp-<pid>" and "<out>.tmp-<pid>.spool"
// beside <out> whose process no longer exists (kill(pid, 0) fails with ESRCH); those of live
// processes, of this process and names that do not parse are kept. Each removal is reported to the
// reporter set by set_stale_temporary_reporter (the CLI prints it on stderr; the library itself
// never prints), unless the sweep of many outputs is asked not to (the batch job's, before it
// starts: a killed run's leftovers are expected there). Never throws; a directory that cannot be
// listed is skipped.
#pragma once
#include <cstddef>
#include <cstdio>
#include <string>
#include <vector>

namespace meshless {

inline constexpr std::size_t kMaxLiveTemporaries = 128;
inline constexpr std::size_t kMaxTemporaryPath = 4096;  ///< bytes, terminating NUL included

/// Registers a temporary path; returns its slot, or -1 when it cannot be registered (see above).
int register_temporary(const std::string& path) noexcept;
/// Forgets slot (from register_temporary; -1 is ignored). Call after the file is renamed or removed.
void unregister_temporary(int slot) noexcept;
/// unlink(2)s every registered path. Async-signal-safe; the registrations stay.
void remove_live_temporaries() noexcept;
/// Calls fn(path) for every registered path. Async-signal-safe when fn is (a signal handler's
/// message naming the outputs it abandons).
void for_each_live_temporary(void (*fn)(const char* path)) noexcept;
/// Number of registered paths (for tests).
std::size_t live_temporary_count() noexcept;

/// Called once per stale temporary removed: its path and the pid in its name.
using StaleTemporaryReporter = void (*)(const char* path, long pid);
/// Sets the reporter (nullptr: none). Thread-safe.
void set_stale_temporary_reporter(StaleTemporaryReporter r) noexcept;

/// A scratch file in $TMPDIR (or /tmp) named "meshless-<purpose>-XXXXXX", unlinked at once (its
/// space is freed however the process ends; nothing to register), opened "w+b". `name` gets the
/// name it had, for messages. Throws IoError naming it when it cannot be made or opened.
std::FILE* unlinked_temporary(const std::string& purpose, std::string& name);
/// Removes the stale temporaries of <out> (see above); returns the paths removed.
std::vector<std::string> remove_stale_temporaries(const std::string& out) noexcept;
/// The same for many outputs, each folder listed once; `report`: whether the reporter hears of the
/// removals.
std::vector<std::string> remove_stale_temporaries(const std::vector<std::string>& outs, bool report) noexcept;

/// RAII registration of one temporary path (not copyable, not movable).
class TemporaryRegistration {
public:
    TemporaryRegistration() = default;
    explicit TemporaryRegistration(const std::string& path) noexcept : slot_(register_temporary(path)) {}
    ~TemporaryRegistration() { unregister_temporary(slot_); }
    TemporaryRegistration(const TemporaryRegistration&) = delete;
    TemporaryRegistration& operator=(const TemporaryRegistration&) = delete;
    /// Registers path instead of the current one.
    void reset(const std::string& path) noexcept {
        unregister_temporary(slot_);
        slot_ = register_temporary(path);
    }
    /// Forgets the path now (after it was renamed into place or removed).
    void release() noexcept {
        unregister_temporary(slot_);
        slot_ = -1;
    }

private:
    int slot_ = -1;
};

}  // namespace meshless
