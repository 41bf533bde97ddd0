// Removing near-duplicate surface points (--dedup; dissertation section 4.6: points
// seeded twice where local meshes overlap project onto the same surface, so one of each close pair
// can go). Greedy in arrival order: a point is kept unless a kept point lies closer than
// fraction x its own radius; kept points are remembered in a hash grid of edge `cell` (world units),
// so the result depends only on the order of the points (the stage graph's sequence order).
// Memory: 32 bytes per kept point (the output's size, not the input's). Units: world.
// Not thread-safe (one instance per ordered stream). Throws InvalidArgument for fraction < 0 or a
// cell that is not finite and positive; std::bad_alloc.
#pragma once
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

class PointDedup {
public:
    PointDedup(double fraction, double cell);
    /// True (and p remembered) when no kept point is closer than fraction x radius to p.
    bool keep(const Vec3& p, double radius);
    std::int64_t kept() const { return static_cast<std::int64_t>(pts_.size()); }
    std::int64_t removed() const { return removed_; }

private:
    double fraction_, cell_;
    std::vector<Vec3> pts_;
    std::vector<std::uint32_t> next_;
    std::unordered_map<std::uint64_t, std::uint32_t> head_;
    std::int64_t removed_ = 0;
};

}  // namespace meshless
