// Hardy's multiquadric interpolant with a linear polynomial (dissertation section 2.1.1, Eq. for
// H(x)), used globally (kernels/global_rbf_field.hpp) and as the local interpolant of the RBF grid
// (section 4.3) and the MPU octree (section 5.5):
//
//     H(x) = a0 + a.(x - o) + sum_i lambda_i sqrt(|x - p_i|^2 + c^2),
//     H(p_i) = f_i,   sum_i lambda_i = 0,   sum_i lambda_i p_i = 0   (side conditions),
//
// so every linear function is reproduced exactly. Units: positions and c in the caller's frame
// (world units, usually shifted by a field origin), values in data units, gradient per world unit.
//
// Solve (MultiquadricSolver::fit): the points are centred on their mean and scaled by their radius
// L for conditioning; the side conditions are eliminated with a column-pivoted QR of the polynomial
// matrix P = [1 q] (null-space method), leaving a symmetric positive definite system (the
// multiquadric is conditionally negative definite of order 1) solved by Cholesky (LLT). Outcomes:
//   interpolated      exact solve: Cholesky succeeds, the interpolation residual is <= 1e-8 of the
//                     data range, and sum|lambda_i| * max phi <= 1e8 x the data range (so evaluating
//                     H cancels away at most ~1e-8 of the range: ill-conditioning that amplifies
//                     rounding noise shows up as large cancelling coefficients)
//   regularised       ridge eps*I added to the reduced system (eps = 1e-12 .. 1e-4 of its mean
//                     diagonal, the first with rcond >= 1e-10 passing the same coefficient
//                     bound): approximates, still
//                     reproduces linear functions (exactly when the data is linear to rounding,
//                     which is detected first and fitted by the polynomial alone)
//   linear_fallback   no ridge helped: lambda = 0, least-squares linear fit
//   polynomial_only   fewer points than polynomial terms of the affine hull (1-3 points): least
//                     squares constant/linear fit (exact through the points when they are independent)
// Collinear/coplanar points make P rank-deficient (poly_rank < 4): the polynomial is the basic
// least-squares solution over the points' affine hull (no slope across it) and the RBF part is
// solved on the remaining null space, so data on a line/plane is still interpolated. Never
// returns NaN for finite input.
//
// Speed: the fit runs in the AVX2 + FMA build of kernels/multiquadric_fit_isa.hpp where the CPU
// has both (chosen once per process), else in the generic one.
//
// Thread-safety: MultiquadricSolver holds scratch matrices, use one per thread. Evaluation is a
// pure function. Throws only std::bad_alloc.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>

#include "kernels/vec3.hpp"

namespace meshless {

/// One fitted interpolant. Its lambda_i and point indices live in the owner's arrays at
/// [first, first + count); count == 0 means the polynomial part only.
struct MultiquadricLocal {
    Vec3 origin;                 ///< o: mean of its points (caller's frame)
    double a0 = 0;               ///< value at o of the polynomial part
    Vec3 a;                      ///< gradient of the polynomial part, per world unit
    double c2 = 0;               ///< Hardy's c squared, world units^2
    std::uint32_t first = 0;     ///< start in the owner's index / lambda arrays
    std::uint32_t count = 0;     ///< number of RBF terms
};

enum class MultiquadricOutcome : std::uint8_t { interpolated, regularised, linear_fallback, polynomial_only };

struct MultiquadricFitResult {
    MultiquadricOutcome outcome = MultiquadricOutcome::interpolated;
    int poly_rank = 4;           ///< rank of [1 q]: 4 general, 3 coplanar, 2 collinear, 1 one point
    double rcond = 0;            ///< reciprocal condition estimate of the ridge system (0 unless regularised)
    /// RMS leave-one-out error (data units, Rippa's formula e_k = lambda_k / (M^-1)_kk over the
    /// augmented system M), when asked and the fit has an RBF part (interpolated or regularised); else -1.
    double loo = -1;
};

class MultiquadricSolver {
public:
    MultiquadricSolver();
    /// Tests: a solver running build `isa` ("generic" or "avx2") of the fit; precondition:
    /// multiquadric_fit_isa_available(isa).
    explicit MultiquadricSolver(std::string_view isa);
    ~MultiquadricSolver();
    MultiquadricSolver(const MultiquadricSolver&) = delete;
    MultiquadricSolver& operator=(const MultiquadricSolver&) = delete;

    /// Fit H to the points pos[idx[k]] with values value[idx[k]], k < idx.size() (>= 1, distinct
    /// points, finite). c >= 0 in the frame's units. Writes lambda (lambda.size() == idx.size();
    /// only the first out.count entries are meaningful) and out (out.first is left as given).
    /// With leave_one_out, also the fit's leave-one-out error (costs about a second factorisation).
    MultiquadricFitResult fit(std::span<const Vec3> pos, std::span<const double> value,
                              std::span<const std::uint32_t> idx, double c, MultiquadricLocal& out,
                              std::span<double> lambda, bool leave_one_out = false);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

/// Which build of the fit this process runs (kernels/multiquadric_fit_isa.hpp): "avx2" or "generic".
const char* multiquadric_fit_isa();
/// Whether this build and CPU can run build `isa` of the fit ("generic" always).
bool multiquadric_fit_isa_available(std::string_view isa);

/// H(x) and, when grad != nullptr, its gradient. idx and lambda are the owner's full arrays.
inline double multiquadric_evaluate(const MultiquadricLocal& h, const Vec3* pos, const std::uint32_t* idx,
                                    const double* lambda, const Vec3& x, Vec3* grad) {
    const Vec3 dx = x - h.origin;
    double v = h.a0 + dot(h.a, dx);
    const std::uint32_t* id = idx + h.first;
    const double* lam = lambda + h.first;
    if (grad) {
        double gx = h.a.x, gy = h.a.y, gz = h.a.z;
        for (std::uint32_t k = 0; k < h.count; ++k) {
            const Vec3& p = pos[id[k]];
            const double ex = x.x - p.x, ey = x.y - p.y, ez = x.z - p.z;
            const double phi = std::sqrt(ex * ex + ey * ey + ez * ez + h.c2);
            v += lam[k] * phi;
            const double s = phi > 0 ? lam[k] / phi : 0.0;
            gx += s * ex;
            gy += s * ey;
            gz += s * ez;
        }
        *grad = {gx, gy, gz};
    } else {
        for (std::uint32_t k = 0; k < h.count; ++k) {
            const Vec3& p = pos[id[k]];
            const double ex = x.x - p.x, ey = x.y - p.y, ez = x.z - p.z;
            v += lam[k] * std::sqrt(ex * ex + ey * ey + ez * ez + h.c2);
        }
    }
    return v;
}

}  // namespace meshless
