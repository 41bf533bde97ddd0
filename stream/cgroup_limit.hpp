// The smallest resource limit over this process's cgroups and their ancestors, the one walker of
// /proc/self/cgroup behind available_cpus (stream/available_cpus.hpp) and available_memory
// (stream/available_memory.hpp). cgroup v2: the unified hierarchy, mounted at /sys/fs/cgroup or, on
// hybrid systems, /sys/fs/cgroup/unified; v1: the hierarchy of one named controller under its
// mount points. Each directory from the process's own up to the root is read; the smallest wins.
// Never throws (unreadable files mean no limit). Thread-safety: reentrant.
#pragma once
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <optional>
#include <string>

namespace meshless {

/// A limit read from one cgroup directory (nullopt: none there).
using CgroupReader = std::function<std::optional<std::uint64_t>(const std::string& dir)>;

/// The smallest of v2(dir) over the unified hierarchy and v1(dir) over the hierarchy of the v1
/// controller `v1_controller` ("cpu", "memory"), whose mount points are `v1_roots`.
std::optional<std::uint64_t> cgroup_limit(const CgroupReader& v2, const std::string& v1_controller,
                                          std::initializer_list<const char*> v1_roots, const CgroupReader& v1);

/// A small file's text ("" when it cannot be read).
std::string read_small_file(const std::string& path);

}  // namespace meshless
