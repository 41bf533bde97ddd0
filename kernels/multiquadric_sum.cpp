#include "kernels/multiquadric_sum.hpp"

#include <immintrin.h>

// GCC 12 reports its own AVX-512 intrinsics (_mm512_reduce_add_pd, masked loads) as reading an
// uninitialised variable (a known false positive of the headers' _mm512_undefined_pd()).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"

#include <cmath>

namespace meshless {
namespace {

using SumFn = void (*)(const double*, const double*, const double*, const MqRun*, std::size_t, const double*, double,
                       const Vec3&, bool, MqSum&);

void sum_scalar(const double* px, const double* py, const double* pz, const MqRun* runs, std::size_t nruns,
                const double* lam, double c2, const Vec3& x, bool grad, MqSum& out) {
    double v = 0, gx = 0, gy = 0, gz = 0;
    for (std::size_t r = 0; r < nruns; ++r)
    for (std::size_t k = runs[r].start, e = runs[r].start + runs[r].count; k < e; ++k, ++lam) {
        const double ex = x.x - px[k], ey = x.y - py[k], ez = x.z - pz[k];
        const double phi = std::sqrt(ex * ex + ey * ey + ez * ez + c2);
        v += *lam * phi;
        if (grad) {
            const double s = phi > 0 ? *lam / phi : 0.0;
            gx += s * ex;
            gy += s * ey;
            gz += s * ez;
        }
    }
    out.v += v;
    out.gx += gx;
    out.gy += gy;
    out.gz += gz;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define MESHLESS_MQ_X86 1

__attribute__((target("avx2,fma"))) inline double hsum4(__m256d a) {
    const __m128d lo = _mm256_castpd256_pd128(a), hi = _mm256_extractf128_pd(a, 1);
    const __m128d s = _mm_add_pd(lo, hi);
    return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
}

__attribute__((target("avx2,fma"))) void sum_avx2(const double* px, const double* py, const double* pz,
                                                  const MqRun* runs, std::size_t nruns, const double* lam, double c2,
                                                  const Vec3& x, bool grad, MqSum& out) {
    const __m256d X = _mm256_set1_pd(x.x), Y = _mm256_set1_pd(x.y), Z = _mm256_set1_pd(x.z), C2 = _mm256_set1_pd(c2);
    const __m256d zero = _mm256_setzero_pd();
    __m256d v = zero, gx = zero, gy = zero, gz = zero;
    MqSum tail;
    for (std::size_t r = 0; r < nruns; ++r) {
    const std::size_t n = runs[r].start + runs[r].count;
    std::size_t k = runs[r].start;
    for (; k + 4 <= n; k += 4, lam += 4) {
        const __m256d ex = _mm256_sub_pd(X, _mm256_loadu_pd(px + k));
        const __m256d ey = _mm256_sub_pd(Y, _mm256_loadu_pd(py + k));
        const __m256d ez = _mm256_sub_pd(Z, _mm256_loadu_pd(pz + k));
        const __m256d r2 = _mm256_fmadd_pd(ex, ex, _mm256_fmadd_pd(ey, ey, _mm256_fmadd_pd(ez, ez, C2)));
        const __m256d phi = _mm256_sqrt_pd(r2);
        const __m256d l = _mm256_loadu_pd(lam);
        v = _mm256_fmadd_pd(l, phi, v);
        if (grad) {
            const __m256d pos = _mm256_cmp_pd(phi, zero, _CMP_GT_OQ);
            const __m256d s = _mm256_and_pd(_mm256_div_pd(l, phi), pos);
            gx = _mm256_fmadd_pd(s, ex, gx);
            gy = _mm256_fmadd_pd(s, ey, gy);
            gz = _mm256_fmadd_pd(s, ez, gz);
        }
    }
    const MqRun rest{static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(n - k)};
    sum_scalar(px, py, pz, &rest, 1, lam, c2, x, grad, tail);
    lam += n - k;
    }
    out.v += hsum4(v) + tail.v;
    if (grad) {
        out.gx += hsum4(gx) + tail.gx;
        out.gy += hsum4(gy) + tail.gy;
        out.gz += hsum4(gz) + tail.gz;
    }
}

__attribute__((target("avx512f,avx512vl,avx512dq,fma"))) void sum_avx512(const double* px, const double* py,
                                                                         const double* pz, const MqRun* runs,
                                                                         std::size_t nruns, const double* lam, double c2,
                                                                         const Vec3& x, bool grad, MqSum& out) {
    const __m512d X = _mm512_set1_pd(x.x), Y = _mm512_set1_pd(x.y), Z = _mm512_set1_pd(x.z), C2 = _mm512_set1_pd(c2);
    const __m512d zero = _mm512_setzero_pd(), half = _mm512_set1_pd(0.5), threehalf = _mm512_set1_pd(1.5);
    __m512d v = zero, gx = zero, gy = zero, gz = zero;
    for (std::size_t r = 0; r < nruns; ++r) {
    const std::size_t n = runs[r].start + runs[r].count;
    for (std::size_t k = runs[r].start; k < n; k += 8, lam += 8) {
        const __mmask8 m = n - k >= 8 ? __mmask8(0xFF) : static_cast<__mmask8>((1u << (n - k)) - 1u);
        const __m512d ex = _mm512_sub_pd(X, _mm512_maskz_loadu_pd(m, px + k));
        const __m512d ey = _mm512_sub_pd(Y, _mm512_maskz_loadu_pd(m, py + k));
        const __m512d ez = _mm512_sub_pd(Z, _mm512_maskz_loadu_pd(m, pz + k));
        const __m512d r2 = _mm512_fmadd_pd(ex, ex, _mm512_fmadd_pd(ey, ey, _mm512_fmadd_pd(ez, ez, C2)));
        // y = 1/sqrt(r2): 14-bit estimate, two Newton steps (error ~ 2^-56 + a few ulp)
        __m512d y = _mm512_rsqrt14_pd(r2);
        const __m512d hr2 = _mm512_mul_pd(half, r2);
        y = _mm512_mul_pd(y, _mm512_fnmadd_pd(hr2, _mm512_mul_pd(y, y), threehalf));
        y = _mm512_mul_pd(y, _mm512_fnmadd_pd(hr2, _mm512_mul_pd(y, y), threehalf));
        const __mmask8 pos = _mm512_mask_cmp_pd_mask(m, r2, zero, _CMP_GT_OQ);  // r2 == 0: phi = 0, no slope
        const __m512d phi = _mm512_maskz_mul_pd(pos, r2, y);
        const __m512d l = _mm512_maskz_loadu_pd(m, lam);  // 0 in the masked-off lanes
        v = _mm512_fmadd_pd(l, phi, v);
        if (grad) {
            const __m512d s = _mm512_maskz_mul_pd(pos, l, y);
            gx = _mm512_fmadd_pd(s, ex, gx);
            gy = _mm512_fmadd_pd(s, ey, gy);
            gz = _mm512_fmadd_pd(s, ez, gz);
        }
    }
    lam -= (8 - (runs[r].count % 8)) % 8;  // the last step went past the run's end
    }
    out.v += _mm512_reduce_add_pd(v);
    if (grad) {
        out.gx += _mm512_reduce_add_pd(gx);
        out.gy += _mm512_reduce_add_pd(gy);
        out.gz += _mm512_reduce_add_pd(gz);
    }
}
#endif

struct Choice {
    SumFn fn;
    const char* name;
};

Choice choose() {
#ifdef MESHLESS_MQ_X86
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq"))
        return {sum_avx512, "avx512"};
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return {sum_avx2, "avx2"};
#endif
    return {sum_scalar, "scalar"};
}

const Choice& chosen() {
    static const Choice c = choose();  // thread-safe initialisation, once per process
    return c;
}

}  // namespace

void multiquadric_sum(const double* px, const double* py, const double* pz, std::span<const MqRun> runs,
                      const double* lambda, double c2, const Vec3& x, bool grad, MqSum& out) {
    chosen().fn(px, py, pz, runs.data(), runs.size(), lambda, c2, x, grad, out);
}

const char* multiquadric_sum_isa() { return chosen().name; }

bool multiquadric_sum_isa_available(std::string_view isa) {
    if (isa == "scalar") return true;
#ifdef MESHLESS_MQ_X86
    __builtin_cpu_init();
    if (isa == "avx2") return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    if (isa == "avx512")
        return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512dq");
#endif
    return false;
}

void multiquadric_sum_with(std::string_view isa, const double* px, const double* py, const double* pz,
                           std::span<const MqRun> runs, const double* lambda, double c2, const Vec3& x, bool grad,
                           MqSum& out) {
    SumFn fn = sum_scalar;
#ifdef MESHLESS_MQ_X86
    if (isa == "avx2") fn = sum_avx2;
    if (isa == "avx512") fn = sum_avx512;
#endif
    fn(px, py, pz, runs.data(), runs.size(), lambda, c2, x, grad, out);
}

}  // namespace meshless
