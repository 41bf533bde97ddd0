// A cluster's centre, value and error (dissertation section 6.3):
//     p_c = (1/|C|) sum_{j in C} p_j,
//     f_c = H(p_c), H the local multiquadric (kernels/multiquadric.hpp, linear polynomial part)
//           through the N = min(|C|, k) samples of C nearest p_c,
//     sigma_c = max_{j in C} |f_j - f_c|;
// or, for CbtValueKind::mean, f_c = the mean of the f_j (no fit, no neighbour search).
// The N nearest are the N smallest (|p_j - p_c|^2, j) pairs (ties broken by sample number, so the
// choice does not depend on the order of idx); of samples at one exact position only the first
// (lowest number) enters the fit (the multiquadric needs distinct points). A fit that is not
// finite (it never is for finite input) falls back to the mean value of the N samples.
// Sums and selections over clusters of chunks::kParallelItems samples or more run in fixed chunks
// on oneTBB (kernels/fixed_chunks.hpp): the result has the same bits for any thread count.
// Units: world positions, Hardy's c in world units, data-unit values.
// Thread-safety: one ClusterValueEvaluator per thread (it holds scratch); evaluate() may itself
// run oneTBB tasks. Throws only std::bad_alloc.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "kernels/cluster_tree.hpp"
#include "kernels/multiquadric.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct ClusterValue {
    Vec3 centre;            ///< p_c
    double mean_value = 0;  ///< mean of the f_j (the PCA's centre in value)
    double value = 0;       ///< f_c
    double error = 0;       ///< sigma_c
};

class ClusterValueEvaluator {
public:
    /// k >= 1 neighbours, Hardy's c >= 0 in world units (both unused for CbtValueKind::mean).
    ClusterValueEvaluator(std::uint32_t k, double hardy_c, CbtValueKind kind = CbtValueKind::fit)
        : k_(k), c_(hardy_c), kind_(kind) {}
    /// The values of the cluster idx[*] (>= 1 sample).
    ClusterValue evaluate(std::span<const Vec3> pos, std::span<const double> value, std::span<const std::uint32_t> idx);
    /// The sample numbers the fit used for the last evaluate() (tests), nearest first; empty for the mean.
    const std::vector<std::uint32_t>& last_neighbours() const { return sel_; }

private:
    std::uint32_t k_;
    double c_;
    CbtValueKind kind_;
    MultiquadricSolver solver_;
    std::vector<std::pair<double, std::uint32_t>> cand_;
    std::vector<std::uint32_t> sel_;
    std::vector<double> lambda_;
};

}  // namespace meshless
