#include "kernels/interval_tree.hpp"

#include <algorithm>
#include <cmath>

namespace meshless {

IntervalTree::IntervalTree(std::vector<Interval> intervals) {
    intervals.erase(std::remove_if(intervals.begin(), intervals.end(),
                                   [](const Interval& i) { return !(i.lo <= i.hi); }),
                    intervals.end());
    size_ = intervals.size();
    by_lo_.reserve(size_);
    by_hi_.reserve(size_);
    root_ = build(intervals, 0);
}

std::int32_t IntervalTree::build(std::vector<Interval>& items, std::size_t depth) {
    if (items.empty()) return -1;
    // centre: median of the endpoints, so each side holds at most half of the intervals
    std::vector<double> ends;
    ends.reserve(2 * items.size());
    for (const auto& i : items) {
        ends.push_back(i.lo);
        ends.push_back(i.hi);
    }
    std::nth_element(ends.begin(), ends.begin() + ends.size() / 2, ends.end());
    const double c = ends[ends.size() / 2];
    std::vector<Interval> left, right, here;
    for (const auto& i : items) {
        if (i.hi < c) left.push_back(i);
        else if (i.lo > c) right.push_back(i);
        else here.push_back(i);
    }
    items.clear();
    items.shrink_to_fit();
    const auto idx = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back(Node{});
    Node n;
    n.centre = c;
    n.begin = static_cast<std::uint32_t>(by_lo_.size());
    std::sort(here.begin(), here.end(), [](const Interval& a, const Interval& b) {
        return a.lo < b.lo || (a.lo == b.lo && a.id < b.id);
    });
    by_lo_.insert(by_lo_.end(), here.begin(), here.end());
    std::sort(here.begin(), here.end(), [](const Interval& a, const Interval& b) {
        return a.hi > b.hi || (a.hi == b.hi && a.id < b.id);
    });
    by_hi_.insert(by_hi_.end(), here.begin(), here.end());
    n.end = static_cast<std::uint32_t>(by_lo_.size());
    n.left = build(left, depth + 1);
    n.right = build(right, depth + 1);
    nodes_[idx] = n;
    return idx;
}

void IntervalTree::stab(double v, std::vector<std::uint64_t>& out) const {
    std::int32_t at = root_;
    while (at >= 0) {
        const Node& n = nodes_[at];
        if (v <= n.centre) {
            // every interval here has hi >= centre >= v: it contains v iff lo <= v
            for (std::uint32_t i = n.begin; i < n.end && by_lo_[i].lo <= v; ++i) out.push_back(by_lo_[i].id);
            if (v == n.centre) return;  // the other sides hold intervals entirely below/above v
            at = n.left;
        } else {
            // every interval here has lo <= centre < v: it contains v iff hi >= v
            for (std::uint32_t i = n.begin; i < n.end && by_hi_[i].hi >= v; ++i) out.push_back(by_hi_[i].id);
            at = n.right;
        }
    }
}

std::vector<std::uint64_t> IntervalTree::stab(double v) const {
    std::vector<std::uint64_t> out;
    stab(v, out);
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace meshless
