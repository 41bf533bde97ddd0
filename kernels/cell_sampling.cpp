#include "kernels/cell_sampling.hpp"

#include <cmath>
#include <cstring>

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

template <class T, class Emit>
void sample_rows(const T* data, const GridSpec& g, double iso, std::int64_t row0, std::int64_t row1,
                 const SamplingParams& params, Emit&& emit, SamplingStats& stats) {
    constexpr bool is_float = std::is_floating_point_v<T>;
    const IsoThreshold<T> thr(iso);
    if (thr.none_above || thr.all_above) return;  // every cell on one side: nothing is active
    const T t = thr.t;
    const std::int64_t nx = g.dims[0], ny = g.dims[1];
    const std::int64_t sy = nx, sz = nx * ny;
    const double sx_w = g.spacing[0], sy_w = g.spacing[1], sz_w = g.spacing[2];
    const float radius = static_cast<float>(
        params.radius_scale * 0.5 * std::sqrt(sx_w * sx_w + sy_w * sy_w + sz_w * sz_w));
    const Vec3 size{sx_w, sy_w, sz_w};
    // count[i] = how many of the 4 samples of x-column i of this cell row are above iso; a cell
    // (columns i, i+1) is active unless count[i] + count[i+1] is 0 or 8. The counting loop is
    // branch-free and vectorises; the scan below tests 16 cells at a time (SSE2) and visits only
    // the active ones, in increasing i (so the output order is that of a plain loop over i).
    // Padding of 32 zero counts past nx: the 16-wide scan reads up to cnt[nx + 14].
    std::vector<std::uint8_t> count(static_cast<std::size_t>(nx) + 32, 0);
    for (std::int64_t r = row0; r < row1; ++r) {
        const std::int64_t j = r % (ny - 1), k = r / (ny - 1);
        const T* p00 = data + j * sy + k * sz;  // (0, j,   k)
        const T* p10 = p00 + sy;                // (0, j+1, k)
        const T* p01 = p00 + sz;                // (0, j,   k+1)
        const T* p11 = p01 + sy;                // (0, j+1, k+1)
        std::uint8_t* cnt = count.data();
        for (std::int64_t i = 0; i < nx; ++i)
            cnt[i] = static_cast<std::uint8_t>((p00[i] >= t) + (p10[i] >= t) + (p01[i] >= t) + (p11[i] >= t));
        auto cell = [&](std::int64_t i) {
            double c[8] = {static_cast<double>(p00[i]), static_cast<double>(p00[i + 1]),
                           static_cast<double>(p10[i]), static_cast<double>(p10[i + 1]),
                           static_cast<double>(p01[i]), static_cast<double>(p01[i + 1]),
                           static_cast<double>(p11[i]), static_cast<double>(p11[i + 1])};
            if constexpr (is_float) {
                // NaN compares false (reads as "below"), so only cells whose finite corners
                // straddle the isovalue get here; those with a NaN/Inf corner are skipped, counted.
                bool finite = true;
                for (double x : c) finite = finite && std::isfinite(x);
                if (!finite) {
                    ++stats.nonfinite_cells;
                    return;
                }
            }
            const ValueGrad vg = trilinear(c, 0.5, 0.5, 0.5);
            const Vec3 gw = to_world_gradient(vg.grad, size);
            SampleRecord s;
            const auto& off = params.index_offset;
            const double lo[3] = {g.origin[0] + static_cast<double>(i + off[0]) * sx_w,
                                  g.origin[1] + static_cast<double>(j + off[1]) * sy_w,
                                  g.origin[2] + static_cast<double>(k + off[2]) * sz_w};
            s.pos[0] = static_cast<float>(lo[0] + 0.5 * sx_w);
            s.pos[1] = static_cast<float>(lo[1] + 0.5 * sy_w);
            s.pos[2] = static_cast<float>(lo[2] + 0.5 * sz_w);
            s.grad[0] = static_cast<float>(gw.x);
            s.grad[1] = static_cast<float>(gw.y);
            s.grad[2] = static_cast<float>(gw.z);
            s.value = static_cast<float>(vg.value);
            s.radius = radius;
            for (int a = 0; a < 3; ++a) {
                s.cell_lo[a] = static_cast<float>(lo[a]);
                s.cell_size[a] = static_cast<float>(g.spacing[a]);
            }
            for (int a = 0; a < 8; ++a) s.corner[a] = static_cast<float>(c[a]);
            emit(s);
            ++stats.active_cells;
        };
        const std::int64_t cells = nx - 1;
#if defined(__SSE2__)
        const __m128i zero = _mm_setzero_si128(), eight = _mm_set1_epi8(8);
        for (std::int64_t i0 = 0; i0 < cells; i0 += 16) {
            const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cnt + i0));
            const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cnt + i0 + 1));
            const __m128i sum = _mm_add_epi8(a, b);
            const __m128i inactive = _mm_or_si128(_mm_cmpeq_epi8(sum, zero), _mm_cmpeq_epi8(sum, eight));
            unsigned m = ~static_cast<unsigned>(_mm_movemask_epi8(inactive)) & 0xFFFFu;
            if (cells - i0 < 16) m &= (1u << (cells - i0)) - 1u;
            while (m != 0) {
                cell(i0 + __builtin_ctz(m));
                m &= m - 1;
            }
        }
#else
        for (std::int64_t i = 0; i < cells; ++i) {
            const unsigned sum = cnt[i] + cnt[i + 1];
            if (sum != 0u && sum != 8u) cell(i);
        }
#endif
    }
}

}  // namespace

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
    PointRecord p;
    auto emit = [&](const SampleRecord& s) {
        if (project_sample(s, iso, mode, p, pstats)) out.push_back(p);
    };
    visit_samples(v, [&](auto* d) { sample_rows(d, v.grid, iso, row0, row1, params, emit, stats); });
}

}  // namespace meshless
