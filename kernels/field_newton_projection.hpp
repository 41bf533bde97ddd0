// Newton projection onto the isosurface f = iso of any Field (docs/architecture.md "What the graph carries":
// the one projector chapters 4, 5 and 7 share). It iterates the step of dissertation section 3.3.2,
// Eq. 3.5,
//   p' = p + lambda * (iso - f(p)) / (grad f(p) . grad f(p)) * grad f(p),
// to a tolerance, safeguarded:
//   - step halving: a step whose |f(p') - iso| is not smaller than |f(p) - iso| (or is not finite)
//     is retried with lambda halved, at most `max_halvings` times in a row (then `stalled`);
//     an accepted step resets lambda to 1;
//   - a maximum displacement: a candidate farther than max_displacement from the seed ends the
//     point as `too_far` (the displacement criterion of Fig. 3.3, generalised);
//   - a maximum number of field evaluations per point after the first (`max_iterations`; then
//     `not_converged`).
// Convergence: |f(p) - iso| <= tolerance * |grad f(p)|, i.e. the first-order distance to the
// surface is at most `tolerance` world units. A zero gradient ends the point as `flat`, a NaN/Inf
// value or gradient at the seed as `nonfinite`. Non-convergence is a counted result, never an
// exception.
//
// Evaluation is batched: each round evaluates the candidates of every point still iterating with
// one Field::evaluate call (value and gradient), so a batch of n seeds costs about
// (1 + rounds) virtual calls, not n * rounds.
//
// Units: positions, tolerance and displacements in world units; values in the field's units.
// Thread-safety: reentrant; the Field must be thread-safe (Field's contract). Allocates scratch
// proportional to the number of seeds. Throws only std::bad_alloc.
#pragma once
#include <cstdint>
#include <limits>
#include <span>

#include "kernels/field.hpp"

namespace meshless {

struct FieldNewtonParams {
    double tolerance = 1e-5;  ///< world units: stop when |f - iso| / |grad f| <= tolerance
    int max_iterations = 20;  ///< field evaluations per point after the seed's (halvings count)
    int max_halvings = 12;    ///< consecutive step halvings before a point is `stalled`
    double max_displacement = std::numeric_limits<double>::infinity();  ///< world units from the seed
    /// On convergence, also take the last step p' = p - (f - iso) grad / |grad|^2 (at most `tolerance`
    /// long) without a further evaluation: pos is p', grad stays the gradient at p. Newton's quadratic
    /// convergence leaves p' much nearer the surface than the tolerance; off: pos is p.
    bool final_step = false;
};

enum class FieldNewtonStatus : std::uint8_t { converged, flat, too_far, not_converged, stalled, nonfinite };

struct FieldNewtonStats {
    std::int64_t input = 0;          ///< seeds
    std::int64_t converged = 0;      ///< points on the surface within tolerance
    std::int64_t flat = 0;           ///< zero gradient before convergence
    std::int64_t too_far = 0;        ///< would move farther than max_displacement from the seed
    std::int64_t not_converged = 0;  ///< max_iterations reached
    std::int64_t stalled = 0;        ///< max_halvings consecutive halvings without decrease
    std::int64_t nonfinite = 0;      ///< NaN/Inf value or gradient at the seed
    std::int64_t evaluations = 0;    ///< points evaluated in total (seeds included)
    std::int64_t dropped() const { return flat + too_far + not_converged + stalled + nonfinite; }
    FieldNewtonStats& operator+=(const FieldNewtonStats& o) {
        input += o.input; converged += o.converged; flat += o.flat; too_far += o.too_far;
        not_converged += o.not_converged; stalled += o.stalled; nonfinite += o.nonfinite;
        evaluations += o.evaluations;
        return *this;
    }
};

/// Projects every seed. Outputs (each of size seeds.size()): pos[i] the last accepted position
/// (the surface point when converged), grad[i] the gradient there, status[i] why it stopped.
/// max_displacement, when not empty (size seeds.size()), is a per-seed limit used instead of
/// params.max_displacement (the smaller of the two is NOT taken: the span wins); likewise
/// tolerance, when not empty, is a per-seed tolerance used instead of params.tolerance (the
/// multiblock seeds' tolerance is relative to their cell's size, section 4.4).
/// Adds the counts to `stats`.
void project_onto_field(const Field& f, double iso, std::span<const Vec3> seeds, const FieldNewtonParams& params,
                        std::span<const double> max_displacement, std::span<Vec3> pos, std::span<Vec3> grad,
                        std::span<FieldNewtonStatus> status, FieldNewtonStats& stats,
                        std::span<const double> tolerance = {});

const char* to_string(FieldNewtonStatus s);

}  // namespace meshless
