#include "stream/stencil_seed_stage.hpp"

#include <cassert>
#include <chrono>

#include "kernels/barycentric_lattice.hpp"

namespace meshless {

StencilSeedStage::StencilSeedStage(const StencilInput& in, double iso, int n)
    : in_(in), iso_(iso), n_(n), lattice_(barycentric_lattice(n)) {}

void StencilSeedStage::process(Batch& b) const {
    const auto t0 = std::chrono::steady_clock::now();
    assert(b.kind == RecordKind::seed);
    b.seeds.clear();
    StencilSeedStats st;
    stencil_seeds(in_, iso_, n_, lattice_, b.cells.k0, b.cells.k1, b.seeds, st);
    const auto v = st.as_array();
    for (std::size_t i = 0; i < v.size(); ++i) {
        if (i == StencilSeedStats::kMaxIndex) {  // max_stencil_points: a maximum, not a sum
            std::int64_t cur = st_[i].load(std::memory_order_relaxed);
            while (v[i] > cur && !st_[i].compare_exchange_weak(cur, v[i], std::memory_order_relaxed)) {
            }
            continue;
        }
        st_[i].fetch_add(v[i], std::memory_order_relaxed);
    }
    busy_ns_ += std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count();
}

StencilSeedStats StencilSeedStage::stats() const {
    std::array<std::int64_t, StencilSeedStats::kCounters> v{};
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = st_[i].load();
    return StencilSeedStats::from_array(v);
}

}  // namespace meshless
