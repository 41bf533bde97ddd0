// Wall-clock seconds since a steady_clock time point, for the timing fields of the recipes'
// statistics and the front ends' --stats lines (seconds, double). Throws nothing; thread-safe.
#pragma once
#include <chrono>

namespace meshless {

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace meshless
