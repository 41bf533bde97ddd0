#include "kernels/block_minmax.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace meshless {

namespace {

std::int64_t blocks_along(std::int64_t n, int edge) { return std::max<std::int64_t>(1, (n - 1 + edge - 1) / edge); }

// Min/max of p[0..n) over finite values (integers are always finite). Branch-free for integers.
template <class T>
void segment_minmax(const T* p, std::int64_t n, T& lo, T& hi, bool& any) {
    if constexpr (std::is_floating_point_v<T>) {
        for (std::int64_t i = 0; i < n; ++i) {
            const T v = p[i];
            if (!std::isfinite(v)) continue;
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
            any = true;
        }
    } else {
        T a = lo, b = hi;
        for (std::int64_t i = 0; i < n; ++i) {
            a = std::min(a, p[i]);
            b = std::max(b, p[i]);
        }
        lo = a;
        hi = b;
        any = any || n > 0;
    }
}

// The blocks (up to 2 per axis: neighbours share a voxel layer) that voxel index i of an axis with
// nb blocks of edge B belongs to, in o; returns how many.
int block_owners(std::int64_t i, int B, std::int64_t nb, std::int64_t* o) {
    int c = 0;
    const std::int64_t b = i / B;
    if (b < nb) o[c++] = b;
    if (i % B == 0 && b > 0) o[c++] = b - 1;
    return c;
}

// Adds z-slices [k0, k0 + count) (data: those slices, x fastest) to the per-block doubles lo/hi
// (+inf/-inf until a finite sample arrives).
template <class T>
void add_rows(const T* data, const GridSpec& g, std::int64_t k0, std::int64_t count, int B,
              const std::array<std::int64_t, 3>& blocks, std::vector<double>& lo, std::vector<double>& hi) {
    const std::int64_t nx = g.dims[0], ny = g.dims[1];
    const std::int64_t bx = blocks[0], by = blocks[1], bz = blocks[2];
    const T tmax = std::numeric_limits<T>::has_infinity ? std::numeric_limits<T>::infinity() : std::numeric_limits<T>::max();
    const T tmin = std::numeric_limits<T>::has_infinity ? -std::numeric_limits<T>::infinity() : std::numeric_limits<T>::lowest();
    std::vector<T> rlo(static_cast<std::size_t>(bx)), rhi(rlo.size());
    std::vector<char> rany(rlo.size());
    for (std::int64_t k = k0; k < k0 + count; ++k) {
        std::int64_t oz[2];
        const int cz = block_owners(k, B, bz, oz);
        for (std::int64_t j = 0; j < ny; ++j) {
            std::int64_t oy[2];
            const int cy = block_owners(j, B, by, oy);
            const T* row = data + nx * (j + ny * (k - k0));
            for (std::int64_t b = 0; b < bx; ++b) {
                const std::int64_t x0 = b * B, x1 = std::min<std::int64_t>(x0 + B, nx - 1);
                T a = tmax, h = tmin;
                bool seen = false;
                segment_minmax(row + x0, x1 - x0 + 1, a, h, seen);
                rlo[b] = a;
                rhi[b] = h;
                rany[b] = seen;
            }
            for (int zi = 0; zi < cz; ++zi)
                for (int yi = 0; yi < cy; ++yi) {
                    const std::size_t base = static_cast<std::size_t>(bx * (oy[yi] + by * oz[zi]));
                    for (std::int64_t b = 0; b < bx; ++b) {
                        if (!rany[b]) continue;
                        lo[base + b] = std::min(lo[base + b], static_cast<double>(rlo[b]));
                        hi[base + b] = std::max(hi[base + b], static_cast<double>(rhi[b]));
                    }
                }
        }
    }
}

#if defined(__SSE2__)
// add_rows for 8-bit samples: per z-slice and y-block, the min/max of each x-block's segments are
// gathered down the block's rows in 16-byte vectors (three overlapping loads cover a 33-sample
// segment) and reduced across lanes once per block, not once per row. Same blocks as add_rows.
void add_rows_u8(const std::uint8_t* data, const GridSpec& g, std::int64_t k0, std::int64_t count, int B,
                 const std::array<std::int64_t, 3>& blocks, std::vector<double>& lo, std::vector<double>& hi) {
    const std::int64_t nx = g.dims[0], ny = g.dims[1];
    const std::int64_t bx = blocks[0], by = blocks[1], bz = blocks[2];
    struct Lanes {
        __m128i v;
    };
    std::vector<Lanes> vlo(static_cast<std::size_t>(bx)), vhi(vlo.size());
    // the minimum (or maximum) of the 16 lanes, by halving
    auto reduce = [](__m128i v, auto op) {
        v = op(v, _mm_srli_si128(v, 8));
        v = op(v, _mm_srli_si128(v, 4));
        v = op(v, _mm_srli_si128(v, 2));
        v = op(v, _mm_srli_si128(v, 1));
        return static_cast<double>(_mm_cvtsi128_si32(v) & 0xFF);
    };
    const auto lane_min = [](__m128i a, __m128i b) { return _mm_min_epu8(a, b); };
    const auto lane_max = [](__m128i a, __m128i b) { return _mm_max_epu8(a, b); };
    for (std::int64_t k = k0; k < k0 + count; ++k) {
        std::int64_t oz[2];
        const int cz = block_owners(k, B, bz, oz);
        if (cz == 0) continue;
        const std::uint8_t* slice = data + nx * ny * (k - k0);
        for (std::int64_t yb = 0; yb < by; ++yb) {
            const std::int64_t j0 = yb * B, j1 = std::min<std::int64_t>(j0 + B, ny - 1);
            std::fill(vlo.begin(), vlo.end(), Lanes{_mm_set1_epi8(static_cast<char>(0xFF))});
            std::fill(vhi.begin(), vhi.end(), Lanes{_mm_setzero_si128()});
            for (std::int64_t j = j0; j <= j1; ++j) {
                const std::uint8_t* row = slice + nx * j;
                for (std::int64_t b = 0; b < bx; ++b) {
                    const std::int64_t x0 = b * B, x1 = std::min<std::int64_t>(x0 + B, nx - 1);
                    __m128i mn, mx;
                    if (B == 32 && x1 - x0 == 32) {
                        const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x0));
                        const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x0 + 16));
                        const __m128i d = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x0 + 17));
                        mn = _mm_min_epu8(_mm_min_epu8(a, c), d);
                        mx = _mm_max_epu8(_mm_max_epu8(a, c), d);
                    } else {
                        std::uint8_t a = 0xFF, h = 0;
                        for (std::int64_t x = x0; x <= x1; ++x) {
                            a = std::min(a, row[x]);
                            h = std::max(h, row[x]);
                        }
                        mn = _mm_set1_epi8(static_cast<char>(a));
                        mx = _mm_set1_epi8(static_cast<char>(h));
                    }
                    vlo[static_cast<std::size_t>(b)].v = _mm_min_epu8(vlo[static_cast<std::size_t>(b)].v, mn);
                    vhi[static_cast<std::size_t>(b)].v = _mm_max_epu8(vhi[static_cast<std::size_t>(b)].v, mx);
                }
            }
            for (std::int64_t b = 0; b < bx; ++b) {
                const double l = reduce(vlo[static_cast<std::size_t>(b)].v, lane_min);
                const double h = reduce(vhi[static_cast<std::size_t>(b)].v, lane_max);
                for (int zi = 0; zi < cz; ++zi) {
                    const std::size_t at = static_cast<std::size_t>(b + bx * (yb + by * oz[zi]));
                    lo[at] = std::min(lo[at], l);
                    hi[at] = std::max(hi[at], h);
                }
            }
        }
    }
}
#endif

}  // namespace

std::array<double, 2> BlockMinMax::range() const {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < vmin.size(); ++i) {
        if (std::isnan(vmin[i])) continue;
        lo = std::min(lo, vmin[i]);
        hi = std::max(hi, vmax[i]);
    }
    if (lo > hi) return {std::nan(""), std::nan("")};
    return {lo, hi};
}

BlockMinMaxBuilder::BlockMinMaxBuilder(const GridSpec& g, SampleType type, int edge) : grid_(g), type_(type) {
    out_.edge = std::max(edge, 1);
    for (int a = 0; a < 3; ++a) out_.blocks[a] = blocks_along(g.dims[a], out_.edge);
    const auto n = static_cast<std::size_t>(out_.blocks[0] * out_.blocks[1] * out_.blocks[2]);
    out_.vmin.assign(n, std::numeric_limits<double>::infinity());
    out_.vmax.assign(n, -std::numeric_limits<double>::infinity());
}

void BlockMinMaxBuilder::add_slices(std::int64_t k0, std::int64_t count, const std::byte* data) {
    if (count <= 0 || grid_.dims[0] <= 0 || grid_.dims[1] <= 0) return;
    GridSpec part = grid_;
    part.dims[2] = count;
#if defined(__SSE2__)
    if (type_ == SampleType::u8) {
        add_rows_u8(reinterpret_cast<const std::uint8_t*>(data), grid_, k0, count, out_.edge, out_.blocks, out_.vmin,
                    out_.vmax);
        return;
    }
#endif
    visit_samples(VolumeView{data, type_, part}, [&](auto* p) {
        add_rows(p, grid_, k0, count, out_.edge, out_.blocks, out_.vmin, out_.vmax);
    });
}

BlockMinMax BlockMinMaxBuilder::finish() && {
    for (std::size_t i = 0; i < out_.vmin.size(); ++i)
        if (out_.vmin[i] > out_.vmax[i]) out_.vmin[i] = out_.vmax[i] = std::nan("");  // no finite sample
    return std::move(out_);
}

BlockMinMax block_minmax(const VolumeView& v, int edge) {
    BlockMinMaxBuilder b(v.grid, v.type, edge);
    if (v.grid.voxel_count() > 0) b.add_slices(0, v.grid.dims[2], static_cast<const std::byte*>(v.data));
    return std::move(b).finish();
}

std::optional<VoxelBox> active_block_box(const BlockMinMax& b, const GridSpec& g, double iso) {
    std::optional<VoxelBox> box;
    std::size_t i = 0;
    for (std::int64_t z = 0; z < b.blocks[2]; ++z)
        for (std::int64_t y = 0; y < b.blocks[1]; ++y)
            for (std::int64_t x = 0; x < b.blocks[0]; ++x, ++i) {
                if (!(b.vmin[i] < iso && iso <= b.vmax[i])) continue;
                const std::int64_t c[3] = {x, y, z};
                VoxelBox one;
                for (int a = 0; a < 3; ++a) {
                    one.lo[a] = c[a] * b.edge;
                    one.hi[a] = std::min<std::int64_t>(one.lo[a] + b.edge, g.dims[a] - 1);
                }
                if (!box) {
                    box = one;
                } else {
                    for (int a = 0; a < 3; ++a) {
                        box->lo[a] = std::min(box->lo[a], one.lo[a]);
                        box->hi[a] = std::max(box->hi[a], one.hi[a]);
                    }
                }
            }
    return box;
}

std::array<Vec3, 2> world_bounds(const GridSpec& g, const VoxelBox& box) {
    Vec3 lo{g.origin[0] + box.lo[0] * g.spacing[0], g.origin[1] + box.lo[1] * g.spacing[1],
            g.origin[2] + box.lo[2] * g.spacing[2]};
    Vec3 hi{g.origin[0] + box.hi[0] * g.spacing[0], g.origin[1] + box.hi[1] * g.spacing[1],
            g.origin[2] + box.hi[2] * g.spacing[2]};
    return {lo, hi};
}

}  // namespace meshless
