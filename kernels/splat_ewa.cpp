// Elliptical (EWA-style) splat kernel of SplatFrame; see splat_rasterizer.hpp for the model
// (Zwicker et al. 2001 surface splatting, as used in dissertation section 3.6).
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define MESHLESS_EWA_AVX2 1
// Every function between these marks, lambdas included, is compiled for AVX2 (no FMA: no
// contraction) and called only where the CPU has it.
#if defined(__clang__)
#define MESHLESS_AVX2_BEGIN _Pragma("clang attribute push(__attribute__((target(\"avx2\"))), apply_to = function)")
#define MESHLESS_AVX2_END _Pragma("clang attribute pop")
#else
#define MESHLESS_AVX2_BEGIN _Pragma("GCC push_options") _Pragma("GCC target(\"avx2\")")
#define MESHLESS_AVX2_END _Pragma("GCC pop_options")
#endif
#endif

#include "kernels/shading.hpp"
#include "kernels/splat_rasterizer.hpp"

namespace meshless {
namespace {

constexpr int kTable = 1024;           // Gaussian lookup entries over q in [0, cutoff^2]
constexpr float kFixed = 1048576.0f;  // 2^20: fixed-point scale of weights and weighted normals

using Footprint = EwaFootprint;  // identical in both passes (same code, same inputs)

struct Setup {
    detail::FloatView fv;
    float inv_c2;   // 1 / cutoff^2: variance of the object-space Gaussian in unit-disk coordinates
    float c2;       // cutoff^2
    float lowpass;  // pixel^2
    float depth_eps;
    int W, H;
    bool avx2;  // the pixel loops' AVX2 variants (the same bits)
};

// 10 bits per component of a unit normal, enough to decide which way a fragment faces.
std::uint64_t pack_normal(const float* n) {
    std::uint64_t out = 0;
    for (int i = 0; i < 3; ++i)
        out = (out << 10) | static_cast<std::uint64_t>(std::lrint(std::clamp(n[i], -1.0f, 1.0f) * 511.0f + 511.0f));
    return out;
}

// Whether n points the same way as the packed normal in the low bits of a visibility key.
bool agrees(std::uint64_t key, const float* n) {
    const float a = static_cast<float>((key >> 20) & 1023u) - 511.0f;
    const float b = static_cast<float>((key >> 10) & 1023u) - 511.0f;
    const float c = static_cast<float>(key & 1023u) - 511.0f;
    return a * n[0] + b * n[1] + c * n[2] >= 0.0f;
}

bool footprint(const Setup& s, const PointRecord& rec, Footprint& f) {
    if (!(std::isfinite(rec.pos[0]) && std::isfinite(rec.pos[1]) && std::isfinite(rec.pos[2]))) return false;
    const detail::FloatView& fv = s.fv;
    float pc[3];
    fv.point(rec.pos, pc);
    const float D = fv.distance - pc[2];
    if (!(D > fv.near_depth)) return false;
    const float k = fv.perspective ? fv.focal / D : fv.focal;
    f.sx = fv.cx + k * pc[0];
    f.sy = fv.cy - k * pc[1];
    const float r = std::isfinite(rec.radius) ? std::max(rec.radius, 0.0f) : 0.0f;

    float v[3];
    // Raw orientation here: fragments are aligned per pixel in pass 2 and the blended normal is
    // flipped towards the viewer at resolve time (flipping per splat would cancel at silhouettes).
    detail::oriented_normal(fv, rec, pc, D, false, f.n, v);
    const float* n = f.n;
    // Tangent axes u, w (orthonormal, perpendicular to n), scaled by the radius.
    float a[3] = {0, 0, 0};
    const float ax = std::fabs(n[0]), ay = std::fabs(n[1]), az = std::fabs(n[2]);
    a[(ax <= ay && ax <= az) ? 0 : (ay <= az ? 1 : 2)] = 1.0f;
    float u[3] = {n[1] * a[2] - n[2] * a[1], n[2] * a[0] - n[0] * a[2], n[0] * a[1] - n[1] * a[0]};
    const float ul = r / std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (float& c : u) c *= ul;
    const float w[3] = {n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};

    // Jacobian of (tangent coords s, t) -> screen offset. Perspective: x = f X / D, D = dist - Z.
    float j00, j01, j10, j11;
    if (fv.perspective) {
        const float ex = pc[0] / D, ey = pc[1] / D;
        j00 = k * (u[0] + ex * u[2]);
        j01 = k * (w[0] + ex * w[2]);
        j10 = -k * (u[1] + ey * u[2]);
        j11 = -k * (w[1] + ey * w[2]);
    } else {
        j00 = k * u[0];
        j01 = k * w[0];
        j10 = -k * u[1];
        j11 = -k * w[1];
    }
    // V = J J^T / c^2 + lowpass I
    const float v00 = (j00 * j00 + j01 * j01) * s.inv_c2 + s.lowpass;
    const float v01 = (j00 * j10 + j01 * j11) * s.inv_c2;
    const float v11 = (j10 * j10 + j11 * j11) * s.inv_c2 + s.lowpass;
    const float det = v00 * v11 - v01 * v01;
    if (!(det > 0.0f) || !std::isfinite(det)) return false;
    f.q00 = v11 / det;
    f.q01 = -v01 / det;
    f.q11 = v00 / det;

    // Depth of the splat plane, linear in the screen offset: depth(s,t) = D - (s u_z + t w_z),
    // clamped to [max(D - r, 0), D + r] (DepthRange).
    f.depth = D;
    f.radius = r;
    const float detj = j00 * j11 - j01 * j10;
    if (std::fabs(detj) > 1e-6f * (std::fabs(j00 * j11) + std::fabs(j01 * j10)) && detj != 0.0f) {
        // (s,t) = J^-1 d
        f.gx = -(u[2] * j11 - w[2] * j10) / detj;
        f.gy = -(w[2] * j00 - u[2] * j01) / detj;
    } else {
        f.gx = f.gy = 0.0f;
    }

    const float c = std::sqrt(s.c2);
    const float ex = c * std::sqrt(v00), ey = c * std::sqrt(v11);
    const float fx0 = std::ceil(f.sx - ex - 0.5f), fx1 = std::floor(f.sx + ex - 0.5f);
    const float fy0 = std::ceil(f.sy - ey - 0.5f), fy1 = std::floor(f.sy + ey - 0.5f);
    if (!(fx1 >= 0 && fy1 >= 0 && fx0 <= s.W - 1 && fy0 <= s.H - 1 && fx0 <= fx1 && fy0 <= fy1)) return false;
    // image sides are at most 16384 (cli/common.cpp): the range fits 16 bits
    f.x0 = static_cast<std::uint16_t>(std::max(fx0, 0.0f));
    f.x1 = static_cast<std::uint16_t>(std::min(fx1, float(s.W - 1)));
    f.y0 = static_cast<std::uint16_t>(std::max(fy0, 0.0f));
    f.y1 = static_cast<std::uint16_t>(std::min(fy1, float(s.H - 1)));
    f.base = 0;
    return true;
}

// The depth clamp and blending tolerance of a footprint: the disk spans at most +-radius in depth;
// zlo is non-negative, so depth bits order the visibility keys.
struct DepthRange {
    float zlo, zhi, eps;
    DepthRange(const Setup& s, const Footprint& f)
        : zlo(std::max(f.depth - f.radius, 0.0f)), zhi(f.depth + f.radius), eps(s.depth_eps * f.radius) {}
};

// True when no fragment of f can pass pass 2's depth test (z > visible + eps rejects): every
// fragment depth is >= zlo (the depth plane cannot give NaN: finite, bounded gradient), and zlo
// exceeds the largest visible depth of every tile under f's bounding box by more than eps (float
// addition is monotonic, so visible + eps <= tile max + eps < zlo <= z at every pixel).
bool plane_is_bounded(const Footprint& f) {
    return std::isfinite(f.depth) && std::fabs(f.gx) < 1e30f && std::fabs(f.gy) < 1e30f;
}

// Whether every tile under f's bounding box has a largest visible depth t with zlo > t + eps (the
// box holds at least one tile, and tiles are non-negative or +infinity, so this is zlo > (their
// maximum) + eps: float addition is monotonic). Stops at the first tile that fails.
bool beyond_tiles(const VisibleDepthTiles& t, const Footprint& f, float zlo, float eps) {
    constexpr int sh = VisibleDepthTiles::kShift;
    const int tx0 = f.x0 >> sh, tx1 = f.x1 >> sh;
    for (int ty = f.y0 >> sh; ty <= f.y1 >> sh; ++ty) {
        const float* row = t.max_depth.data() + static_cast<std::size_t>(ty) * t.tiles_x;
        for (int tx = tx0; tx <= tx1; ++tx)
            if (!(zlo > row[tx] + eps)) return false;
    }
    return true;
}

bool hidden(const VisibleDepthTiles& t, const Footprint& f, const DepthRange& d) {
    return plane_is_bounded(f) && beyond_tiles(t, f, d.zlo, d.eps);
}

// True when every fragment of f lies beyond the largest depth of the tiles under it: its keys all
// exceed the keys there (depth bits lead the key; strictly, so ties still meet the normal bits), so
// pass 1's minimum would keep them all.
bool behind(const VisibleDepthTiles& t, const Footprint& f, const DepthRange& d) {
    return plane_is_bounded(f) && beyond_tiles(t, f, d.zlo, 0.0f);
}

// Pass 1 on one row of f's bounding box (dy: the row's centre offset): each pixel inside the
// cut-off ellipse takes min(key, (depth bits << 32) | packed). Returns the fragments drawn. With
// SSE2, four pixels at a time: the same float operations in the same order as the scalar loop (no
// contraction, IEEE rounding per operation), so the same bits; the keys' minimum stays scalar.
std::int64_t draw_row(const Setup& s, const Footprint& f, const DepthRange& d, float dy, std::uint64_t packed,
                      std::uint64_t* row) {
    constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
    std::int64_t frags = 0;
    int x = f.x0;
#if defined(__SSE2__)
    const __m128 sx = _mm_set1_ps(f.sx), half = _mm_set1_ps(0.5f), c2 = _mm_set1_ps(s.c2);
    const __m128 q00 = _mm_set1_ps(f.q00), q01x2 = _mm_set1_ps(2.0f * f.q01), vdy = _mm_set1_ps(dy);
    const __m128 q11dydy = _mm_set1_ps(f.q11 * dy * dy);
    const __m128 depth = _mm_set1_ps(f.depth), gx = _mm_set1_ps(f.gx), gydy = _mm_set1_ps(f.gy * dy);
    const __m128 zlo = _mm_set1_ps(d.zlo), zhi = _mm_set1_ps(d.zhi);
    for (; x <= f.x1; x += 4) {
        const __m128 dx = _mm_sub_ps(_mm_add_ps(_mm_cvtepi32_ps(_mm_setr_epi32(x, x + 1, x + 2, x + 3)), half), sx);
        // q = q00 dx dx + 2 q01 dx dy + q11 dy dy, evaluated left to right as in C++
        const __m128 q = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(q00, dx), dx), _mm_mul_ps(_mm_mul_ps(q01x2, dx), vdy)),
                                    q11dydy);
        // std::clamp(v, lo, hi) = v < lo ? lo : (hi < v ? hi : v); max_ps(a, b) = a > b ? a : b
        const __m128 v = _mm_add_ps(_mm_add_ps(depth, _mm_mul_ps(gx, dx)), gydy);
        const __m128 z = _mm_min_ps(zhi, _mm_max_ps(zlo, v));
        const int inside = _mm_movemask_ps(_mm_cmpngt_ps(q, c2));  // !(q > c2), NaN included
        alignas(16) std::uint32_t zb[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(zb), _mm_castps_si128(z));
        const int n = std::min(4, f.x1 - x + 1);
        for (int i = 0; i < n; ++i) {
            const bool in = (inside >> i) & 1;
            frags += in;
            const std::uint64_t key = (std::uint64_t{zb[i]} << 32) | packed;
            row[x + i] = std::min(row[x + i], in ? key : kEmpty);
        }
    }
#endif
    for (; x <= f.x1; ++x) {
        const float dx = x + 0.5f - f.sx;
        const float q = f.q00 * dx * dx + 2.0f * f.q01 * dx * dy + f.q11 * dy * dy;
        const float z = std::clamp(f.depth + f.gx * dx + f.gy * dy, d.zlo, d.zhi);
        // Branch-free (the ellipse's edge is unpredictable): outside it, the candidate is the
        // empty key, which the minimum ignores.
        const bool inside = !(q > s.c2);
        frags += inside;
        const std::uint64_t key = (std::uint64_t{std::bit_cast<std::uint32_t>(z)} << 32) | packed;
        row[x] = std::min(row[x], inside ? key : kEmpty);
    }
    return frags;
}

#if MESHLESS_EWA_AVX2
MESHLESS_AVX2_BEGIN
// The lanes of one AVX2 step of the pixel loops: eight pixels, each with its own dx and row (dy);
// lanes 0-3 are 4 consecutive pixels from pixel index half[0], lanes 4-7 from half[1]. A footprint at
// most four pixels wide takes two rows per step (half[1] = the next row), a wider one eight
// pixels of one row (half[1] = half[0] + 4). Every lane's float operations are the scalar loop's,
// in its order, whatever its place in the vector, so both layouts give the same bits.
struct Lanes8 {
    __m256 dx, vdy, q11dydy, gydy;
    __m256i on;           // lanes holding a pixel of the footprint's bounding box
    std::size_t half[2];  // pixel index of lanes 0 and 4
};

// q = q00 dx dx + 2 q01 dx dy + q11 dy dy on the lanes, evaluated left to right as in C++
// (q01x2 = 2 q01): the ellipse test of both passes.
inline __m256 lanes_q(const Lanes8& l, __m256 q00, __m256 q01x2) {
    return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(_mm256_mul_ps(q00, l.dx), l.dx), _mm256_mul_ps(_mm256_mul_ps(q01x2, l.dx), l.vdy)),
                         l.q11dydy);
}

// The depth plane on the lanes, clamped to [zlo, zhi] as std::clamp does it (both passes).
inline __m256 lanes_z(const Lanes8& l, __m256 depth, __m256 gx, __m256 zlo, __m256 zhi) {
    return _mm256_min_ps(zhi, _mm256_max_ps(zlo, _mm256_add_ps(_mm256_add_ps(depth, _mm256_mul_ps(gx, l.dx)), l.gydy)));
}

// Calls step(Lanes8) over f's bounding box, rows in pairs when it is at most four pixels wide.
template <class Step>
inline void for_each_lanes8(const Setup& s, const Footprint& f, Step&& step) {
    const __m256 sx = _mm256_set1_ps(f.sx), half = _mm256_set1_ps(0.5f);
    const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    const int W = s.W, w = f.x1 - f.x0 + 1;
    if (w <= 4) {
        const __m256i col = _mm256_setr_epi32(0, 1, 2, 3, 0, 1, 2, 3);
        const __m256 dx = _mm256_sub_ps(_mm256_add_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(f.x0), col)), half), sx);
        const __m256i in_row = _mm256_cmpgt_epi32(_mm256_set1_epi32(w), col);
        const __m256i upper = _mm256_setr_epi32(0, 0, 0, 0, -1, -1, -1, -1);
        for (int y = f.y0; y <= f.y1; y += 2) {
            const bool two = y < f.y1;
            const float dy0 = y + 0.5f - f.sy, dy1 = (y + 1) + 0.5f - f.sy;
            const float d1 = two ? dy1 : dy0;  // (a lone last row: the upper lanes are off)
            Lanes8 l;
            l.dx = dx;
            l.vdy = _mm256_setr_m128(_mm_set1_ps(dy0), _mm_set1_ps(d1));
            l.q11dydy = _mm256_setr_m128(_mm_set1_ps(f.q11 * dy0 * dy0), _mm_set1_ps(f.q11 * d1 * d1));
            l.gydy = _mm256_setr_m128(_mm_set1_ps(f.gy * dy0), _mm_set1_ps(f.gy * d1));
            l.on = two ? in_row : _mm256_andnot_si256(upper, in_row);
            l.half[0] = static_cast<std::size_t>(y) * W + f.x0;
            l.half[1] = l.half[0] + (two ? static_cast<std::size_t>(W) : 0);
            step(l);
        }
        return;
    }
    for (int y = f.y0; y <= f.y1; ++y) {
        const float dy = y + 0.5f - f.sy;
        Lanes8 l;
        l.vdy = _mm256_set1_ps(dy);
        l.q11dydy = _mm256_set1_ps(f.q11 * dy * dy);
        l.gydy = _mm256_set1_ps(f.gy * dy);
        const std::size_t rowi = static_cast<std::size_t>(y) * W;
        for (int x = f.x0; x <= f.x1; x += 8) {
            l.on = _mm256_cmpgt_epi32(_mm256_set1_epi32(std::min(8, f.x1 - x + 1)), iota);
            l.dx = _mm256_sub_ps(_mm256_add_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(_mm256_set1_epi32(x), iota)), half), sx);
            l.half[0] = rowi + x;
            l.half[1] = rowi + x + 4;
            step(l);
        }
    }
}

// draw_row with AVX2 (for_each_lanes8): the same float operations in the same order as the
// scalar loop (AVX without FMA: no contraction), so the same bits; the keys' unsigned minimum is
// vectorised too (sign-flipped signed compares), the lanes off the bounding box masked off.
std::int64_t draw_rows_avx2(const Setup& s, const Footprint& f, const DepthRange& d, std::uint64_t packed,
                            std::uint64_t* kb) {
    const __m256 c2 = _mm256_set1_ps(s.c2);
    const __m256 q00 = _mm256_set1_ps(f.q00), q01x2 = _mm256_set1_ps(2.0f * f.q01);
    const __m256 depth = _mm256_set1_ps(f.depth), gx = _mm256_set1_ps(f.gx);
    const __m256 zlo = _mm256_set1_ps(d.zlo), zhi = _mm256_set1_ps(d.zhi);
    const __m256i vpacked = _mm256_set1_epi64x(static_cast<long long>(packed));
    const __m256i sign = _mm256_set1_epi64x(static_cast<long long>(0x8000000000000000ull));
    const __m256i empty = _mm256_set1_epi64x(-1);
    std::int64_t frags = 0;
    for_each_lanes8(s, f, [&](const Lanes8& l) {
        const __m256 q = lanes_q(l, q00, q01x2);
        const __m256 z = lanes_z(l, depth, gx, zlo, zhi);
        const __m256i inside = _mm256_and_si256(_mm256_castps_si256(_mm256_cmp_ps(q, c2, _CMP_NGT_UQ)), l.on);
        frags += std::popcount(static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(inside))));
        const __m256i zb = _mm256_castps_si256(z);
        for (int h = 0; h < 2; ++h) {
            const __m128i lh = h ? _mm256_extracti128_si256(l.on, 1) : _mm256_castsi256_si128(l.on);
            if (_mm_movemask_epi8(lh) == 0) break;  // (lanes are on from lane 0, in each half)
            const __m128i zh = h ? _mm256_extracti128_si256(zb, 1) : _mm256_castsi256_si128(zb);
            const __m128i ih = h ? _mm256_extracti128_si256(inside, 1) : _mm256_castsi256_si128(inside);
            const __m256i key = _mm256_or_si256(_mm256_slli_epi64(_mm256_cvtepu32_epi64(zh), 32), vpacked);
            const __m256i cand = _mm256_blendv_epi8(empty, key, _mm256_cvtepi32_epi64(ih));
            const __m256i mask = _mm256_cvtepi32_epi64(lh);
            long long* p = reinterpret_cast<long long*>(kb + l.half[h]);
            const __m256i old = _mm256_maskload_epi64(p, mask);
            const __m256i older = _mm256_cmpgt_epi64(_mm256_xor_si256(old, sign), _mm256_xor_si256(cand, sign));
            _mm256_maskstore_epi64(p, _mm256_and_si256(mask, older), cand);
        }
    });
    return frags;
}
MESHLESS_AVX2_END
#endif

// The Gaussian table entry of t = q * qscale, clamped to [0, kTable] (a splat thousands of pixels
// wide can round q slightly below 0; NaN gives 0), as the AVX2 loop does it: max(t, 0) with the
// SSE/AVX operand order (NaN -> 0), then min with kTable, then truncation.
inline int gauss_index(float t) {
    const float lo = t > 0.0f ? t : 0.0f;
    return static_cast<int>(lo < static_cast<float>(kTable) ? lo : static_cast<float>(kTable));
}

// Pass 2 for one footprint: adds its fragments near the visible surface; returns fragments tested.
// Adds one accepted fragment (weight from q, aligned normal, colour) to the pixel's accumulators.
inline void add_fragment(const Footprint& f, const float* colour, float q, std::uint64_t key, const float* gauss,
                         float qscale, std::int64_t* a, bool coloured) {
    // Align with the visible fragment's orientation before blending.
    const float wgt = gauss[gauss_index(q * qscale)] * kFixed;
    const float wn = agrees(key, f.n) ? wgt : -wgt;
    a[0] += static_cast<std::int64_t>(wgt);
    a[1] += static_cast<std::int64_t>(std::lrint(wn * f.n[0]));
    a[2] += static_cast<std::int64_t>(std::lrint(wn * f.n[1]));
    a[3] += static_cast<std::int64_t>(std::lrint(wn * f.n[2]));
    if (coloured) {
        a[4] += static_cast<std::int64_t>(std::lrint(wgt * colour[0]));
        a[5] += static_cast<std::int64_t>(std::lrint(wgt * colour[1]));
        a[6] += static_cast<std::int64_t>(std::lrint(wgt * colour[2]));
    }
}

#if MESHLESS_EWA_AVX2
MESHLESS_AVX2_BEGIN
// accumulate_one with AVX2, eight pixels at a time, for the plain (uncoloured) accumulators: q, z,
// the depth test, the Gaussian weight, the orientation test against the visible key and the
// fixed-point conversions run on all lanes with the scalar loop's float operations in the same
// order (no contraction; lrint = cvtps2dq in the default rounding mode, the weight's truncation =
// cvttps2dq, every value below 2^21), so the same sums; each accepted pixel's four words are then
// added as one 256-bit vector.
std::int64_t accumulate_plain_avx2(const Setup& s, const Footprint& f, const DepthRange& d, const float* gauss,
                                   float qscale, const std::uint64_t* kb, std::int64_t* acc) {
    const __m256 c2 = _mm256_set1_ps(s.c2);
    const __m256 q00 = _mm256_set1_ps(f.q00), q01x2 = _mm256_set1_ps(2.0f * f.q01);
    const __m256 depth = _mm256_set1_ps(f.depth), gx = _mm256_set1_ps(f.gx), eps = _mm256_set1_ps(d.eps);
    const __m256 zlo = _mm256_set1_ps(d.zlo), zhi = _mm256_set1_ps(d.zhi);
    const __m256 n0 = _mm256_set1_ps(f.n[0]), n1 = _mm256_set1_ps(f.n[1]), n2 = _mm256_set1_ps(f.n[2]);
    const __m256 vqscale = _mm256_set1_ps(qscale), fixed = _mm256_set1_ps(kFixed), c511 = _mm256_set1_ps(511.0f);
    const __m256i m1023 = _mm256_set1_epi32(1023);
    const __m256i even = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
    std::int64_t frags = 0;
    for_each_lanes8(s, f, [&](const Lanes8& l) {
        const __m256 q = lanes_q(l, q00, q01x2);
        const __m256i inside = _mm256_and_si256(_mm256_castps_si256(_mm256_cmp_ps(q, c2, _CMP_NGT_UQ)), l.on);
        const int in_bits = _mm256_movemask_ps(_mm256_castsi256_ps(inside));
        if (!in_bits) return;
        frags += std::popcount(static_cast<unsigned>(in_bits));
        const __m256 z = lanes_z(l, depth, gx, zlo, zhi);
        // the eight visible keys: high words = depth bits, low words = packed normal
        const __m256i k0 = (in_bits & 0x0F) ? _mm256_maskload_epi64(reinterpret_cast<const long long*>(kb + l.half[0]),
                                                                     _mm256_cvtepi32_epi64(_mm256_castsi256_si128(inside)))
                                            : _mm256_setzero_si256();
        const __m256i k1 = (in_bits & 0xF0) ? _mm256_maskload_epi64(reinterpret_cast<const long long*>(kb + l.half[1]),
                                                                     _mm256_cvtepi32_epi64(_mm256_extracti128_si256(inside, 1)))
                                            : _mm256_setzero_si256();
        // de-interleave: lo = low words of keys 0..7, hi = high words, in lane order
        const __m256i p0 = _mm256_permutevar8x32_epi32(k0, even), p1 = _mm256_permutevar8x32_epi32(k1, even);
        const __m256i lo = _mm256_permute2x128_si256(p0, p1, 0x20), hi = _mm256_permute2x128_si256(p0, p1, 0x31);
        const __m256 limit = _mm256_add_ps(_mm256_castsi256_ps(hi), eps);
        const __m256i take = _mm256_castps_si256(_mm256_cmp_ps(z, limit, _CMP_NGT_UQ));
        const int accept = in_bits & _mm256_movemask_ps(_mm256_castsi256_ps(take));
        if (!accept) return;
        // weight, orientation, fixed point (add_fragment on every lane)
        // gauss_index on every lane: max(t, 0) (NaN -> 0), min with kTable, truncation
        const __m256i gi = _mm256_cvttps_epi32(
            _mm256_min_ps(_mm256_max_ps(_mm256_mul_ps(q, vqscale), _mm256_setzero_ps()), _mm256_set1_ps(static_cast<float>(kTable))));
        const __m256 g = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), gauss, gi, _mm256_castsi256_ps(_mm256_and_si256(take, inside)), 4);
        const __m256 wgt = _mm256_mul_ps(g, fixed);
        const __m256 a = _mm256_sub_ps(_mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(lo, 20), m1023)), c511);
        const __m256 b = _mm256_sub_ps(_mm256_cvtepi32_ps(_mm256_and_si256(_mm256_srli_epi32(lo, 10), m1023)), c511);
        const __m256 c = _mm256_sub_ps(_mm256_cvtepi32_ps(_mm256_and_si256(lo, m1023)), c511);
        const __m256 dot = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(a, n0), _mm256_mul_ps(b, n1)), _mm256_mul_ps(c, n2));
        const __m256 agrees = _mm256_cmp_ps(dot, _mm256_setzero_ps(), _CMP_GE_OQ);
        const __m256 wn = _mm256_blendv_ps(_mm256_xor_ps(wgt, _mm256_set1_ps(-0.0f)), wgt, agrees);
        const __m256i w0 = _mm256_cvttps_epi32(wgt);
        const __m256i w1 = _mm256_cvtps_epi32(_mm256_mul_ps(wn, n0));
        const __m256i w2 = _mm256_cvtps_epi32(_mm256_mul_ps(wn, n1));
        const __m256i w3 = _mm256_cvtps_epi32(_mm256_mul_ps(wn, n2));
        // transpose to one (w0, w1, w2, w3) quadruple per lane
        const __m256i t0 = _mm256_unpacklo_epi32(w0, w1), t1 = _mm256_unpackhi_epi32(w0, w1);
        const __m256i t2 = _mm256_unpacklo_epi32(w2, w3), t3 = _mm256_unpackhi_epi32(w2, w3);
        alignas(32) __m128i per[8];
        const __m256i r0 = _mm256_unpacklo_epi64(t0, t2), r1 = _mm256_unpackhi_epi64(t0, t2);
        const __m256i r2 = _mm256_unpacklo_epi64(t1, t3), r3 = _mm256_unpackhi_epi64(t1, t3);
        per[0] = _mm256_castsi256_si128(r0);
        per[1] = _mm256_castsi256_si128(r1);
        per[2] = _mm256_castsi256_si128(r2);
        per[3] = _mm256_castsi256_si128(r3);
        per[4] = _mm256_extracti128_si256(r0, 1);
        per[5] = _mm256_extracti128_si256(r1, 1);
        per[6] = _mm256_extracti128_si256(r2, 1);
        per[7] = _mm256_extracti128_si256(r3, 1);
        for (int bits = accept; bits; bits &= bits - 1) {
            const int i = std::countr_zero(static_cast<unsigned>(bits));
            __m256i* ap = reinterpret_cast<__m256i*>(acc + 4 * (l.half[i >> 2] + (i & 3)));
            _mm256_storeu_si256(ap, _mm256_add_epi64(_mm256_loadu_si256(ap), _mm256_cvtepi32_epi64(per[i])));
        }
    });
    return frags;
}
MESHLESS_AVX2_END
#endif

// Pass 2 for one footprint: adds its fragments near the visible surface; returns fragments tested.
// With SSE2, q, z and the depth test run four pixels at a time with the float operations of the
// scalar loop in the same order (the same bits); accepted fragments are added one by one.
std::int64_t accumulate_one(const Setup& s, const Footprint& f, const DepthRange& d, const float* gauss, float qscale,
                            const std::uint64_t* kb, std::int64_t* acc, std::size_t words) {
    const bool coloured = words == 7;
#if MESHLESS_EWA_AVX2
    if (s.avx2 && words == 4) return accumulate_plain_avx2(s, f, d, gauss, qscale, kb, acc);
#endif
    float colour[3] = {0, 0, 0};
    if (coloured) {
        colour[0] = static_cast<float>(f.base >> 16) / 255.0f;
        colour[1] = static_cast<float>((f.base >> 8) & 255u) / 255.0f;
        colour[2] = static_cast<float>(f.base & 255u) / 255.0f;
    }
    const int W = s.W;
    std::int64_t frags = 0;
#if defined(__SSE2__)
    const __m128 sx = _mm_set1_ps(f.sx), half = _mm_set1_ps(0.5f), c2 = _mm_set1_ps(s.c2);
    const __m128 q00 = _mm_set1_ps(f.q00), q01x2 = _mm_set1_ps(2.0f * f.q01);
    const __m128 depth = _mm_set1_ps(f.depth), gx = _mm_set1_ps(f.gx), eps = _mm_set1_ps(d.eps);
    const __m128 zlo = _mm_set1_ps(d.zlo), zhi = _mm_set1_ps(d.zhi);
#endif
    for (int y = f.y0; y <= f.y1; ++y) {
        const float dy = y + 0.5f - f.sy;
        const std::size_t rowi = static_cast<std::size_t>(y) * W;
        int x = f.x0;
#if defined(__SSE2__)
        const __m128 vdy = _mm_set1_ps(dy), q11dydy = _mm_set1_ps(f.q11 * dy * dy), gydy = _mm_set1_ps(f.gy * dy);
        for (; x <= f.x1; x += 4) {
            const int n = std::min(4, f.x1 - x + 1);
            const __m128 dx = _mm_sub_ps(_mm_add_ps(_mm_cvtepi32_ps(_mm_setr_epi32(x, x + 1, x + 2, x + 3)), half), sx);
            const __m128 q = _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(q00, dx), dx), _mm_mul_ps(_mm_mul_ps(q01x2, dx), vdy)),
                                        q11dydy);
            const int lanes = (1 << n) - 1;
            const int inside = _mm_movemask_ps(_mm_cmpngt_ps(q, c2)) & lanes;  // !(q > c2)
            if (!inside) continue;
            frags += (0x4332322132212110ull >> (4 * inside)) & 15u;  // popcount of 4 bits (no POPCNT in baseline x86-64)
            const __m128 z = _mm_min_ps(zhi, _mm_max_ps(zlo, _mm_add_ps(_mm_add_ps(depth, _mm_mul_ps(gx, dx)), gydy)));
            alignas(16) std::uint32_t vis[4] = {0, 0, 0, 0};
            const std::uint64_t* key = kb + rowi + x;
            for (int i = 0; i < n; ++i) vis[i] = static_cast<std::uint32_t>(key[i] >> 32);
            const __m128 limit = _mm_add_ps(_mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(vis))), eps);
            int accept = inside & _mm_movemask_ps(_mm_cmpngt_ps(z, limit));  // !(z > visible + eps)
            if (!accept) continue;
            alignas(16) float qs[4];
            _mm_store_ps(qs, q);
            for (; accept; accept &= accept - 1) {
                const int i = std::countr_zero(static_cast<unsigned>(accept));
                add_fragment(f, colour, qs[i], key[i], gauss, qscale, acc + words * (rowi + x + i), coloured);
            }
        }
#endif
        for (; x <= f.x1; ++x) {
            const float dx = x + 0.5f - f.sx;
            const float q = f.q00 * dx * dx + 2.0f * f.q01 * dx * dy + f.q11 * dy * dy;
            if (q > s.c2) continue;
            ++frags;
            const float z = std::clamp(f.depth + f.gx * dx + f.gy * dy, d.zlo, d.zhi);
            const std::uint64_t key = kb[rowi + x];
            if (z > std::bit_cast<float>(static_cast<std::uint32_t>(key >> 32)) + d.eps) continue;
            add_fragment(f, colour, q, key, gauss, qscale, acc + words * (rowi + x), coloured);
        }
    }
    return frags;
}

#if defined(__SSE2__)
// The lanes of footprint_lanes (kernels/splat_ewa_footprint_lanes.hpp): SSE2, four points at once.
namespace sse2 {
struct Ops {
    using V = __m128;
    static constexpr int W = 4;
    static V zero() { return _mm_setzero_ps(); }
    static V ones() { return _mm_castsi128_ps(_mm_set1_epi32(-1)); }
    static V set1(float x) { return _mm_set1_ps(x); }
    static V load(const float* p) { return _mm_load_ps(p); }
    static void store(float* p, V a) { _mm_store_ps(p, a); }
    static V add(V a, V b) { return _mm_add_ps(a, b); }
    static V sub(V a, V b) { return _mm_sub_ps(a, b); }
    static V mul(V a, V b) { return _mm_mul_ps(a, b); }
    static V div(V a, V b) { return _mm_div_ps(a, b); }
    static V sqrt(V a) { return _mm_sqrt_ps(a); }
    static V max(V a, V b) { return _mm_max_ps(a, b); }
    static V and_(V a, V b) { return _mm_and_ps(a, b); }
    static V or_(V a, V b) { return _mm_or_ps(a, b); }
    static V andnot(V a, V b) { return _mm_andnot_ps(a, b); }
    static V xor_(V a, V b) { return _mm_xor_ps(a, b); }
    static V gt(V a, V b) { return _mm_cmpgt_ps(a, b); }
    static V le(V a, V b) { return _mm_cmple_ps(a, b); }
    static V eq(V a, V b) { return _mm_cmpeq_ps(a, b); }
    static V neq(V a, V b) { return _mm_cmpneq_ps(a, b); }
    static V sel(V m, V a, V b) { return or_(and_(m, a), andnot(m, b)); }
    static V finite(V x) { return eq(sub(x, x), zero()); }
    static V fabs(V x) { return andnot(set1(-0.0f), x); }
};
#include "kernels/splat_ewa_footprint_lanes.hpp"
}  // namespace sse2
#endif

#if MESHLESS_EWA_AVX2
// The same lanes with AVX2, eight points at once: every function of this region is compiled for
// AVX2 (no FMA: no contraction) and called only where the CPU has it; the compares are the SSE2
// predicates (ordered, cmpneq unordered), so every lane still gives footprint()'s bits.
MESHLESS_AVX2_BEGIN
namespace avx2 {
struct Ops {
    using V = __m256;
    static constexpr int W = 8;
    static V zero() { return _mm256_setzero_ps(); }
    static V ones() { return _mm256_castsi256_ps(_mm256_set1_epi32(-1)); }
    static V set1(float x) { return _mm256_set1_ps(x); }
    static V load(const float* p) { return _mm256_load_ps(p); }
    static void store(float* p, V a) { _mm256_store_ps(p, a); }
    static V add(V a, V b) { return _mm256_add_ps(a, b); }
    static V sub(V a, V b) { return _mm256_sub_ps(a, b); }
    static V mul(V a, V b) { return _mm256_mul_ps(a, b); }
    static V div(V a, V b) { return _mm256_div_ps(a, b); }
    static V sqrt(V a) { return _mm256_sqrt_ps(a); }
    static V max(V a, V b) { return _mm256_max_ps(a, b); }
    static V and_(V a, V b) { return _mm256_and_ps(a, b); }
    static V or_(V a, V b) { return _mm256_or_ps(a, b); }
    static V andnot(V a, V b) { return _mm256_andnot_ps(a, b); }
    static V xor_(V a, V b) { return _mm256_xor_ps(a, b); }
    static V gt(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
    static V le(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
    static V eq(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
    static V neq(V a, V b) { return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ); }
    static V sel(V m, V a, V b) { return or_(and_(m, a), andnot(m, b)); }
    static V finite(V x) { return eq(sub(x, x), zero()); }
    static V fabs(V x) { return andnot(set1(-0.0f), x); }
};
#include "kernels/splat_ewa_footprint_lanes.hpp"
void footprint8(const Setup& s, const PointRecord* rec, Footprint* f, bool* ok) { footprint_lanes<Ops>(s, rec, f, ok); }
}  // namespace avx2
MESHLESS_AVX2_END
#endif


float ewa_c2(const ShadingParams& sh) {
    const float cutoff = static_cast<float>(std::max(sh.ewa_cutoff, 1e-3));
    return cutoff * cutoff;
}

bool cpu_has_avx2() {
#if MESHLESS_EWA_AVX2
    static const bool has = [] {
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") != 0;
    }();
    return has;
#else
    return false;
#endif
}

Setup make_setup(const ViewTransform& view, const ShadingParams& sh, bool avx2) {
    const float c2 = ewa_c2(sh);
    return Setup{detail::FloatView(view),
                 1.0f / c2,
                 c2,
                 static_cast<float>(std::max(sh.ewa_lowpass_px2, 0.0)),
                 static_cast<float>(std::max(sh.depth_epsilon, 0.0)),
                 view.width,
                 view.height,
                 avx2};
}

// Calls fn(footprint, index) for every point with a footprint, in order: eight points at a time
// (AVX2) or four (SSE2), the same bits as one at a time, the rest one by one.
template <class Fn>
void for_each_footprint(const Setup& s, std::span<const PointRecord> points, Fn&& fn) {
    std::size_t pi = 0;
#if MESHLESS_EWA_AVX2
    if (s.avx2) {
        Footprint f8[8];
        bool ok8[8];
        for (; pi + 8 <= points.size(); pi += 8) {
            avx2::footprint8(s, points.data() + pi, f8, ok8);
            for (int i = 0; i < 8; ++i)
                if (ok8[i]) fn(f8[i], pi + static_cast<std::size_t>(i));
        }
    }
#endif
#if defined(__SSE2__)
    Footprint f4[4];
    bool ok[4];
    for (; pi + 4 <= points.size(); pi += 4) {
        sse2::footprint_lanes<sse2::Ops>(s, points.data() + pi, f4, ok);
        for (int i = 0; i < 4; ++i)
            if (ok[i]) fn(f4[i], pi + static_cast<std::size_t>(i));
    }
#endif
    Footprint f;
    for (; pi < points.size(); ++pi)
        if (footprint(s, points[pi], f)) fn(f, pi);
}

// Pass 1 for one footprint (the rows of its bounding box); returns the fragments drawn.
std::int64_t draw_footprint(const Setup& s, const Footprint& fp, std::uint64_t* kb) {
    const DepthRange d(s, fp);
    const std::uint64_t packed = pack_normal(fp.n);
    std::int64_t frags = 0;
#if MESHLESS_EWA_AVX2
    if (s.avx2) return draw_rows_avx2(s, fp, d, packed, kb);
#endif
    for (int y = fp.y0; y <= fp.y1; ++y)
        frags += draw_row(s, fp, d, y + 0.5f - fp.sy, packed, kb + static_cast<std::size_t>(y) * s.W);
    return frags;
}

#if MESHLESS_EWA_AVX2
MESHLESS_AVX2_BEGIN
// depth_tiles' scan with AVX2: bits[tile] = the largest high word (depth bits) of the keys in each
// kSize x kSize tile (kSize = 4), eight pixels of a row at a time; the same values as the scalar
// loop (an unsigned maximum, in any order).
void tile_key_max_avx2(const std::uint64_t* keys, int W, int H, std::uint32_t* bits, int tiles_x) {
    static_assert(VisibleDepthTiles::kShift == 2);
    const __m256i even_odd = _mm256_setr_epi32(1, 3, 5, 7, 0, 2, 4, 6);  // high words first
    const int W8 = W & ~7;
    for (int y = 0; y < H; ++y) {
        std::uint32_t* trow = bits + static_cast<std::size_t>(y >> 2) * tiles_x;
        const std::uint64_t* row = keys + static_cast<std::size_t>(y) * W;
        int x = 0;
        for (; x < W8; x += 8) {
            const __m256i k0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row + x));
            const __m256i k1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row + x + 4));
            // high words of keys x..x+3 in the low 128 bits of h0, of x+4..x+7 in h1's
            const __m128i h0 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(k0, even_odd));
            const __m128i h1 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(k1, even_odd));
            __m128i m0 = _mm_max_epu32(h0, _mm_shuffle_epi32(h0, _MM_SHUFFLE(1, 0, 3, 2)));
            __m128i m1 = _mm_max_epu32(h1, _mm_shuffle_epi32(h1, _MM_SHUFFLE(1, 0, 3, 2)));
            m0 = _mm_max_epu32(m0, _mm_shuffle_epi32(m0, _MM_SHUFFLE(2, 3, 0, 1)));
            m1 = _mm_max_epu32(m1, _mm_shuffle_epi32(m1, _MM_SHUFFLE(2, 3, 0, 1)));
            std::uint32_t* t = trow + (x >> 2);
            t[0] = std::max(t[0], static_cast<std::uint32_t>(_mm_cvtsi128_si32(m0)));
            t[1] = std::max(t[1], static_cast<std::uint32_t>(_mm_cvtsi128_si32(m1)));
        }
        for (; x < W; ++x) trow[x >> 2] = std::max(trow[x >> 2], static_cast<std::uint32_t>(row[x] >> 32));
    }
}
MESHLESS_AVX2_END
#endif

}  // namespace

void SplatFrame::footprints(std::span<const PointRecord> points, std::vector<EwaFootprint>& out,
                            std::span<const std::uint32_t> blocks) const {
    const Setup s = make_setup(view_, shading_, ewa_avx2_);
    const bool coloured = acc_words() == 7;
    out.clear();
    for_each_footprint(s, points, [&](const Footprint& fp, std::size_t pi) {
        out.push_back(fp);
        if (coloured) out.back().base = splat_base_color(shading_, points[pi], blocks, pi);
    });
}

void SplatFrame::draw(std::span<const EwaFootprint> footprints, std::uint64_t* kb, SplatStats& st, EwaCull* cull) const {
    const Setup s = make_setup(view_, shading_, ewa_avx2_);
    const std::int64_t refresh = EwaCull::refresh_after(npix());
    std::int64_t drawn = 0, frags = 0;
    for (const Footprint& fp : footprints) {
        if (cull) {
            // no tiles before the first refresh: an empty buffer hides nothing
            if (cull->drawn_since >= refresh) {
                cull->tiles = depth_tiles(kb);
                cull->drawn_since = 0;
            }
            if (!cull->tiles.max_depth.empty() && behind(cull->tiles, fp, DepthRange(s, fp))) continue;
            ++cull->drawn_since;
        }
        ++drawn;
        frags += draw_footprint(s, fp, kb);
    }
    st.splats_drawn += drawn;
    st.fragments += frags;
}

void SplatFrame::init_ewa() {
    ewa_avx2_ = cpu_has_avx2();
    const float c2 = ewa_c2(shading_);
    gauss_.resize(kTable + 1);
    for (int i = 0; i <= kTable; ++i) gauss_[i] = std::exp(-0.5f * c2 * static_cast<float>(i) / kTable);
}

void SplatFrame::draw_ewa(std::span<const PointRecord> points, std::uint64_t* kb, SplatStats& st) const {
    const Setup s = make_setup(view_, shading_, ewa_avx2_);
    std::int64_t drawn = 0, frags = 0;
    // Pass 1: visibility. Key = (depth bits << 32) | packed normal of the nearest fragment, so the
    // minimum is independent of the drawing order, ties included.
    for_each_footprint(s, points, [&](const Footprint& fp, std::size_t) {
        ++drawn;
        frags += draw_footprint(s, fp, kb);
    });
    st.splats_drawn += drawn;
    st.fragments += frags;
}

const char* SplatFrame::ewa_isa() const {
#if defined(__SSE2__)
    return ewa_avx2_ ? "avx2" : "sse2";
#else
    return "scalar";
#endif
}

VisibleDepthTiles SplatFrame::depth_tiles(const std::uint64_t* keys) const {
    constexpr int sh = VisibleDepthTiles::kShift;
    const int W = view_.width, H = view_.height;
    VisibleDepthTiles t;
    t.tiles_x = (W + VisibleDepthTiles::kSize - 1) >> sh;
    t.tiles_y = (H + VisibleDepthTiles::kSize - 1) >> sh;
    std::vector<std::uint32_t> bits(static_cast<std::size_t>(t.tiles_x) * t.tiles_y, 0);
#if MESHLESS_EWA_AVX2
    if (ewa_avx2_) {
        tile_key_max_avx2(keys, W, H, bits.data(), t.tiles_x);
    } else
#endif
    {
        for (int y = 0; y < H; ++y) {
            std::uint32_t* trow = bits.data() + static_cast<std::size_t>(y >> sh) * t.tiles_x;
            const std::uint64_t* row = keys + static_cast<std::size_t>(y) * W;
            for (int x = 0; x < W; ++x) trow[x >> sh] = std::max(trow[x >> sh], static_cast<std::uint32_t>(row[x] >> 32));
        }
    }
    // Non-negative finite floats order like their bits; anything else (an empty pixel, a negative
    // zero, infinity, NaN) has larger bits and makes the tile never hide anything.
    t.max_depth.resize(bits.size());
    for (std::size_t i = 0; i < bits.size(); ++i)
        t.max_depth[i] = bits[i] < 0x7F800000u ? std::bit_cast<float>(bits[i]) : std::numeric_limits<float>::infinity();
    return t;
}

void SplatFrame::accumulate(std::span<const PointRecord> points, const std::uint64_t* kb, std::int64_t* acc,
                            SplatStats& st, std::span<const std::uint32_t> blocks, const VisibleDepthTiles* tiles) const {
    const std::size_t words = acc_words();
    const bool coloured = words == 7;
    const Setup s = make_setup(view_, shading_, ewa_avx2_);
    const float qscale = kTable / s.c2;
    std::int64_t frags = 0;
    // Pass 2: accumulation of fragments near the visible surface.
    auto add_one = [&](Footprint& f, std::size_t pi) {
        const DepthRange d(s, f);
        if (tiles && hidden(*tiles, f, d)) return;
        if (coloured) f.base = splat_base_color(shading_, points[pi], blocks, pi);
        frags += accumulate_one(s, f, d, gauss_.data(), qscale, kb, acc, words);
    };
    for_each_footprint(s, points, add_one);
    st.fragments += frags;
}

void SplatFrame::accumulate(std::span<const EwaFootprint> footprints, const std::uint64_t* kb, std::int64_t* acc,
                            SplatStats& st, const VisibleDepthTiles* tiles) const {
    const std::size_t words = acc_words();
    const Setup s = make_setup(view_, shading_, ewa_avx2_);
    const float qscale = kTable / s.c2;
    std::int64_t frags = 0;
    for (const Footprint& f : footprints) {
        const DepthRange d(s, f);
        if (tiles && hidden(*tiles, f, d)) continue;
        frags += accumulate_one(s, f, d, gauss_.data(), qscale, kb, acc, words);
    }
    st.fragments += frags;
}

void SplatFrame::resolve_ewa(const std::int64_t* acc, Image& img) const {
    const int W = view_.width, H = view_.height;
    // Resolve: normalise the blended normal and shade (deferred).
    const detail::Shader shader(shading_);
    const detail::FloatView fv(view_);
    const auto& bg = shading_.background;
    const bool two_sided = shading_.two_sided;
    const std::size_t words = acc_words();
    std::uint8_t* out = img.rgb.data();
    for (int y = 0; y < H; ++y) {
        for (int x = 0; x < W; ++x, out += 3) {
            const std::int64_t* a = acc + words * (static_cast<std::size_t>(y) * W + x);
            if (a[0] == 0) {
                out[0] = bg[0];
                out[1] = bg[1];
                out[2] = bg[2];
                continue;
            }
            float v[3] = {0, 0, 1};
            if (fv.perspective) {
                v[0] = -(x + 0.5f - fv.cx) / fv.focal;
                v[1] = (y + 0.5f - fv.cy) / fv.focal;
                const float il = 1.0f / std::sqrt(v[0] * v[0] + v[1] * v[1] + 1.0f);
                v[0] *= il;
                v[1] *= il;
                v[2] = il;
            }
            float n[3] = {static_cast<float>(a[1]), static_cast<float>(a[2]), static_cast<float>(a[3])};
            const float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            if (len2 > 0.0f) {
                float il = 1.0f / std::sqrt(len2);
                if (two_sided && n[0] * v[0] + n[1] * v[1] + n[2] * v[2] < 0) il = -il;
                n[0] *= il;
                n[1] *= il;
                n[2] *= il;
            } else {
                n[0] = v[0];
                n[1] = v[1];
                n[2] = v[2];
            }
            if (words == 7) {
                // the weighted mean base colour of the blended fragments
                const float inv = 1.0f / static_cast<float>(a[0]);
                const float colour[3] = {std::clamp(static_cast<float>(a[4]) * inv, 0.0f, 1.0f),
                                         std::clamp(static_cast<float>(a[5]) * inv, 0.0f, 1.0f),
                                         std::clamp(static_cast<float>(a[6]) * inv, 0.0f, 1.0f)};
                detail::unpack_rgb(shader.shade(colour, n[0], n[1], n[2], v[0], v[1], v[2]), out);
            } else {
                detail::unpack_rgb(shader.shade(n[0], n[1], n[2], v[0], v[1], v[2]), out);
            }
        }
    }
}

}  // namespace meshless
