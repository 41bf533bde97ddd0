// Full check of a point store (.mlc; meshless verify): header, index and footer (PointStore::open),
// then every brick is read, its CRC and size checked, its points decoded and checked against the
// index (formats/point_store_format.hpp check_point_brick: Morton keys inside its cell and in order,
// exact bounds and value range), and the header's totals against the bricks' (bounds, value range).
// Reports the first bad brick. Memory: one brick (at most 2^20 points). Never throws for damage (it
// is the result); IoError when the file cannot be read at all.
// Thread-safety: reentrant.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace meshless {

struct PointStoreVerifyReport {
    bool ok = false;
    std::uint64_t bricks_checked = 0, points_checked = 0;
    std::optional<std::uint64_t> first_bad_brick;
    std::string message;  ///< one line: "ok: N points in M bricks" or what is wrong and where
};

/// `progress`, when given, is called after each brick with (bricks checked, bricks in the store).
PointStoreVerifyReport verify_point_store(const std::string& path,
                                          const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});

}  // namespace meshless
