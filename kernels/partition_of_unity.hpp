// Partition-of-unity blending of local approximations (dissertation section 2.1.1) with the
// inverse-distance singular weights of Franke and Nielson:
//
//     w_j(x) = [ (R_j - |x - c_j|)_+ / (R_j |x - c_j|) ]^2 = (1/d - 1/R)^2 for d < R, else 0,
//     F(x) = sum_j w_j Q_j / sum_j w_j,
//     grad F = sum_j ( w_j grad Q_j + grad w_j (Q_j - F) ) / sum_j w_j      (quotient rule),
//     grad w_j = -2 (1/d - 1/R) (x - c_j) / d^3.
//
// w_j is infinite at its centre, where F = Q_j: within 1e-12 R of a centre the blend returns that
// local's value and gradient (the limit, continuous). The (Q_j - F) form avoids the cancellation
// of large weight gradients near centres. Units: world; weights are dimensionless^-2 (only their
// ratios matter). Thread-safety: PuBlend is a per-thread accumulator; the functions are pure.
#pragma once
#include <cmath>
#include <limits>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

/// Franke-Nielson weight of a sphere (centre c, radius R) at x; grad (optional) receives its
/// gradient. Returns 0 (and a zero gradient) outside the open sphere. d must be > 0.
inline double franke_nielson_weight(const Vec3& x, const Vec3& c, double R, double d, Vec3* grad) {
    if (!(d < R)) {
        if (grad) *grad = {0, 0, 0};
        return 0;
    }
    const double t = 1.0 / d - 1.0 / R;
    if (grad) *grad = (x - c) * (-2.0 * t / (d * d * d));
    return t * t;
}

/// Collects (weight, weight gradient, Q, grad Q) of the locals covering x, then blends them.
class PuBlend {
public:
    void reset() { items_.clear(); at_centre_ = false; }
    /// True when the local centred at c (radius R) covers x: the caller then evaluates Q_j and
    /// calls add() with the returned distance. Sets *d.
    static bool covers(const Vec3& x, const Vec3& c, double R, double* d) {
        const Vec3 e = x - c;
        const double d2 = dot(e, e);
        if (!(d2 < R * R)) return false;
        *d = std::sqrt(d2);
        return true;
    }
    /// Adds local Q_j (value q, gradient gq; gq ignored when gradients are not needed).
    void add(const Vec3& x, const Vec3& c, double R, double d, double q, const Vec3& gq) {
        if (at_centre_) return;
        if (d <= 1e-12 * R) {
            at_centre_ = true;
            centre_q_ = q;
            centre_g_ = gq;
            return;
        }
        Item it;
        it.w = franke_nielson_weight(x, c, R, d, &it.gw);
        it.q = q;
        it.gq = gq;
        if (it.w > 0) items_.push_back(it);
    }
    bool empty() const { return !at_centre_ && items_.empty(); }
    /// F(x) and (when grad != nullptr) grad F. NaN (and a NaN gradient) when nothing covers x.
    double finish(Vec3* grad) const {
        if (at_centre_) {
            if (grad) *grad = centre_g_;
            return centre_q_;
        }
        if (items_.empty()) {
            const double nan = std::numeric_limits<double>::quiet_NaN();
            if (grad) *grad = {nan, nan, nan};
            return nan;
        }
        double sw = 0, swq = 0;
        for (const Item& it : items_) { sw += it.w; swq += it.w * it.q; }
        const double inv = 1.0 / sw;
        const double f = swq * inv;
        if (grad) {
            Vec3 g{0, 0, 0};
            for (const Item& it : items_) g += it.gq * it.w + it.gw * (it.q - f);
            *grad = g * inv;
        }
        return f;
    }

private:
    struct Item {
        double w, q;
        Vec3 gw, gq;
    };
    std::vector<Item> items_;
    bool at_centre_ = false;
    double centre_q_ = 0;
    Vec3 centre_g_;
};

}  // namespace meshless
