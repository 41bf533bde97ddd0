// How many CPUs this process may use: the CPUs of its affinity mask (sched_getaffinity: taskset,
// cpusets, container CPU sets), further capped by the CPU quota of its cgroup and the cgroup's
// ancestors: v2 cpu.max "QUOTA PERIOD" (ceil(QUOTA / PERIOD) CPUs; "max" = no quota), v1
// cpu.cfs_quota_us / cpu.cfs_period_us (-1 = no quota). At least 1. The default thread
// count of every command (--threads 0 or absent) and of RunOptions{threads <= 0}.
// Reads /proc/self/cgroup and /sys/fs/cgroup; never throws (unreadable files mean no limit).
// Thread-safety: reentrant.
#pragma once
#include <optional>
#include <string>

namespace meshless {

int available_cpus();

/// The CPU limit of a cgroup v2 cpu.max text ("200000 100000" -> 2, "150000 100000" -> 2,
/// "max 100000" and "-1 100000" -> nullopt); nullopt when the text is not of that form. Exposed for tests.
std::optional<int> cpu_quota_limit(const std::string& cpu_max_text);

}  // namespace meshless
