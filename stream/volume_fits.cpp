#include "stream/volume_fits.hpp"

#include <cstdio>

#include "formats/stored_type.hpp"
#include "kernels/errors.hpp"
#include "stream/available_memory.hpp"

namespace meshless {

std::string byte_size_text(std::uint64_t bytes) {
    static const char* const kUnit[] = {"bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
    double v = static_cast<double>(bytes);
    int u = 0;
    while (v >= 1024 && u < 6) v /= 1024, ++u;
    char b[48];
    if (u == 0) std::snprintf(b, sizeof b, "%llu bytes", static_cast<unsigned long long>(bytes));
    else std::snprintf(b, sizeof b, "%.1f %s", v, kUnit[u]);
    return b;
}

void check_volume_fits(const std::string& path, const VolumeInfo& vi, bool map, std::optional<std::uint64_t> memory) {
    if (map && vi.maps) return;  // the samples stay in the file (page cache), not in this process's memory
    const std::uint64_t need = decoded_bytes(vi, path);
    const std::uint64_t budget = memory ? *memory : available_memory();
    if (need <= budget) return;
    throw IoError(path + ": the volume takes " + byte_size_text(need) + " (" + dims_string(vi.grid) + " " +
                  to_string(vi.type) + ") in memory, more than " +
                  (memory ? "--memory " + byte_size_text(budget)
                          : "the " + byte_size_text(budget) + " this process may use (physical memory, cgroup limit; --memory sets it)") +
                  "; a brick store streams it: meshless convert " + path + " -o vol.mlb");
}

}  // namespace meshless
