// The inner loop of every local multiquadric (dissertation section 2.1.1): the sum
//     v = sum_k lambda_k sqrt(|x - p_k|^2 + c^2),   g = sum_k lambda_k (x - p_k) / sqrt(|x - p_k|^2 + c^2)
// over a run of centres stored structure-of-arrays (px, py, pz, lambda contiguous), as the RBF-grid
// (section 4.3) and MPU (section 5.5) fields evaluate their locals. A term with sqrt(...) == 0
// (c == 0 at a centre) adds nothing to g, as in multiquadric_evaluate().
//
// SIMD: the sum runs 8 (AVX-512) or 4 (AVX2 + FMA) lanes wide where the CPU has them, chosen once
// per process with __builtin_cpu_supports; otherwise a plain loop. The lanes are reduced in a fixed
// order, so on one machine the result is deterministic (independent of threads, batch sizes and
// call order); it differs from a scalar left-to-right sum by rounding only (~1e-16 relative to
// sum |lambda_k| phi_k). AVX2 takes phi = sqrt(r^2 + c^2) and the gradient's weight lambda / phi
// with the correctly rounded vsqrtpd and vdivpd, whole groups of four centres with plain loads and
// each run's tail masked: on AMD Zen 3 that runs at ~1.2 ns a term, twice the rate of a float
// vrsqrtps estimate refined by a Taylor step (a chain of ~50 cycles a group, which the out-of-order
// window could not overlap enough). The AVX-512 path computes no square root nor division: y =
// 1/sqrt(r^2 + c^2) starts from vrsqrt14pd (relative error <= 2^-14) and is refined by one step of
// the Taylor series of (1 - e)^(-1/2), e = 1 - r^2 y0^2, to the 3rd degree (35/128 e^4 <= 6e-17
// truncation), then phi = r^2 y and the gradient's weight lambda y (the 512-bit square root and
// division are slow on the CPUs that have AVX-512). Units: those of the caller (frame
// coordinates, data units).
// Thread-safety: pure functions. Throws nothing.
#pragma once
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "kernels/vec3.hpp"

namespace meshless {

/// Running sums of one local's multiquadric terms (value and gradient).
struct MqSum {
    double v = 0, gx = 0, gy = 0, gz = 0;
};

/// A run of consecutive centres [start, start + count) of the px/py/pz arrays.
struct MqRun {
    std::uint32_t start = 0, count = 0;
};

/// Adds the terms of the centres of `runs` (in order; p = {px[i], py[i], pz[i]}) with the
/// coefficients lambda[0], lambda[1], ... (one per centre, consecutive across runs) at x to out.
/// c2 = c^2 >= 0. With grad == false only out.v changes. Arrays need not be aligned or padded.
void multiquadric_sum(const double* px, const double* py, const double* pz, std::span<const MqRun> runs,
                      const double* lambda, double c2, const Vec3& x, bool grad, MqSum& out);

/// One local's terms for multiquadric_sums(): runs[0 .. nruns) of the px/py/pz arrays with the
/// coefficients lambda[0], lambda[1], ... (consecutive across runs), c2 = c^2 >= 0.
struct MqLocalTerms {
    const MqRun* runs = nullptr;
    std::uint32_t nruns = 0;
    const double* lambda = nullptr;
    double c2 = 0;
};

/// out[i] = the sums of locals[i] at x (out[i] is overwritten, not added to), for every i: the
/// same bits as multiquadric_sum() into a zeroed MqSum, one dispatch for all the locals a query
/// blends. With grad == false only out[i].v is set (the gradients are left unspecified).
void multiquadric_sums(const double* px, const double* py, const double* pz, std::span<const MqLocalTerms> locals,
                       const Vec3& x, bool grad, MqSum* out);

/// Which implementation multiquadric_sum() uses on this machine: "avx512", "avx2" or "scalar".
const char* multiquadric_sum_isa();
/// Tests: whether this CPU can run implementation `isa`, and multiquadric_sum() through it
/// (precondition: multiquadric_sum_isa_available(isa)).
bool multiquadric_sum_isa_available(std::string_view isa);
void multiquadric_sum_with(std::string_view isa, const double* px, const double* py, const double* pz,
                           std::span<const MqRun> runs, const double* lambda, double c2, const Vec3& x, bool grad,
                           MqSum& out);

}  // namespace meshless
