// The MPU local fits (dissertation section 5.5) that one region build of the field leaves to the
// next (docs/architecture.md, "Fields out of core"). Neighbouring regions answer for query boxes
// that overlap by the Newton reach and a few fit spheres, so both builds fit the leaves there. A
// leaf's fit depends only on its point list (positions and values, in order), Hardy's c and the
// field parameters: a later build of the same run (same frame, same parameters) whose leaf has the
// same cube and a bit-identical list copies the kept fit instead of solving it again, so the field
// keeps its bits.
//
// A leaf is known by its octree cube (frame units) and two independent 64-bit hashes of its list's
// bits with the list's length: a lookup that matches all of them is taken as the same list (two
// different lists agree on 128 hash bits with probability ~2^-128).
//
// Use, per region: begin(keep_z) before the build (the build looks fits up among those kept
// by the previous region and keeps, for the next one, every leaf whose blend sphere rises to world
// z >= keep_z; regions taken from the top down keep those reaching down to z <= keep_z); advance() once the region's build is final (what it kept
// becomes what the next build finds; the previous region's fits are freed). A build that is
// started again (a wider halo) calls begin() again first. Not thread-safe, except find(), which
// may run on many threads while nothing else runs. Throws only std::bad_alloc.
#pragma once
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "kernels/multiquadric.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

class MpuFitCache {
public:
    struct Key {
        Vec3 c;             ///< the leaf cube's centre (frame units)
        double half = 0;    ///< its half edge (frame units)
        std::uint32_t count = 0;  ///< the list's length
        std::uint64_t h1 = 0, h2 = 0;  ///< hashes of the list's positions and values
        bool operator==(const Key& o) const;
    };
    /// A fit as MpuField keeps it: the local (its `first` is the owner's), its lambdas (count),
    /// the solver's outcome and MpuField's rank/refit bits.
    struct Fit {
        MultiquadricLocal local;
        std::vector<double> lambda;
        MultiquadricOutcome outcome = MultiquadricOutcome::interpolated;
        std::uint8_t flags = 0;
    };

    /// The key of the leaf cube (c, half) fitting the points pos[i], value[i] for i in idx, in order.
    static Key key_of(const Vec3& c, double half, std::span<const Vec3> pos, std::span<const double> value,
                      std::span<const std::uint32_t> idx);

    /// Starts a build that keeps the leaves rising to world z >= keep_z (world units), or with
    /// `falling` (regions taken from the top down) those reaching down to z <= keep_z; clears what a
    /// previous start of the same region kept.
    void begin(double keep_z, bool falling = false);
    /// Whether the current build keeps a leaf whose blend sphere spans world z = [bottom, top].
    bool keeps(double bottom, double top) const { return falling_ ? bottom <= keep_z_ : top >= keep_z_; }
    /// The fit kept by the previous region under `key`, or null.
    const Fit* find(const Key& key) const;
    /// Keeps a fit for the next region.
    void keep(const Key& key, Fit fit);
    /// The current build is final: its kept fits become the ones find() sees.
    void advance();
    /// Forgets every fit (a region that cannot afford them builds without).
    void clear();
    /// Heap bytes held (both generations; an estimate of the allocator's share).
    std::uint64_t bytes() const { return bytes_found_ + bytes_kept_; }
    /// Lookups that found a fit, over the cache's life.
    std::uint64_t hits() const { return hits_; }
    void count_hits(std::uint64_t n) { hits_ += n; }

private:
    struct Hash {
        std::size_t operator()(const Key& k) const { return static_cast<std::size_t>(k.h1 ^ (k.h2 >> 1)); }
    };
    std::unordered_map<Key, Fit, Hash> found_, kept_;
    std::uint64_t bytes_found_ = 0, bytes_kept_ = 0, hits_ = 0;
    double keep_z_ = 0;
    bool falling_ = false;
};

}  // namespace meshless
