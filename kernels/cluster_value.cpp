#include "kernels/cluster_value.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "kernels/fixed_chunks.hpp"

namespace meshless {

namespace {

using Cand = std::pair<double, std::uint32_t>;

/// Keeps the k smallest of v (by (d2, index)), sorted.
void keep_smallest(std::vector<Cand>& v, std::size_t k) {
    if (v.size() > k) {
        std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
        v.resize(k);
    }
    std::sort(v.begin(), v.end());
}

/// max_j |value[idx[j]] - f|, in fixed chunks (the same bits for any thread count).
double max_deviation(std::span<const double> value, std::span<const std::uint32_t> idx, double f) {
    return chunks::reduce(
        idx.size(), 0.0,
        [&](std::size_t b, std::size_t e) {
            double m = 0;
            for (std::size_t i = b; i < e; ++i) m = std::max(m, std::abs(value[idx[i]] - f));
            return m;
        },
        [](double a, double b) { return std::max(a, b); });
}

}  // namespace

ClusterValue ClusterValueEvaluator::evaluate(std::span<const Vec3> pos, std::span<const double> value,
                                             std::span<const std::uint32_t> idx) {
    const std::size_t n = idx.size();
    ClusterValue out;
    // centre and mean value
    using S4 = std::array<double, 4>;
    const S4 t = chunks::reduce(
        n, S4{},
        [&](std::size_t b, std::size_t e) {
            S4 s{};
            for (std::size_t i = b; i < e; ++i) {
                const std::uint32_t j = idx[i];
                s[0] += pos[j].x;
                s[1] += pos[j].y;
                s[2] += pos[j].z;
                s[3] += value[j];
            }
            return s;
        },
        [](S4 a, const S4& b) {
            for (int q = 0; q < 4; ++q) a[q] += b[q];
            return a;
        });
    const double inv = 1.0 / static_cast<double>(n);
    out.centre = {t[0] * inv, t[1] * inv, t[2] * inv};
    out.mean_value = t[3] * inv;
    const Vec3 c = out.centre;
    sel_.clear();
    if (kind_ == CbtValueKind::mean) {
        out.value = out.mean_value;
        out.error = max_deviation(value, idx, out.value);
        return out;
    }
    auto d2 = [&](std::uint32_t j) {
        const Vec3 d = pos[j] - c;
        return dot(d, d);
    };
    // the N = min(n, k) nearest
    const std::size_t want = std::min<std::size_t>(n, k_);
    cand_.clear();
    if (n < chunks::kParallelItems) {
        cand_.reserve(n);
        for (std::size_t i = 0; i < n; ++i) cand_.push_back({d2(idx[i]), idx[i]});
        keep_smallest(cand_, want);
    } else {
        std::vector<std::vector<Cand>> best(chunks::count(n));
        chunks::for_each(n, [&](std::size_t k, std::size_t b, std::size_t e) {
            std::vector<Cand> v;  // one chunk's candidates; only its `want` best are kept
            v.reserve(e - b);
            for (std::size_t i = b; i < e; ++i) v.push_back({d2(idx[i]), idx[i]});
            keep_smallest(v, want);
            best[k].assign(v.begin(), v.end());
        });
        for (const auto& v : best) cand_.insert(cand_.end(), v.begin(), v.end());
        keep_smallest(cand_, want);
    }
    for (std::size_t i = 0; i < cand_.size(); ++i) {
        const Vec3& p = pos[cand_[i].second];
        bool dup = false;
        for (std::size_t q = i; q-- > 0 && cand_[q].first == cand_[i].first;) {
            const Vec3& o = pos[cand_[q].second];
            if (o.x == p.x && o.y == p.y && o.z == p.z) {
                dup = true;
                break;
            }
        }
        if (!dup) sel_.push_back(cand_[i].second);
    }
    lambda_.assign(sel_.size(), 0.0);
    MultiquadricLocal h;
    solver_.fit(pos, value, sel_, c_, h, lambda_);
    double fc = multiquadric_evaluate(h, pos.data(), sel_.data(), lambda_.data(), c, nullptr);
    if (!std::isfinite(fc)) {
        double s = 0;
        for (std::uint32_t j : sel_) s += value[j];
        fc = s / static_cast<double>(sel_.size());
    }
    out.value = fc;
    out.error = max_deviation(value, idx, fc);
    return out;
}

}  // namespace meshless
