// Platform ceilings for the threads rows of `meshless-bench process`: how much two
// threads gain over one on the machine itself, for the three kinds of work a whole `meshless`
// process does besides computing, measured in the same run as the commands they bound:
//   page_cache_read   pread(2) of a cached file in 1 MiB pieces into one reused buffer (how
//                     `isosurface` streams a raw/NRRD volume: the kernel copies every byte);
//   memory_copy       memcpy between two buffers already faulted in (plain DRAM bandwidth);
//   fresh_memory      a fresh mapping on advised huge pages, written once and unmapped (the
//                     kernel's page faults and zero-filling: what the splat sink's buffers and
//                     footprint spool cost on first touch; stream/zeroed_buffer.hpp).
// Each is the best of `reps` runs with one thread doing all the work and with two threads doing
// half each; the ratio one / two is the speedup a perfectly parallel program of that kind could
// reach here. Units: seconds, bytes. Throws IoError naming the file when it cannot be read (on
// either thread: the other is joined first).
#pragma once
#include <cstddef>
#include <filesystem>

namespace meshless::bench {

struct Scaling {
    double one_s = 0, two_s = 0;  ///< best wall seconds with 1 thread, with 2 threads
    std::size_t bytes = 0;        ///< bytes moved (or touched) per run
    double speedup() const { return two_s > 0 ? one_s / two_s : 0; }
};

/// Reads the whole file (once first, to have it cached).
Scaling page_cache_read(const std::filesystem::path& file, int reps);
/// Copies `bytes` between two pre-faulted buffers.
Scaling memory_copy(std::size_t bytes, int reps);
/// Maps, writes once and unmaps `bytes` of fresh memory (ZeroedBuffer).
Scaling fresh_memory(std::size_t bytes, int reps);

}  // namespace meshless::bench
