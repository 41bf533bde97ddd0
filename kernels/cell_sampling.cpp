#include "kernels/cell_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <type_traits>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "kernels/iso_threshold.hpp"
#include "kernels/trilinear.hpp"

namespace meshless {

std::int64_t cell_row_count(const GridSpec& g) {
    if (g.dims[0] < 2 || g.dims[1] < 2 || g.dims[2] < 2) return 0;
    return (g.dims[1] - 1) * (g.dims[2] - 1);
}

namespace {

/// above[w] bit b = (p[64 w + b] >= t) for the n samples of one voxel row; bits past n are 0.
/// A NaN compares false (reads as "below"), as in the active-cell test of the header.
template <class T>
void above_bits(const T* p, std::int64_t n, T t, std::uint64_t* above) {
    const std::int64_t words = (n + 63) / 64;
    std::int64_t i = 0;
#if defined(__SSE2__)
    if constexpr (std::is_same_v<T, std::uint8_t>) {
        const __m128i vt = _mm_set1_epi8(static_cast<char>(t));
        for (; i + 16 <= n; i += 16) {  // 16 samples at a time, never past the row
            const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + i));
            const auto m = static_cast<std::uint64_t>(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_max_epu8(v, vt), v)));
            if (i % 64 == 0) above[i / 64] = m;
            else above[i / 64] |= m << (i % 64);
        }
        if (i == n) return;
        // the last partial group of 16: scalar bits into the word begun above (or a new one)
        std::uint64_t w = i % 64 == 0 ? 0 : above[i / 64];
        for (std::int64_t b = i; b < n; ++b) w |= static_cast<std::uint64_t>(p[b] >= t) << (b % 64);
        above[i / 64] = w;
        for (std::int64_t q = i / 64 + 1; q < words; ++q) above[q] = 0;
        return;
    }
#endif
    for (; i < words * 64; i += 64) {
        std::uint64_t w = 0;
        const std::int64_t m = std::min<std::int64_t>(64, n - i);
        for (std::int64_t b = 0; b < m; ++b) w |= static_cast<std::uint64_t>(p[i + b] >= t) << b;
        above[i / 64] = w;
    }
}

/// Visits the active cells of cell rows [row0, row1), row by row in increasing i:
/// on_row(j, k, p00, p10, p01, p11, idx, n) with the row's four voxel rows (p00 = (0, j, k),
/// p10 = (0, j+1, k), p01 = (0, j, k+1), p11 = (0, j+1, k+1)) and idx[0..n) the x indices of its
/// active cells (corners not all on one side of the threshold; float corners not yet checked for
/// NaN/Inf), which on_row may rewrite (idx has room for nx entries, n <= nx - 1). Does nothing when every sample lies on one side.
template <class T, class OnRow>
void for_each_active_row(const T* data, const GridSpec& g, double iso, std::int64_t row0, std::int64_t row1,
                         OnRow&& on_row) {
    const IsoThreshold<T> thr(iso);
    if (thr.none_above || thr.all_above) return;  // every cell on one side: nothing is active
    const T t = thr.t;
    const std::int64_t nx = g.dims[0], ny = g.dims[1];
    const std::int64_t sy = nx, sz = nx * ny;
    // One bit per sample (>= iso), 64 samples per word, for the voxel rows of the two slices k and
    // k+1 the current cell row touches; each voxel row's bits are computed once (on first use) and
    // kept while its slice is one of the two, so the volume is read about once, not four times. A
    // cell (columns i, i+1) is active unless its 8 bits are all set or all clear, tested 64 cells
    // at a time with shifts (a zero padding word past each row).
    const std::int64_t words = (nx + 63) / 64, stride = words + 1;
    struct SliceBits {
        std::int64_t k = -1;
        std::unique_ptr<std::uint64_t[]> bits;  // not cleared: a row is written before it is read
        std::vector<char> ready;
    };
    SliceBits slice[2];
    for (SliceBits& sb : slice) {
        sb.bits.reset(new std::uint64_t[static_cast<std::size_t>(stride * ny)]);
        sb.ready.assign(static_cast<std::size_t>(ny), 0);
    }
    auto row_bits = [&](std::int64_t kk, std::int64_t jj) -> const std::uint64_t* {
        SliceBits* sb = slice[0].k == kk ? &slice[0] : slice[1].k == kk ? &slice[1] : nullptr;
        if (!sb) {  // rows come in increasing order: the slice with the lower k is done with
            sb = slice[0].k < slice[1].k ? &slice[0] : &slice[1];
            sb->k = kk;
            std::fill(sb->ready.begin(), sb->ready.end(), 0);
        }
        std::uint64_t* b = sb->bits.get() + stride * jj;
        if (!sb->ready[static_cast<std::size_t>(jj)]) {
            above_bits(data + jj * sy + kk * sz, nx, t, b);
            b[words] = 0;  // the padding word the shifts read
            sb->ready[static_cast<std::size_t>(jj)] = 1;
        }
        return b;
    };
    std::vector<std::int64_t> active(static_cast<std::size_t>(nx));
    const std::int64_t cells = nx - 1;
    for (std::int64_t r = row0; r < row1; ++r) {
        const std::int64_t j = r % (ny - 1), k = r / (ny - 1);
        const T* p00 = data + j * sy + k * sz;  // (0, j,   k)
        const T* p10 = p00 + sy;                // (0, j+1, k)
        const T* p01 = p00 + sz;                // (0, j,   k+1)
        const T* p11 = p01 + sy;                // (0, j+1, k+1)
        const std::uint64_t* m00 = row_bits(k, j);
        const std::uint64_t* m10 = row_bits(k, j + 1);
        const std::uint64_t* m01 = row_bits(k + 1, j);
        const std::uint64_t* m11 = row_bits(k + 1, j + 1);
        std::int64_t* idx = active.data();
        std::int64_t n = 0;
        for (std::int64_t w = 0; w < words; ++w) {
            // column bits of words w and w+1 (the padding word is 0), cell i uses columns i, i+1
            const std::uint64_t o0 = m00[w] | m10[w] | m01[w] | m11[w];
            const std::uint64_t a0 = m00[w] & m10[w] & m01[w] & m11[w];
            const std::uint64_t o1 = m00[w + 1] | m10[w + 1] | m01[w + 1] | m11[w + 1];
            const std::uint64_t a1 = m00[w + 1] & m10[w + 1] & m01[w + 1] & m11[w + 1];
            const std::uint64_t any = o0 | (o0 >> 1) | (o1 << 63);
            const std::uint64_t all = a0 & ((a0 >> 1) | (a1 << 63));
            std::uint64_t m = any & ~all;
            const std::int64_t left = cells - 64 * w;
            if (left < 64) m &= left > 0 ? (std::uint64_t{1} << left) - 1u : 0u;
            while (m != 0) {
                idx[n++] = 64 * w + __builtin_ctzll(m);
                m &= m - 1;
            }
        }
        if (n > 0) on_row(j, k, p00, p10, p01, p11, idx, n);
    }
}

/// Drops from idx the cells with a NaN/Inf corner (float samples), counting them; keeps the order.
template <class T>
std::int64_t drop_nonfinite(const T* p00, const T* p10, const T* p01, const T* p11, std::int64_t* idx,
                            std::int64_t n, SamplingStats& stats) {
    if constexpr (!std::is_floating_point_v<T>) {
        return n;
    } else {
        std::int64_t m = 0;
        for (std::int64_t a = 0; a < n; ++a) {
            const std::int64_t i = idx[a];
            const bool finite = std::isfinite(p00[i]) && std::isfinite(p00[i + 1]) && std::isfinite(p10[i]) &&
                                std::isfinite(p10[i + 1]) && std::isfinite(p01[i]) && std::isfinite(p01[i + 1]) &&
                                std::isfinite(p11[i]) && std::isfinite(p11[i + 1]);
            if (finite) idx[m++] = i;
            else ++stats.nonfinite_cells;
        }
        return m;
    }
}

/// The frame of a volume's cell centres, as sample_rows computes positions.
struct CentreFrame {
    double origin[3], spacing[3];
    std::array<std::int64_t, 3> off;
    float radius;
    explicit CentreFrame(const GridSpec& g, const SamplingParams& params)
        : origin{g.origin[0], g.origin[1], g.origin[2]}, spacing{g.spacing[0], g.spacing[1], g.spacing[2]},
          off(params.index_offset),
          radius(static_cast<float>(params.radius_scale * 0.5 *
                                    std::sqrt(g.spacing[0] * g.spacing[0] + g.spacing[1] * g.spacing[1] +
                                              g.spacing[2] * g.spacing[2]))) {}
    /// World coordinate of voxel index i (+ offset) on axis a: the cell's low corner.
    double lo(int a, std::int64_t i) const { return origin[a] + static_cast<double>(i + off[a]) * spacing[a]; }
};

#if defined(__SSE2__)
/// The per-row arrays of pass 1 (one entry per active cell): the sample's x and lo_x, gradient and
/// value as the record's floats (held in double).
struct CentreArrays {
    std::vector<double> buf;
    double *px, *lox, *gx, *gy, *gz, *v;
    explicit CentreArrays(std::int64_t nx) : buf(static_cast<std::size_t>(6 * (nx + 2))) {
        const std::size_t m = static_cast<std::size_t>(nx + 2);
        px = buf.data();
        lox = px + m;
        gx = lox + m;
        gy = gx + m;
        gz = gy + m;
        v = gz + m;
    }
};

/// trilinear(c, 0.5, 0.5, 0.5) on two cells at once (one per lane): the value and the local
/// gradient, the very operations of the scalar definition (IEEE add, sub, mul, div and conversions
/// round alike in SSE2 lanes and scalars; no FMA).
struct CentreLanes {
    __m128d value, lgx, lgy, lgz;
};
inline CentreLanes centre_lanes(const __m128d c[8]) {
    const __m128d half = _mm_set1_pd(0.5);
    const __m128d c00 = _mm_add_pd(c[0], _mm_mul_pd(half, _mm_sub_pd(c[1], c[0])));
    const __m128d c10 = _mm_add_pd(c[2], _mm_mul_pd(half, _mm_sub_pd(c[3], c[2])));
    const __m128d c01 = _mm_add_pd(c[4], _mm_mul_pd(half, _mm_sub_pd(c[5], c[4])));
    const __m128d c11 = _mm_add_pd(c[6], _mm_mul_pd(half, _mm_sub_pd(c[7], c[6])));
    const __m128d e0 = _mm_add_pd(c00, _mm_mul_pd(half, _mm_sub_pd(c10, c00)));
    const __m128d e1 = _mm_add_pd(c01, _mm_mul_pd(half, _mm_sub_pd(c11, c01)));
    CentreLanes r;
    r.value = _mm_add_pd(e0, _mm_mul_pd(half, _mm_sub_pd(e1, e0)));
    const __m128d d00 = _mm_sub_pd(c[1], c[0]), d10 = _mm_sub_pd(c[3], c[2]);
    const __m128d d01 = _mm_sub_pd(c[5], c[4]), d11 = _mm_sub_pd(c[7], c[6]);
    const __m128d f0 = _mm_add_pd(d00, _mm_mul_pd(half, _mm_sub_pd(d10, d00)));
    const __m128d f1 = _mm_add_pd(d01, _mm_mul_pd(half, _mm_sub_pd(d11, d01)));
    r.lgx = _mm_add_pd(f0, _mm_mul_pd(half, _mm_sub_pd(f1, f0)));
    const __m128d dy0 = _mm_sub_pd(c10, c00);
    r.lgy = _mm_add_pd(dy0, _mm_mul_pd(half, _mm_sub_pd(_mm_sub_pd(c11, c01), dy0)));
    r.lgz = _mm_sub_pd(e1, e0);
    return r;
}

/// Pass 1 over a row's active cells idx[0..n2) (n2 even), two per SSE2 step: centre_lanes,
/// to_world_gradient and the record's float rounding.
template <class T>
void centre_samples(const T* p00, const T* p10, const T* p01, const T* p11, const std::int64_t* idx, std::int64_t n2,
                    const CentreFrame& f, CentreArrays& o) {
    const __m128d half = _mm_set1_pd(0.5);
    const __m128d vsx = _mm_set1_pd(f.spacing[0]), vsy = _mm_set1_pd(f.spacing[1]), vsz = _mm_set1_pd(f.spacing[2]);
    const __m128d vox = _mm_set1_pd(f.origin[0]);
    for (std::int64_t a = 0; a < n2; a += 2) {
        const std::int64_t ia = idx[a], ib = idx[a + 1];
        auto ld = [&](const T* p, std::int64_t d) {
            return _mm_set_pd(static_cast<double>(p[ib + d]), static_cast<double>(p[ia + d]));
        };
        const __m128d c[8] = {ld(p00, 0), ld(p00, 1), ld(p10, 0), ld(p10, 1), ld(p01, 0), ld(p01, 1), ld(p11, 0), ld(p11, 1)};
        const CentreLanes t = centre_lanes(c);
        const __m128d ix = _mm_set_pd(static_cast<double>(ib + f.off[0]), static_cast<double>(ia + f.off[0]));
        const __m128d lo_x = _mm_add_pd(vox, _mm_mul_pd(ix, vsx));
        _mm_storeu_pd(o.lox + a, lo_x);
        _mm_storeu_pd(o.px + a, _mm_cvtps_pd(_mm_cvtpd_ps(_mm_add_pd(lo_x, _mm_mul_pd(half, vsx)))));
        _mm_storeu_pd(o.gx + a, _mm_cvtps_pd(_mm_cvtpd_ps(_mm_div_pd(t.lgx, vsx))));
        _mm_storeu_pd(o.gy + a, _mm_cvtps_pd(_mm_cvtpd_ps(_mm_div_pd(t.lgy, vsy))));
        _mm_storeu_pd(o.gz + a, _mm_cvtps_pd(_mm_cvtpd_ps(_mm_div_pd(t.lgz, vsz))));
        _mm_storeu_pd(o.v + a, _mm_cvtps_pd(_mm_cvtpd_ps(t.value)));
    }
}
#endif

/// The samples of the active cells of rows [row0, row1), emitted in order: emit(const SampleRecord&).
/// The definition (and the path without SSE2) is the scalar loop; with SSE2 pass 1 runs two cells
/// per step and gives the same bytes (tests/kernels/test_cell_sampling.cpp checks both against a
/// scalar reference).
template <class T, class Emit>
void sample_rows(const T* data, const GridSpec& g, double iso, std::int64_t row0, std::int64_t row1,
                 const SamplingParams& params, Emit&& emit, SamplingStats& stats) {
    const CentreFrame f(g, params);
    SampleRecord s{};
    s.radius = f.radius;
    for (int ax = 0; ax < 3; ++ax) s.cell_size[ax] = static_cast<float>(g.spacing[ax]);
#if defined(__SSE2__)
    CentreArrays arr(g.dims[0]);
#endif
    for_each_active_row(data, g, iso, row0, row1,
                        [&](std::int64_t j, std::int64_t k, const T* p00, const T* p10, const T* p01, const T* p11,
                            std::int64_t* idx, std::int64_t count) {
        const std::int64_t n = drop_nonfinite(p00, p10, p01, p11, idx, count, stats);
        if (n == 0) return;
        const double lo_y = f.lo(1, j), lo_z = f.lo(2, k);
        s.pos[1] = static_cast<float>(lo_y + 0.5 * f.spacing[1]);
        s.pos[2] = static_cast<float>(lo_z + 0.5 * f.spacing[2]);
        s.cell_lo[1] = static_cast<float>(lo_y);
        s.cell_lo[2] = static_cast<float>(lo_z);
#if defined(__SSE2__)
        if (n % 2 == 1) idx[n] = idx[n - 1];  // the odd last cell fills both lanes
        centre_samples(p00, p10, p01, p11, idx, (n + 1) / 2 * 2, f, arr);
        for (std::int64_t a = 0; a < n; ++a) {
            const std::int64_t i = idx[a];
            s.pos[0] = static_cast<float>(arr.px[a]);
            s.grad[0] = static_cast<float>(arr.gx[a]);
            s.grad[1] = static_cast<float>(arr.gy[a]);
            s.grad[2] = static_cast<float>(arr.gz[a]);
            s.value = static_cast<float>(arr.v[a]);
            s.cell_lo[0] = static_cast<float>(arr.lox[a]);
            const T c[8] = {p00[i], p00[i + 1], p10[i], p10[i + 1], p01[i], p01[i + 1], p11[i], p11[i + 1]};
            for (int ax = 0; ax < 8; ++ax) s.corner[ax] = static_cast<float>(static_cast<double>(c[ax]));
            emit(s);
        }
        stats.active_cells += n;
#else
        const Vec3 size{f.spacing[0], f.spacing[1], f.spacing[2]};
        for (std::int64_t a = 0; a < n; ++a) {
            const std::int64_t i = idx[a];
            const double c[8] = {static_cast<double>(p00[i]), static_cast<double>(p00[i + 1]),
                                 static_cast<double>(p10[i]), static_cast<double>(p10[i + 1]),
                                 static_cast<double>(p01[i]), static_cast<double>(p01[i + 1]),
                                 static_cast<double>(p11[i]), static_cast<double>(p11[i + 1])};
            const ValueGrad vg = trilinear(c, 0.5, 0.5, 0.5);
            const Vec3 gw = to_world_gradient(vg.grad, size);
            const double lo_x = f.lo(0, i);
            s.pos[0] = static_cast<float>(lo_x + 0.5 * f.spacing[0]);
            s.grad[0] = static_cast<float>(gw.x);
            s.grad[1] = static_cast<float>(gw.y);
            s.grad[2] = static_cast<float>(gw.z);
            s.value = static_cast<float>(vg.value);
            s.cell_lo[0] = static_cast<float>(lo_x);
            for (int ax = 0; ax < 8; ++ax) s.corner[ax] = static_cast<float>(c[ax]);
            emit(s);
            ++stats.active_cells;
        }
#endif
    });
}

#if defined(__SSE2__)
/// The approximate projection fused with the sampling: pass 1 (centre_samples), then
/// project_sample's approx branch (newton_step, the normal) two cells per SSE2 step with the same
/// operations in the same order, then the points in order; the bytes equal sample_rows followed by
/// project_sample. Three passes per row so that one cell's long dependency chain (divisions, square
/// root, float roundings) overlaps with the next cells'. Integers and finite floats only
/// (drop_nonfinite first).
template <class T>
void project_rows_approx(const T* data, const GridSpec& g, double iso, std::int64_t row0, std::int64_t row1,
                         const SamplingParams& params, std::vector<PointRecord>& out, SamplingStats& stats,
                         ProjectionStats& pstats) {
    const CentreFrame f(g, params);
    // project_sample's displacement bound from the record's float cell size
    const Vec3 fsize{static_cast<float>(g.spacing[0]), static_cast<float>(g.spacing[1]), static_cast<float>(g.spacing[2])};
    const double max_d = displacement_threshold(fsize), max_d2 = max_d * max_d;
    const float iso_f = static_cast<float>(iso);
    const __m128d zero = _mm_setzero_pd(), minus_one = _mm_set1_pd(-1.0);
    const __m128d viso = _mm_set1_pd(iso), vmax_d2 = _mm_set1_pd(max_d2);
    const std::size_t lanes_max = static_cast<std::size_t>(g.dims[0] + 2);
    CentreArrays arr(g.dims[0]);
    std::vector<float> fout(6 * lanes_max + 8);
    std::vector<std::uint8_t> flags(lanes_max);
    for_each_active_row(data, g, iso, row0, row1,
                        [&](std::int64_t j, std::int64_t k, const T* p00, const T* p10, const T* p01, const T* p11,
                            std::int64_t* idx, std::int64_t count) {
        const std::int64_t n = drop_nonfinite(p00, p10, p01, p11, idx, count, stats);
        stats.active_cells += n;
        pstats.input += n;
        if (n == 0) return;
        if (n % 2 == 1) idx[n] = idx[n - 1];  // the odd last cell fills both lanes
        const std::int64_t n2 = (n + 1) / 2 * 2;
        const __m128d py = _mm_set1_pd(static_cast<double>(static_cast<float>(f.lo(1, j) + 0.5 * f.spacing[1])));
        const __m128d pz = _mm_set1_pd(static_cast<double>(static_cast<float>(f.lo(2, k) + 0.5 * f.spacing[2])));
        // (1) the samples
        centre_samples(p00, p10, p01, p11, idx, n2, f, arr);
        // (2) newton_step and the normal: float position and normal, and why a lane is dropped
        float* const fo = fout.data();
        for (std::int64_t a = 0; a < n2; a += 2) {
            const __m128d gx = _mm_loadu_pd(arr.gx + a), gy = _mm_loadu_pd(arr.gy + a), gz = _mm_loadu_pd(arr.gz + a);
            const __m128d gg = _mm_add_pd(_mm_add_pd(_mm_mul_pd(gx, gx), _mm_mul_pd(gy, gy)), _mm_mul_pd(gz, gz));
            const __m128d t = _mm_div_pd(_mm_sub_pd(viso, _mm_loadu_pd(arr.v + a)), gg);
            const __m128d sx = _mm_mul_pd(gx, t), sy = _mm_mul_pd(gy, t), sz = _mm_mul_pd(gz, t);
            const __m128d ss = _mm_add_pd(_mm_add_pd(_mm_mul_pd(sx, sx), _mm_mul_pd(sy, sy)), _mm_mul_pd(sz, sz));
            const int not_flat = _mm_movemask_pd(_mm_cmpgt_pd(gg, zero));
            const int too_far = _mm_movemask_pd(_mm_cmpgt_pd(ss, vmax_d2));
            flags[static_cast<std::size_t>(a)] = static_cast<std::uint8_t>((not_flat & 1) | (too_far & 1) << 1);
            flags[static_cast<std::size_t>(a + 1)] = static_cast<std::uint8_t>((not_flat >> 1 & 1) | (too_far >> 1 & 1) << 1);
            const __m128d inv = _mm_div_pd(minus_one, _mm_sqrt_pd(gg));
            // lanes (a, a+1) of x, y, z, nx, ny, nz: 6 pairs of floats, 12 floats per step
            float* o = fo + 6 * a;
            _mm_storel_pi(reinterpret_cast<__m64*>(o + 0), _mm_cvtpd_ps(_mm_add_pd(_mm_loadu_pd(arr.px + a), sx)));
            _mm_storel_pi(reinterpret_cast<__m64*>(o + 2), _mm_cvtpd_ps(_mm_add_pd(py, sy)));
            _mm_storel_pi(reinterpret_cast<__m64*>(o + 4), _mm_cvtpd_ps(_mm_add_pd(pz, sz)));
            _mm_storel_pi(reinterpret_cast<__m64*>(o + 6), _mm_cvtpd_ps(_mm_mul_pd(gx, inv)));
            _mm_storel_pi(reinterpret_cast<__m64*>(o + 8), _mm_cvtpd_ps(_mm_mul_pd(gy, inv)));
            _mm_storel_pi(reinterpret_cast<__m64*>(o + 10), _mm_cvtpd_ps(_mm_mul_pd(gz, inv)));
        }
        // (3) the points, in the row's order
        for (std::int64_t a = 0; a < n; ++a) {
            const std::uint8_t fl = flags[static_cast<std::size_t>(a)];
            if (!(fl & 1)) { ++pstats.flat; continue; }
            if (fl & 2) { ++pstats.too_far; continue; }
            const float* o = fo + 6 * (a & ~std::int64_t{1}) + (a & 1);
            out.push_back(PointRecord{{o[0], o[2], o[4]}, {o[6], o[8], o[10]}, f.radius, iso_f});
            ++pstats.output;
        }
    });
}
#endif

}  // namespace

namespace {
/// complete_centre_samples' scalar definition for one record.
void complete_centre_sample(const double origin[3], const double spacing[3], const std::uint32_t* ijk, SampleRecord& s) {
    // sample_rows' scalar loop, with the cell's low corner origin + i * spacing on every axis
    double c[8];
    for (int q = 0; q < 8; ++q) c[q] = static_cast<double>(s.corner[q]);
    const ValueGrad vg = trilinear(c, 0.5, 0.5, 0.5);
    const Vec3 gw = to_world_gradient(vg.grad, Vec3{spacing[0], spacing[1], spacing[2]});
    for (int a = 0; a < 3; ++a) {
        const CellAxis x = cell_axis(origin[a], spacing[a], ijk[a]);
        s.pos[a] = x.centre;
        s.cell_lo[a] = x.lo;
        s.cell_size[a] = static_cast<float>(spacing[a]);
    }
    s.grad[0] = static_cast<float>(gw.x);
    s.grad[1] = static_cast<float>(gw.y);
    s.grad[2] = static_cast<float>(gw.z);
    s.value = static_cast<float>(vg.value);
}
}  // namespace

void complete_centre_samples(const double origin[3], const double spacing[3], const std::uint32_t* ijk,
                             SampleRecord* rec, std::size_t n) {
    std::size_t r = 0;
#if defined(__SSE2__)
    // two records per step, the operations of complete_centre_sample in the same order
    const __m128d half = _mm_set1_pd(0.5);
    __m128d org[3], sp[3];
    float size[3];
    for (int a = 0; a < 3; ++a) {
        org[a] = _mm_set1_pd(origin[a]);
        sp[a] = _mm_set1_pd(spacing[a]);
        size[a] = static_cast<float>(spacing[a]);
    }
    for (; r + 2 <= n; r += 2) {
        SampleRecord& sa = rec[r];
        SampleRecord& sb = rec[r + 1];
        const std::uint32_t* ia = ijk + 3 * r;
        const std::uint32_t* ib = ia + 3;
        __m128d c[8];
        for (int q = 0; q < 8; ++q) c[q] = _mm_set_pd(static_cast<double>(sb.corner[q]), static_cast<double>(sa.corner[q]));
        const CentreLanes t = centre_lanes(c);
        alignas(16) float out[6][4];
        for (int a = 0; a < 3; ++a) {
            const __m128d i = _mm_set_pd(static_cast<double>(ib[a]), static_cast<double>(ia[a]));
            const __m128d lo = _mm_add_pd(org[a], _mm_mul_pd(i, sp[a]));
            _mm_store_ps(out[a], _mm_cvtpd_ps(_mm_add_pd(lo, _mm_mul_pd(half, sp[a]))));
            _mm_store_ps(out[3 + a], _mm_cvtpd_ps(lo));
        }
        alignas(16) float g[4][4];
        _mm_store_ps(g[0], _mm_cvtpd_ps(_mm_div_pd(t.lgx, sp[0])));
        _mm_store_ps(g[1], _mm_cvtpd_ps(_mm_div_pd(t.lgy, sp[1])));
        _mm_store_ps(g[2], _mm_cvtpd_ps(_mm_div_pd(t.lgz, sp[2])));
        _mm_store_ps(g[3], _mm_cvtpd_ps(t.value));
        SampleRecord* two[2] = {&sa, &sb};
        for (int l = 0; l < 2; ++l) {
            SampleRecord& s = *two[l];
            for (int a = 0; a < 3; ++a) {
                s.pos[a] = out[a][l];
                s.cell_lo[a] = out[3 + a][l];
                s.cell_size[a] = size[a];
                s.grad[a] = g[a][l];
            }
            s.value = g[3][l];
        }
    }
#endif
    for (; r < n; ++r) complete_centre_sample(origin, spacing, ijk + 3 * r, rec[r]);
}

void complete_centre_samples_u8(const double origin[3], const double spacing[3], const std::uint32_t* ijk,
                                const std::uint8_t* corners, SampleRecord* rec, std::size_t n,
                                CentreGradientTable& table) {
    constexpr int kHalf = 1020, kSize = 2 * kHalf + 1;
    // keyed by the bits (+0 and -0 spacings give opposite infinities)
    if (table.grad.empty() || std::memcmp(spacing, table.spacing, sizeof table.spacing) != 0) {
        table.grad.resize(3 * kSize);
        for (int a = 0; a < 3; ++a) {
            table.spacing[a] = spacing[a];
            for (int l = -kHalf; l <= kHalf; ++l)
                table.grad[static_cast<std::size_t>(a * kSize + l + kHalf)] = static_cast<float>(static_cast<double>(l) * 0.25 / spacing[a]);
        }
    }
    const float* gx = table.grad.data() + kHalf;
    const float* gy = gx + kSize;
    const float* gz = gy + kSize;
    float size[3];
    for (int a = 0; a < 3; ++a) size[a] = static_cast<float>(spacing[a]);
    // the last cell's position floats per axis (an index past 2^32: none yet)
    std::uint64_t last[3] = {~std::uint64_t{0}, ~std::uint64_t{0}, ~std::uint64_t{0}};
    CellAxis axis[3] = {};
    for (std::size_t r = 0; r < n; ++r, ijk += 3, corners += 8) {
        SampleRecord& s = rec[r];
        const int c0 = corners[0], c1 = corners[1], c2 = corners[2], c3 = corners[3];
        const int c4 = corners[4], c5 = corners[5], c6 = corners[6], c7 = corners[7];
        for (int q = 0; q < 8; ++q) s.corner[q] = static_cast<float>(corners[q]);
        const int x0 = c0 + c2 + c4 + c6, x1 = c1 + c3 + c5 + c7;
        const int y0 = c0 + c1 + c4 + c5, y1 = c2 + c3 + c6 + c7;
        const int z0 = c0 + c1 + c2 + c3, z1 = c4 + c5 + c6 + c7;
        s.grad[0] = gx[x1 - x0];
        s.grad[1] = gy[y1 - y0];
        s.grad[2] = gz[z1 - z0];
        s.value = static_cast<float>(z0 + z1) * 0.125f;
        for (int a = 0; a < 3; ++a) {
            if (ijk[a] != last[a]) {  // consecutive cells mostly share their row (j, k)
                last[a] = ijk[a];
                axis[a] = cell_axis(origin[a], spacing[a], ijk[a]);
            }
            s.pos[a] = axis[a].centre;
            s.cell_lo[a] = axis[a].lo;
            s.cell_size[a] = size[a];
        }
    }
}

void sample_active_cells(const VolumeView& v, double iso, std::int64_t row0, std::int64_t row1,
                         const SamplingParams& params, std::vector<SampleRecord>& out,
                         SamplingStats& stats) {
    if (cell_row_count(v.grid) == 0 || row0 >= row1) return;
    auto emit = [&](const SampleRecord& s) { out.push_back(s); };
    visit_samples(v, [&](auto* p) { sample_rows(p, v.grid, iso, row0, row1, params, emit, stats); });
}

void sample_and_project_active_cells(const VolumeView& v, double iso, std::int64_t row0, std::int64_t row1,
                                     const SamplingParams& params, Projection mode,
                                     std::vector<PointRecord>& out, SamplingStats& stats,
                                     ProjectionStats& pstats) {
    if (cell_row_count(v.grid) == 0 || row0 >= row1) return;
#if defined(__SSE2__)
    if (mode == Projection::approx) {
        visit_samples(v, [&](auto* d) { project_rows_approx(d, v.grid, iso, row0, row1, params, out, stats, pstats); });
        return;
    }
#endif
    PointRecord p;
    auto emit = [&](const SampleRecord& s) {
        if (project_sample(s, iso, mode, p, pstats)) out.push_back(p);
    };
    visit_samples(v, [&](auto* d) { sample_rows(d, v.grid, iso, row0, row1, params, emit, stats); });
}

}  // namespace meshless
