// A static centred interval tree (Edelsbrunner; the active-cell index of dissertation sections 2.3
// and 3.6): built once over closed intervals [lo, hi] with ids, answers stabbing queries "which
// intervals contain v" in O(log n + k). Used over bricks (ooc/) and anywhere a value interval index
// is needed. Thread-safety: const methods may run concurrently. Throws std::bad_alloc only.
#pragma once
#include <cstdint>
#include <vector>

namespace meshless {

struct Interval {
    double lo = 0, hi = 0;  ///< closed interval, lo <= hi (NaN intervals are ignored at build)
    std::uint64_t id = 0;
};

class IntervalTree {
public:
    IntervalTree() = default;
    explicit IntervalTree(std::vector<Interval> intervals);
    /// Ids of the intervals with lo <= v <= hi, ascending.
    std::vector<std::uint64_t> stab(double v) const;
    /// Same, appended to out in tree order (unsorted), for callers that sort or do not care.
    void stab(double v, std::vector<std::uint64_t>& out) const;
    std::size_t size() const { return size_; }

private:
    struct Node {
        double centre = 0;
        std::uint32_t begin = 0, end = 0;  ///< range in by_lo_ / by_hi_
        std::int32_t left = -1, right = -1;
    };
    std::int32_t build(std::vector<Interval>& items, std::size_t depth);
    std::vector<Node> nodes_;
    std::vector<Interval> by_lo_;  ///< per node: intervals straddling the centre, ascending lo
    std::vector<Interval> by_hi_;  ///< per node: the same, descending hi
    std::int32_t root_ = -1;
    std::size_t size_ = 0;
};

}  // namespace meshless
