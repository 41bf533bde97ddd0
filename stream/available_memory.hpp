// How much memory this process may use: the machine's physical memory (sysconf _SC_PHYS_PAGES x
// _SC_PAGE_SIZE), further capped by the memory limit of its cgroup and the cgroup's ancestors:
// v2 memory.max (a byte count, "max" = no limit), v1 memory.limit_in_bytes (a huge value = no
// limit), and by the address-space limit (RLIMIT_AS, `ulimit -v`) when one is set. The budget of
// a volume read whole when the user gives no --memory, and of what options imply (cli/common.hpp).
// Reads /proc/self/cgroup and /sys/fs/cgroup (stream/cgroup_limit.hpp); never throws.
// Thread-safety: reentrant.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

namespace meshless {

/// Bytes; at least one page.
std::uint64_t available_memory();

/// The limit of a cgroup memory.max / memory.limit_in_bytes text ("1073741824\n" -> 1 GiB;
/// "max", empty or malformed -> nullopt). Exposed for tests.
std::optional<std::uint64_t> memory_limit_value(const std::string& text);

}  // namespace meshless
