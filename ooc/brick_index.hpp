// Which bricks of a store hold part of an isosurface: an interval tree over the bricks' value
// ranges [vmin, vmax] (dissertation sections 2.3 and 3.6; only these bricks are ever read). A brick
// is active for iso when some sample is >= iso and some is < iso (vmin < iso <= vmax), the cell
// convention of kernels/cell_sampling.hpp. Built once per store; const queries are thread-safe.
#pragma once
#include <cstddef>
#include <vector>

#include "kernels/interval_tree.hpp"
#include "ooc/brick_store.hpp"

namespace meshless {

class BrickIndex {
public:
    explicit BrickIndex(const BrickStore& store);
    /// Indices (into store.bricks()) of the active bricks, ascending = Morton order.
    std::vector<std::size_t> active(double iso) const;

private:
    const BrickStore& store_;
    IntervalTree tree_;
};

}  // namespace meshless
