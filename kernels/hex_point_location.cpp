#include "kernels/hex_point_location.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meshless {

namespace {

std::array<Vec3, 8> corners(const StructuredBlock& b, std::int64_t i, std::int64_t j, std::int64_t k, bool& ok) {
    std::array<Vec3, 8> c;
    ok = true;
    for (int q = 0; q < 8; ++q) {
        const std::int64_t n = b.index(i + (q & 1), j + ((q >> 1) & 1), k + ((q >> 2) & 1));
        const Vec3& p = b.node[static_cast<std::size_t>(n)];
        ok = ok && b.is_valid(n) && std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
             std::isfinite(b.value[static_cast<std::size_t>(n)]);
        c[static_cast<std::size_t>(q)] = p;
    }
    return c;
}

}  // namespace

BlockCellLocator::BlockCellLocator(const StructuredBlock& b, double tol) : b_(b), tol_(tol) { build(nullptr, nullptr); }

BlockCellLocator::BlockCellLocator(const StructuredBlock& b, double tol, const Vec3& region_lo, const Vec3& region_hi)
    : b_(b), tol_(tol) {
    build(&region_lo, &region_hi);
}

void BlockCellLocator::build(const Vec3* rlo, const Vec3* rhi) {
    const StructuredBlock& b = b_;
    const double tol = tol_;
    const double inf = std::numeric_limits<double>::infinity();
    lo_ = {inf, inf, inf};
    hi_ = {-inf, -inf, -inf};
    if (b.dims[0] < 2 || b.dims[1] < 2 || b.dims[2] < 2) return;
    const std::int64_t ni = b.dims[0] - 1, nj = b.dims[1] - 1, nk = b.dims[2] - 1;
    std::vector<std::array<Vec3, 2>> box;
    for (std::int64_t k = 0; k < nk; ++k)
        for (std::int64_t j = 0; j < nj; ++j)
            for (std::int64_t i = 0; i < ni; ++i) {
                bool ok = false;
                const auto c = corners(b, i, j, k, ok);
                if (!ok) continue;
                Vec3 l = c[0], h = c[0];
                for (const Vec3& p : c) {
                    l = {std::min(l.x, p.x), std::min(l.y, p.y), std::min(l.z, p.z)};
                    h = {std::max(h.x, p.x), std::max(h.y, p.y), std::max(h.z, p.z)};
                }
                const Vec3 g = (h - l) * tol;
                l = l - g;
                h = h + g;
                if (rlo && (h.x < rlo->x || h.y < rlo->y || h.z < rlo->z || l.x > rhi->x || l.y > rhi->y || l.z > rhi->z))
                    continue;
                box.push_back({l, h});
                cells_.push_back(i + ni * (j + nj * k));
                lo_ = {std::min(lo_.x, l.x), std::min(lo_.y, l.y), std::min(lo_.z, l.z)};
                hi_ = {std::max(hi_.x, h.x), std::max(hi_.y, h.y), std::max(hi_.z, h.z)};
            }
    if (cells_.empty()) return;
    // about one bin per cell, proportioned like the bounding box (flat axes get one bin)
    const Vec3 ext = hi_ - lo_;
    double prod = 1;
    int axes = 0;
    for (int a = 0; a < 3; ++a)
        if (ext[a] > 0 && std::isfinite(ext[a])) {
            prod *= ext[a];
            ++axes;
        }
    const double edge = axes ? std::pow(prod / static_cast<double>(cells_.size()), 1.0 / axes) : 1.0;
    for (int a = 0; a < 3; ++a) {
        const double nb = ext[a] > 0 && edge > 0 ? ext[a] / edge : 1.0;
        bins_[static_cast<std::size_t>(a)] = std::isfinite(nb) ? std::clamp<std::int64_t>(std::llround(nb), 1, 1024) : 1;
    }
    bin_size_ = {ext.x / static_cast<double>(bins_[0]), ext.y / static_cast<double>(bins_[1]), ext.z / static_cast<double>(bins_[2])};
    const std::size_t nbins = static_cast<std::size_t>(bins_[0] * bins_[1] * bins_[2]);
    offset_.assign(nbins + 1, 0);
    for (int pass = 0; pass < 2; ++pass) {
        std::vector<std::uint32_t> fill;
        if (pass == 1) {
            for (std::size_t q = 0; q < nbins; ++q) offset_[q + 1] += offset_[q];
            items_.resize(offset_[nbins]);
            fill.assign(offset_.begin(), offset_.end() - 1);
        }
        for (std::size_t c = 0; c < box.size(); ++c) {
            const std::int64_t x0 = bin_of(box[c][0].x, 0), x1 = bin_of(box[c][1].x, 0);
            const std::int64_t y0 = bin_of(box[c][0].y, 1), y1 = bin_of(box[c][1].y, 1);
            const std::int64_t z0 = bin_of(box[c][0].z, 2), z1 = bin_of(box[c][1].z, 2);
            for (std::int64_t z = z0; z <= z1; ++z)
                for (std::int64_t y = y0; y <= y1; ++y)
                    for (std::int64_t x = x0; x <= x1; ++x) {
                        const auto q = static_cast<std::size_t>(x + bins_[0] * (y + bins_[1] * z));
                        if (pass == 0) ++offset_[q + 1];
                        else items_[fill[q]++] = static_cast<std::uint32_t>(c);
                    }
        }
    }
}

std::int64_t BlockCellLocator::bin_of(double x, int axis) const {
    const double s = bin_size_[axis];
    const double f = s > 0 ? (x - lo_[axis]) / s : 0.0;
    return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(f)), 0, bins_[static_cast<std::size_t>(axis)] - 1);
}

bool BlockCellLocator::cell_coordinates(std::int64_t i, std::int64_t j, std::int64_t k, const Vec3& p, Vec3& uvw) const {
    bool ok = false;
    const auto c = corners(b_, i, j, k, ok);
    double u = 0.5, v = 0.5, w = 0.5;
    for (int it = 0; it < 24; ++it) {
        const double U[2] = {1 - u, u}, V[2] = {1 - v, v}, W[2] = {1 - w, w};
        Vec3 x{0, 0, 0}, du{0, 0, 0}, dv{0, 0, 0}, dw{0, 0, 0};
        for (int q = 0; q < 8; ++q) {
            const int a = q & 1, bb = (q >> 1) & 1, cc = (q >> 2) & 1;
            const Vec3& P = c[static_cast<std::size_t>(q)];
            x += P * (U[a] * V[bb] * W[cc]);
            du += P * ((a ? 1.0 : -1.0) * V[bb] * W[cc]);
            dv += P * (U[a] * (bb ? 1.0 : -1.0) * W[cc]);
            dw += P * (U[a] * V[bb] * (cc ? 1.0 : -1.0));
        }
        const Vec3 r = p - x;
        const double det = dot(du, cross(dv, dw));
        if (!(std::fabs(det) > 0) || !std::isfinite(det)) return false;
        // Cramer's rule for [du dv dw] d = r
        const double su = dot(r, cross(dv, dw)) / det, sv = dot(du, cross(r, dw)) / det, sw = dot(du, cross(dv, r)) / det;
        u += su;
        v += sv;
        w += sw;
        if (!(std::isfinite(u) && std::isfinite(v) && std::isfinite(w))) return false;
        if (std::fabs(u) > 1e3 || std::fabs(v) > 1e3 || std::fabs(w) > 1e3) return false;
        if (std::max({std::fabs(su), std::fabs(sv), std::fabs(sw)}) < 1e-10) {
            uvw = {u, v, w};
            return true;
        }
    }
    return false;
}

bool BlockCellLocator::contains(const Vec3& p) const {
    if (cells_.empty()) return false;
    if (p.x < lo_.x || p.y < lo_.y || p.z < lo_.z || p.x > hi_.x || p.y > hi_.y || p.z > hi_.z) return false;
    const auto q = static_cast<std::size_t>(bin_of(p.x, 0) + bins_[0] * (bin_of(p.y, 1) + bins_[1] * bin_of(p.z, 2)));
    const std::int64_t ni = b_.dims[0] - 1, nj = b_.dims[1] - 1;
    for (std::uint32_t it = offset_[q]; it < offset_[q + 1]; ++it) {
        const std::int64_t c = cells_[items_[it]];
        Vec3 uvw;
        if (!cell_coordinates(c % ni, (c / ni) % nj, c / (ni * nj), p, uvw)) continue;
        if (uvw.x >= -tol_ && uvw.y >= -tol_ && uvw.z >= -tol_ && uvw.x <= 1 + tol_ && uvw.y <= 1 + tol_ && uvw.z <= 1 + tol_)
            return true;
    }
    return false;
}

}  // namespace meshless
