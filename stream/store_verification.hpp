// The store check recipe, what `meshless verify` runs on each store (and any other front end): a
// brick store (.mlb, ooc/verify_brick_store.hpp; dissertation section 3.6), a sample store (.mls,
// paradigm A, ooc/sample_store.hpp; section 3.5) or a point store (.mlc, ooc/verify_point_store.hpp)
// checked completely, the result one line and an exit status.
// Units: bytes (the brick budget).
// Damage is the result, not an exception; throws IoError when a brick or point store cannot be read
// at all (as the checkers do).
#pragma once
#include <cstdio>
#include <cstdint>
#include <functional>
#include <string>

namespace meshless {

/// The kinds of store verify_store checks.
enum class StoreKind { brick, sample, point };

/// A point store by content or by its .mlc name, else a sample store by content, else a brick store.
StoreKind verified_store_kind(const std::string& path);

struct StoreVerdict {
    /// 0: sound; 1: a brick store whose bricks exceed the budget (not read); 2: damaged.
    int status = 0;
    std::string message;  ///< one line: "ok: ..." or what is wrong (not escaped for a terminal)
};

/// Checks the store at `path` as `kind`. budget_bytes: the most one decompressed brick of a brick
/// store may take. `progress`, when given, is called after each brick of a brick or point store with
/// (bricks checked, bricks in the store); a sample store reports no progress.
StoreVerdict verify_store(const std::string& path, StoreKind kind, std::uint64_t budget_bytes,
                          const std::function<void(std::uint64_t, std::uint64_t)>& progress = {});

/// The line of one verdict: "ok: ..." on `out` (prefixed "PATH: " when several stores are checked),
/// or the damage on `err` prefixed "meshless verify: " (`out` flushed first, so a log of both streams
/// keeps the order).
void print_store_verdict(std::FILE* out, std::FILE* err, const std::string& path, const StoreVerdict& v, bool several);

}  // namespace meshless
