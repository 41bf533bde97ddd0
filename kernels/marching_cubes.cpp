#include "kernels/marching_cubes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "kernels/errors.hpp"
#include "kernels/marching_cubes_table.hpp"

namespace meshless {
namespace {

constexpr std::uint8_t kAbove = 0x01;
constexpr std::uint8_t kNonFinite = 0x10;
constexpr std::uint32_t kNoVertex = std::numeric_limits<std::uint32_t>::max();

// Bits (0,1,2,3) of a 4-bit column code -> corner bits (0,2,4,6).
constexpr std::array<std::uint8_t, 16> make_spread() {
    std::array<std::uint8_t, 16> s{};
    for (int v = 0; v < 16; ++v) {
        int r = 0;
        for (int b = 0; b < 4; ++b)
            if (v & (1 << b)) r |= 1 << (2 * b);
        s[v] = static_cast<std::uint8_t>(r);
    }
    return s;
}
constexpr std::array<std::uint8_t, 16> kSpread = make_spread();

/// Per row of a slice mask: first and last x with mask[x] != mask[x+1] (first = nx-1, last = -1 when
/// the row is constant), and the end values.
struct RowInfo {
    std::int64_t first, last;
    std::uint8_t left, right;
};

template <class T>
class McRunner {
public:
    McRunner(const T* p, const GridSpec& g, double iso, const std::array<std::int64_t, 3>& offset,
             std::vector<std::uint64_t>* keys, const std::array<std::int64_t, 3>& whole)
        : p_(p), g_(g), iso_(iso), off_(offset), keys_(keys), whole_(whole) {
        nx_ = g.dims[0], ny_ = g.dims[1], nz_ = g.dims[2];
        sxy_ = nx_ * ny_;
        if constexpr (std::is_floating_point_v<T>) {
            float f = static_cast<float>(iso);
            if (static_cast<double>(f) < iso) f = std::nextafter(f, std::numeric_limits<float>::infinity());
            thr_f_ = f;
        } else {
            const double c = std::ceil(iso);
            thr_i_ = static_cast<std::int32_t>(std::clamp(c, -2.0e9, 2.0e9));
        }
    }

    Mesh run(std::int64_t k0, std::int64_t k1, McStats* stats) {
        Mesh mesh;
        McStats st;
        k0 = std::max<std::int64_t>(k0, 0);
        k1 = std::min<std::int64_t>(k1, nz_ - 1);
        if (nx_ < 2 || ny_ < 2 || nz_ < 2 || k0 >= k1) {
            if (stats) *stats = st;
            return mesh;
        }
        const McTable& table = marching_cubes_table();
        const std::size_t slice = static_cast<std::size_t>(sxy_);
        // Masks of three slices: k and k+1 for the current layer, k+2 built one layer ahead so that
        // the samples the gradients at slice k+1 need are already in cache.
        std::vector<std::uint8_t> mask[3];
        std::vector<RowInfo> rows[3];
        for (int s = 0; s < 3; ++s) {
            mask[s].resize(slice);
            rows[s].resize(static_cast<std::size_t>(ny_));
        }
        std::vector<std::uint32_t> xe[2], ye[2], ze;
        for (int s = 0; s < 2; ++s) {
            xe[s].assign(slice, kNoVertex);
            ye[s].assign(slice, kNoVertex);
        }
        ze.assign(slice, kNoVertex);
        // An edge-array slot is valid when base <= id < vertex count: ids from the array's previous
        // use (two slices earlier) are all below the base recorded when it was taken over.
        std::uint32_t base_xy[2] = {0, 0};
        mesh_ = &mesh;

        build_slice(k0, mask[k0 % 3].data(), rows[k0 % 3].data());
        build_slice(k0 + 1, mask[(k0 + 1) % 3].data(), rows[(k0 + 1) % 3].data());
        for (std::int64_t k = k0; k < k1; ++k) {
            const int a = static_cast<int>(k % 3), b = static_cast<int>((k + 1) % 3);
            if (k + 2 < nz_ && k + 1 < k1)
                build_slice(k + 2, mask[(k + 2) % 3].data(), rows[(k + 2) % 3].data());
            const int pb = static_cast<int>((k + 1) & 1);  // edge arrays alternate by slice parity
            const std::uint32_t layer_base = nverts_;
            base_xy[pb] = layer_base;
            const std::uint32_t base_z = layer_base;
            const std::uint8_t* ma = mask[a].data();
            const std::uint8_t* mb = mask[b].data();
            for (std::int64_t j = 0; j + 1 < ny_; ++j) {
                const RowInfo r[4] = {rows[a][j], rows[a][j + 1], rows[b][j], rows[b][j + 1]};
                std::int64_t lo = r[0].first, hi = r[0].last;
                bool same_left = true, same_right = true;
                for (int q = 1; q < 4; ++q) {
                    lo = std::min(lo, r[q].first);
                    hi = std::max(hi, r[q].last);
                    same_left = same_left && r[q].left == r[0].left;
                    same_right = same_right && r[q].right == r[0].right;
                }
                same_left = same_left && !(r[0].left & kNonFinite);
                same_right = same_right && !(r[0].right & kNonFinite);
                std::int64_t i0 = 0, i1 = nx_ - 1;
                if (lo > hi) {  // all four rows constant
                    if (same_left) continue;
                } else {
                    if (same_left) i0 = lo;
                    if (same_right) i1 = hi + 1;
                }
                const std::uint8_t* a0 = ma + j * nx_;
                const std::uint8_t* a1 = a0 + nx_;
                const std::uint8_t* b0 = mb + j * nx_;
                const std::uint8_t* b1 = b0 + nx_;
                auto column = [&](std::int64_t i) {
                    return static_cast<std::uint8_t>(a0[i] | (a1[i] << 1) | (b0[i] << 2) | (b1[i] << 3));
                };
                std::uint8_t prev = column(i0);
                for (std::int64_t i = i0; i < i1; ++i) {
                    const std::uint8_t cur = column(i + 1);
                    const std::uint8_t both = prev | cur;
                    const int cs = kSpread[prev & 15] | (kSpread[cur & 15] << 1);
                    prev = cur;
                    if (both & 0xF0) {
                        ++st.skipped_nonfinite;
                        continue;
                    }
                    if (cs == 0 || cs == 255) continue;
                    ++st.active_cells;
                    const McCase& mc = table.cases[cs];
                    std::uint32_t id[12];
                    for (unsigned m = mc.edge_mask; m; m &= m - 1) {
                        const int e = __builtin_ctz(m);
                        const int axis = e >> 2, bb = e & 3;
                        const int lo_bit = bb & 1, hi_bit = bb >> 1;
                        std::uint32_t* slot;
                        std::uint32_t base;
                        std::int64_t gi = i, gj = j, gk = k;
                        if (axis == 0) {
                            gj += lo_bit, gk += hi_bit;
                            const int s = static_cast<int>(gk & 1);
                            slot = &xe[s][static_cast<std::size_t>(gj * nx_ + gi)];
                            base = base_xy[s];
                        } else if (axis == 1) {
                            gi += lo_bit, gk += hi_bit;
                            const int s = static_cast<int>(gk & 1);
                            slot = &ye[s][static_cast<std::size_t>(gj * nx_ + gi)];
                            base = base_xy[s];
                        } else {
                            gi += lo_bit, gj += hi_bit;
                            slot = &ze[static_cast<std::size_t>(gj * nx_ + gi)];
                            base = base_z;
                        }
                        std::uint32_t v = *slot;
                        if (v - base >= nverts_ - base) {  // not valid: make the vertex
                            v = make_vertex(axis, gi, gj, gk);
                            *slot = v;
                        }
                        id[e] = v;
                    }
                    for (int t = 0; t < 3 * mc.triangle_count; ++t) mesh.tri.push_back(id[mc.edges[t]]);
                }
            }
        }
        mesh_ = nullptr;
        if (stats) *stats = st;
        return mesh;
    }

private:
    bool is_finite(T v) const {
        if constexpr (std::is_floating_point_v<T>) return (v - v) == T(0);
        else return true;
    }

    std::uint8_t mask_of(T v) const {
        if constexpr (std::is_floating_point_v<T>)
            return static_cast<std::uint8_t>((v >= thr_f_ ? kAbove : 0) | ((v - v) == 0.0f ? 0 : kNonFinite));
        else
            return static_cast<std::uint8_t>(static_cast<std::int32_t>(v) >= thr_i_ ? kAbove : 0);
    }

    void build_slice(std::int64_t k, std::uint8_t* m, RowInfo* rows) const {
        const T* s = p_ + k * sxy_;
        for (std::int64_t j = 0; j < ny_; ++j) {
            const T* r = s + j * nx_;
            std::uint8_t* mr = m + j * nx_;
            for (std::int64_t i = 0; i < nx_; ++i) mr[i] = mask_of(r[i]);
            RowInfo ri{nx_ - 1, -1, mr[0], mr[nx_ - 1]};
            for (std::int64_t i = 0; i + 1 < nx_; ++i)
                if (mr[i] != mr[i + 1]) {
                    ri.first = i;
                    break;
                }
            if (ri.first < nx_ - 1)
                for (std::int64_t i = nx_ - 2; i >= 0; --i)
                    if (mr[i] != mr[i + 1]) {
                        ri.last = i;
                        break;
                    }
            rows[j] = ri;
        }
    }

    /// Gradient (value per world unit) at sample (i,j,k), which is finite.
    void gradient(std::int64_t i, std::int64_t j, std::int64_t k, double g[3]) const {
        const std::int64_t idx = i + nx_ * j + sxy_ * k;
        const double c = static_cast<double>(p_[idx]);
        const std::int64_t coord[3] = {i, j, k};
        const std::int64_t n[3] = {nx_, ny_, nz_};
        const std::int64_t stride[3] = {1, nx_, sxy_};
        for (int d = 0; d < 3; ++d) {
            bool hp = coord[d] > 0, hn = coord[d] + 1 < n[d];
            T vp{}, vn{};
            if (hp) {
                vp = p_[idx - stride[d]];
                hp = is_finite(vp);
            }
            if (hn) {
                vn = p_[idx + stride[d]];
                hn = is_finite(vn);
            }
            double gd = 0;
            if (hp && hn) gd = (static_cast<double>(vn) - static_cast<double>(vp)) * 0.5;
            else if (hn) gd = static_cast<double>(vn) - c;
            else if (hp) gd = c - static_cast<double>(vp);
            g[d] = gd / g_.spacing[d];
        }
    }

    std::uint32_t make_vertex(int axis, std::int64_t i, std::int64_t j, std::int64_t k) {
        if (nverts_ == kNoVertex)
            throw std::length_error("marching_cubes: more than 2^32-1 vertices (uint32 indices)");
        const std::int64_t stride[3] = {1, nx_, sxy_};
        const std::int64_t idx = i + nx_ * j + sxy_ * k;
        const double va = static_cast<double>(p_[idx]);
        const double vb = static_cast<double>(p_[idx + stride[axis]]);
        double t = (iso_ - va) / (vb - va);
        t = std::clamp(t, 0.0, 1.0);
        double pos[3] = {static_cast<double>(i + off_[0]), static_cast<double>(j + off_[1]),
                         static_cast<double>(k + off_[2])};
        pos[axis] += t;
        double ga[3], gb[3];
        gradient(i, j, k, ga);
        std::int64_t o[3] = {i, j, k};
        ++o[axis];
        gradient(o[0], o[1], o[2], gb);
        double nrm[3];
        double len2 = 0;
        for (int d = 0; d < 3; ++d) {
            nrm[d] = ga[d] + t * (gb[d] - ga[d]);
            len2 += nrm[d] * nrm[d];
        }
        if (!(len2 > 0) || !std::isfinite(len2)) {
            nrm[0] = nrm[1] = nrm[2] = 0;
            nrm[axis] = vb > va ? 1.0 : -1.0;
            len2 = 1;
        }
        const double inv = -1.0 / std::sqrt(len2);  // -grad: towards decreasing value (VTK)
        Mesh& m = *mesh_;
        for (int d = 0; d < 3; ++d) {
            m.xyz.push_back(static_cast<float>(g_.origin[d] + g_.spacing[d] * pos[d]));
        }
        for (int d = 0; d < 3; ++d) m.normals.push_back(static_cast<float>(nrm[d] * inv));
        if (keys_) keys_->push_back(mc_edge_key(i + off_[0], j + off_[1], k + off_[2], axis, whole_));
        return nverts_++;
    }

    const T* p_;
    GridSpec g_;
    double iso_;
    std::array<std::int64_t, 3> off_;
    std::int64_t nx_ = 0, ny_ = 0, nz_ = 0, sxy_ = 0;
    float thr_f_ = 0;
    std::int32_t thr_i_ = 0;
    Mesh* mesh_ = nullptr;
    std::vector<std::uint64_t>* keys_ = nullptr;
    std::array<std::int64_t, 3> whole_;
    std::uint32_t nverts_ = 0;
};

}  // namespace

Mesh marching_cubes_slab(const VolumeView& v, double iso, std::int64_t k0, std::int64_t k1,
                         McStats* stats, const std::array<std::int64_t, 3>& index_offset,
                         std::vector<std::uint64_t>* edge_keys, const std::array<std::int64_t, 3>& whole_dims) {
    if (!std::isfinite(iso))
        throw InvalidArgument("marching_cubes: iso value " + std::to_string(iso) + " is not finite");
    if (edge_keys) edge_keys->clear();
    return visit_samples(v, [&](auto* p) {
        using T = std::remove_const_t<std::remove_pointer_t<decltype(p)>>;
        McRunner<T> runner(p, v.grid, iso, index_offset, edge_keys, whole_dims);
        return runner.run(k0, k1, stats);
    });
}

Mesh marching_cubes(const VolumeView& v, double iso, McStats* stats) {
    return marching_cubes_slab(v, iso, 0, v.grid.dims[2] - 1, stats);
}

}  // namespace meshless
