#include "kernels/multiquadric_sum.hpp"

#include <immintrin.h>

// GCC 12 reports its own AVX-512 intrinsics (_mm512_reduce_add_pd, masked loads) as reading an
// uninitialised variable (a known false positive of the headers' _mm512_undefined_pd()).
#pragma GCC diagnostic ignored "-Wuninitialized"
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include <cmath>

namespace meshless {
namespace {

using SumsFn = void (*)(const double*, const double*, const double*, const MqLocalTerms*, std::size_t, const Vec3&,
                        bool, MqSum*);

// One local, plain loop (left to right); out is overwritten.
void local_scalar(const double* px, const double* py, const double* pz, const MqLocalTerms& L, const Vec3& x, bool grad,
                  MqSum& out) {
    double v = 0, gx = 0, gy = 0, gz = 0;
    const double* lam = L.lambda;
    for (std::size_t r = 0; r < L.nruns; ++r)
        for (std::size_t k = L.runs[r].start, e = L.runs[r].start + L.runs[r].count; k < e; ++k, ++lam) {
            const double ex = x.x - px[k], ey = x.y - py[k], ez = x.z - pz[k];
            const double phi = std::sqrt(ex * ex + ey * ey + ez * ez + L.c2);
            v += *lam * phi;
            if (grad) {
                const double s = phi > 0 ? *lam / phi : 0.0;
                gx += s * ex;
                gy += s * ey;
                gz += s * ez;
            }
        }
    out = MqSum{v, gx, gy, gz};
}

void sums_scalar(const double* px, const double* py, const double* pz, const MqLocalTerms* locals, std::size_t n,
                 const Vec3& x, bool grad, MqSum* out) {
    for (std::size_t i = 0; i < n; ++i) local_scalar(px, py, pz, locals[i], x, grad, out[i]);
}

#if defined(__x86_64__) && defined(__GNUC__)
#define MESHLESS_MQ_X86 1

// The four lane sums of v, gx, gy, gz (4 lanes each) into out, each as (a0 + a1) + (a2 + a3).
__attribute__((target("avx2,fma"))) inline void reduce4(__m256d v, __m256d gx, __m256d gy, __m256d gz, MqSum& out) {
    const __m256d ab = _mm256_hadd_pd(v, gx);   // v0+v1, gx0+gx1, v2+v3, gx2+gx3
    const __m256d cd = _mm256_hadd_pd(gy, gz);  // gy0+gy1, gz0+gz1, gy2+gy3, gz2+gz3
    const __m256d lo = _mm256_permute2f128_pd(ab, cd, 0x20), hi = _mm256_permute2f128_pd(ab, cd, 0x31);
    alignas(32) double s[4];
    _mm256_store_pd(s, _mm256_add_pd(lo, hi));
    out = MqSum{s[0], s[1], s[2], s[3]};
}
// The value alone, with the same additions as reduce4.
__attribute__((target("avx2,fma"))) inline double reduce1(__m256d v) {
    const __m256d h = _mm256_hadd_pd(v, v);  // v0+v1, v0+v1, v2+v3, v2+v3
    return _mm_cvtsd_f64(_mm_add_sd(_mm256_castpd256_pd128(h), _mm256_extractf128_pd(h, 1)));
}

// 4-lane mask of the first `left` lanes (left >= 4: all).
__attribute__((target("avx2,fma"))) inline __m256i lanes4(std::size_t left) {
    const __m256i idx = _mm256_setr_epi64x(0, 1, 2, 3);
    return _mm256_cmpgt_epi64(_mm256_set1_epi64x(static_cast<long long>(left < 4 ? left : 4)), idx);
}

// x - p and |x - p|^2 + c^2 for the centres k..k+3 from ex, ey, ez.
struct Offsets4 {
    __m256d ex, ey, ez, r2;
};
__attribute__((target("avx2,fma"))) inline Offsets4 offsets4(__m256d ex, __m256d ey, __m256d ez, __m256d C2) {
    return {ex, ey, ez, _mm256_fmadd_pd(ex, ex, _mm256_fmadd_pd(ey, ey, _mm256_fmadd_pd(ez, ez, C2)))};
}
// ... of four whole centres
__attribute__((target("avx2,fma"))) inline Offsets4 offsets4(const double* px, const double* py, const double* pz,
                                                             std::size_t k, __m256d X, __m256d Y, __m256d Z, __m256d C2) {
    return offsets4(_mm256_sub_pd(X, _mm256_loadu_pd(px + k)), _mm256_sub_pd(Y, _mm256_loadu_pd(py + k)),
                    _mm256_sub_pd(Z, _mm256_loadu_pd(pz + k)), C2);
}
// ... of the lanes of mask m (masked-off lanes read nothing and hold x - p = 0, r^2 = c^2, so that
// no far query makes them infinite)
__attribute__((target("avx2,fma"))) inline Offsets4 offsets4(const double* px, const double* py, const double* pz,
                                                             std::size_t k, __m256i m, __m256d X, __m256d Y, __m256d Z,
                                                             __m256d C2) {
    const __m256d keep = _mm256_castsi256_pd(m);
    return offsets4(_mm256_and_pd(keep, _mm256_sub_pd(X, _mm256_maskload_pd(px + k, m))),
                    _mm256_and_pd(keep, _mm256_sub_pd(Y, _mm256_maskload_pd(py + k, m))),
                    _mm256_and_pd(keep, _mm256_sub_pd(Z, _mm256_maskload_pd(pz + k, m))), C2);
}

template <bool Guard>
__attribute__((target("avx2,fma"))) inline void add4(const Offsets4& o, __m256d l, bool grad, __m256d& v, __m256d& gx,
                                                     __m256d& gy, __m256d& gz) {
    const __m256d phi = _mm256_sqrt_pd(o.r2);
    const __m256d pos = Guard ? _mm256_cmp_pd(phi, _mm256_setzero_pd(), _CMP_GT_OQ) : _mm256_setzero_pd();
    v = _mm256_fmadd_pd(l, Guard ? _mm256_and_pd(phi, pos) : phi, v);
    if (!grad) return;
    const __m256d s = Guard ? _mm256_and_pd(_mm256_div_pd(l, phi), pos) : _mm256_div_pd(l, phi);
    gx = _mm256_fmadd_pd(s, o.ex, gx);
    gy = _mm256_fmadd_pd(s, o.ey, gy);
    gz = _mm256_fmadd_pd(s, o.ez, gz);
}

// AVX2: square root and division (module comment). Whole groups of four centres with plain loads,
// the tail of each run with masked loads (the masked-off lanes: lambda 0 and r^2 = c^2, so they add
// 0 when c > 0 and are guarded when c == 0).
template <bool Guard>
__attribute__((target("avx2,fma"))) void local_avx2_t(const double* px, const double* py, const double* pz,
                                                      const MqLocalTerms& L, const Vec3& x, bool grad, MqSum& out) {
    const __m256d X = _mm256_set1_pd(x.x), Y = _mm256_set1_pd(x.y), Z = _mm256_set1_pd(x.z), C2 = _mm256_set1_pd(L.c2);
    const __m256d zero = _mm256_setzero_pd();
    __m256d v = zero, gx = zero, gy = zero, gz = zero;
    const double* lam = L.lambda;
    for (std::size_t r = 0; r < L.nruns; ++r) {
        const std::size_t start = L.runs[r].start, n = start + L.runs[r].count, whole = start + (L.runs[r].count & ~3u);
        std::size_t k = start;
        for (; k < whole; k += 4, lam += 4)
            add4<Guard>(offsets4(px, py, pz, k, X, Y, Z, C2), _mm256_loadu_pd(lam), grad, v, gx, gy, gz);
        if (k < n) {
            const __m256i m = lanes4(n - k);
            add4<Guard>(offsets4(px, py, pz, k, m, X, Y, Z, C2), _mm256_maskload_pd(lam, m), grad, v, gx, gy, gz);
            lam += n - k;
        }
    }
    if (grad) reduce4(v, gx, gy, gz, out);
    else out.v = reduce1(v);
}

__attribute__((target("avx2,fma"))) void sums_avx2(const double* px, const double* py, const double* pz,
                                                   const MqLocalTerms* locals, std::size_t n, const Vec3& x, bool grad,
                                                   MqSum* out) {
    for (std::size_t i = 0; i < n; ++i) {
        if (locals[i].c2 > 0) local_avx2_t<false>(px, py, pz, locals[i], x, grad, out[i]);
        else local_avx2_t<true>(px, py, pz, locals[i], x, grad, out[i]);
    }
}

// 8 lanes -> 4: lane i + lane i+4.
__attribute__((target("avx512f,avx512vl,avx512dq,fma"))) inline __m256d fold(__m512d a) {
    return _mm256_add_pd(_mm512_castpd512_pd256(a), _mm512_extractf64x4_pd(a, 1));
}

// AVX-512: y0 = vrsqrt14pd, one 3rd-degree Taylor step (module comment).
__attribute__((target("avx512f,avx512vl,avx512dq,fma"))) void local_avx512(const double* px, const double* py,
                                                                           const double* pz, const MqLocalTerms& L,
                                                                           const __m512d X, const __m512d Y,
                                                                           const __m512d Z, bool grad, MqSum& out) {
    const __m512d C2 = _mm512_set1_pd(L.c2), zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
    const __m512d t3 = _mm512_set1_pd(5.0 / 16), t2 = _mm512_set1_pd(3.0 / 8), t1 = _mm512_set1_pd(0.5);
    const bool guard = !(L.c2 > 0);  // r2 may be 0: such a term has phi = 0 and no slope
    __m512d v = zero, gx = zero, gy = zero, gz = zero;
    const double* lam = L.lambda;
    for (std::size_t r = 0; r < L.nruns; ++r) {
        const std::size_t n = L.runs[r].start + L.runs[r].count;
        for (std::size_t k = L.runs[r].start; k < n; k += 8, lam += 8) {
            const __mmask8 m = n - k >= 8 ? __mmask8(0xFF) : static_cast<__mmask8>((1u << (n - k)) - 1u);
            // masked-off lanes hold x - p = 0 (r^2 = c^2): a far query must not make them infinite
            const __m512d ex = _mm512_maskz_sub_pd(m, X, _mm512_maskz_loadu_pd(m, px + k));
            const __m512d ey = _mm512_maskz_sub_pd(m, Y, _mm512_maskz_loadu_pd(m, py + k));
            const __m512d ez = _mm512_maskz_sub_pd(m, Z, _mm512_maskz_loadu_pd(m, pz + k));
            const __m512d r2 = _mm512_fmadd_pd(ex, ex, _mm512_fmadd_pd(ey, ey, _mm512_fmadd_pd(ez, ez, C2)));
            const __m512d y0 = _mm512_rsqrt14_pd(r2);
            const __m512d t = _mm512_mul_pd(r2, y0);
            const __m512d e = _mm512_fnmadd_pd(t, y0, one);  // 1 - r2 y0^2, |e| <= 2^-13
            const __m512d q = _mm512_mul_pd(_mm512_fmadd_pd(_mm512_fmadd_pd(e, t3, t2), e, t1), e);
            __m512d phi = _mm512_fmadd_pd(t, q, t);
            __m512d y = _mm512_fmadd_pd(y0, q, y0);
            if (guard) {
                const __mmask8 pos = _mm512_mask_cmp_pd_mask(m, r2, zero, _CMP_GT_OQ);
                phi = _mm512_maskz_mov_pd(pos, phi);
                y = _mm512_maskz_mov_pd(pos, y);
            }
            const __m512d l = _mm512_maskz_loadu_pd(m, lam);  // 0 in the masked-off lanes
            v = _mm512_fmadd_pd(l, phi, v);
            if (grad) {
                const __m512d s = _mm512_mul_pd(l, y);
                gx = _mm512_fmadd_pd(s, ex, gx);
                gy = _mm512_fmadd_pd(s, ey, gy);
                gz = _mm512_fmadd_pd(s, ez, gz);
            }
        }
        lam -= (8 - (L.runs[r].count % 8)) % 8;  // the last step went past the run's end
    }
    if (grad) reduce4(fold(v), fold(gx), fold(gy), fold(gz), out);
    else out.v = reduce1(fold(v));
}

__attribute__((target("avx512f,avx512vl,avx512dq,fma"))) void sums_avx512(const double* px, const double* py,
                                                                          const double* pz, const MqLocalTerms* locals,
                                                                          std::size_t n, const Vec3& x, bool grad,
                                                                          MqSum* out) {
    const __m512d X = _mm512_set1_pd(x.x), Y = _mm512_set1_pd(x.y), Z = _mm512_set1_pd(x.z);
    for (std::size_t i = 0; i < n; ++i) local_avx512(px, py, pz, locals[i], X, Y, Z, grad, out[i]);
}
#endif

struct Choice {
    SumsFn fn;
    const char* name;
};

Choice choose() {
#ifdef MESHLESS_MQ_X86
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq"))
        return {sums_avx512, "avx512"};
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return {sums_avx2, "avx2"};
#endif
    return {sums_scalar, "scalar"};
}

const Choice& chosen() {
    static const Choice c = choose();  // thread-safe initialisation, once per process
    return c;
}

void add_to(const MqSum& s, bool grad, MqSum& out) {
    out.v += s.v;
    if (grad) {
        out.gx += s.gx;
        out.gy += s.gy;
        out.gz += s.gz;
    }
}

}  // namespace

void multiquadric_sums(const double* px, const double* py, const double* pz, std::span<const MqLocalTerms> locals,
                       const Vec3& x, bool grad, MqSum* out) {
    chosen().fn(px, py, pz, locals.data(), locals.size(), x, grad, out);
}

void multiquadric_sum(const double* px, const double* py, const double* pz, std::span<const MqRun> runs,
                      const double* lambda, double c2, const Vec3& x, bool grad, MqSum& out) {
    const MqLocalTerms L{runs.data(), static_cast<std::uint32_t>(runs.size()), lambda, c2};
    MqSum s;
    chosen().fn(px, py, pz, &L, 1, x, grad, &s);
    add_to(s, grad, out);
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
    SumsFn fn = sums_scalar;
#ifdef MESHLESS_MQ_X86
    if (isa == "avx2") fn = sums_avx2;
    if (isa == "avx512") fn = sums_avx512;
#endif
    const MqLocalTerms L{runs.data(), static_cast<std::uint32_t>(runs.size()), lambda, c2};
    MqSum s;
    fn(px, py, pz, &L, 1, x, grad, &s);
    add_to(s, grad, out);
}

}  // namespace meshless
