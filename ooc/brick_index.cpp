#include "ooc/brick_index.hpp"

#include <algorithm>

namespace meshless {

namespace {
std::vector<Interval> brick_intervals(const BrickStore& s) {
    std::vector<Interval> iv;
    iv.reserve(s.bricks().size());
    for (std::size_t i = 0; i < s.bricks().size(); ++i)
        iv.push_back({s.bricks()[i].vmin, s.bricks()[i].vmax, i});  // NaN ranges are dropped by the tree
    return iv;
}
}  // namespace

BrickIndex::BrickIndex(const BrickStore& store) : store_(store), tree_(brick_intervals(store)) {}

std::vector<std::size_t> BrickIndex::active(double iso) const {
    std::vector<std::uint64_t> hits;
    tree_.stab(iso, hits);
    std::vector<std::size_t> out;
    out.reserve(hits.size());
    for (std::uint64_t h : hits)
        if (store_.bricks()[h].vmin < iso) out.push_back(static_cast<std::size_t>(h));
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace meshless
