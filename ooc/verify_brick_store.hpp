// Full check of a brick store (meshless verify): header, index and footer, then every brick is read
// and decompressed, its CRC, size and value range compared with the index. Reports the first bad
// brick by index and voxel range. Never throws for damage (it is the result); IoError when the file
// cannot be read at all.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

namespace meshless {

struct VerifyReport {
    bool ok = false;
    std::uint64_t bricks_checked = 0;
    std::optional<std::uint64_t> first_bad_brick;
    std::string message;  ///< one line: "ok: N bricks" or what is wrong and where
    bool over_budget = false;  ///< not read: its bricks exceed the memory budget (not damage)
};

/// `progress`, when given, is called after each brick with (bricks checked, bricks in the store).
/// budget_bytes: the most one decompressed brick may take (meshless verify --memory, as the brick
/// cache of the other commands): a store whose index gives bigger bricks is not read (the report
/// says so; a 33 KB file of compressible 1025^3 bricks would otherwise take 1 GB).
VerifyReport verify_brick_store(const std::string& path, std::uint64_t budget_bytes,
                                const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});

}  // namespace meshless
