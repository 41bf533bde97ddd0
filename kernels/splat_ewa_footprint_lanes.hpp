// EWA footprints of several points at once (kernels/splat_ewa.cpp; dissertation section 3.6): the
// scalar footprint()'s float operations in the same order, on O::W lanes, each rounded alone (no
// contraction), so every lane gives footprint()'s bits; the lanes' early exits become masks, the
// bounding box (ceil, floor) is computed per lane as in footprint(). ok[i]: as footprint()'s result
// for rec[i].
// O: the lane operations (splat_ewa.cpp: SSE2, 4 lanes; AVX2, 8 lanes): V, W, zero, ones, set1,
// load, store, add, sub, mul, div, sqrt, max, and_, or_, andnot, xor_, the ordered compares gt, le,
// eq and the unordered neq, sel, finite, fabs, with the semantics of the SSE2 instructions.
// Included once per instruction set, inside that set's namespace (and, for AVX2, inside a region
// compiled for it), after Setup, Footprint and detail::FloatView are defined: deliberately without
// an include guard.
template <class O>
void footprint_lanes(const Setup& s, const PointRecord* rec, Footprint* f, bool* ok) {
    using V = typename O::V;
    constexpr int W = O::W;
    const detail::FloatView& fv = s.fv;
    alignas(32) float in[8][W];
    for (int i = 0; i < W; ++i) {
        for (int j = 0; j < 3; ++j) {
            in[j][i] = rec[i].pos[j];
            in[3 + j][i] = rec[i].normal[j];
        }
        in[6][i] = rec[i].radius;
    }
    const V zero = O::zero(), one = O::set1(1.0f);
    const V px = O::load(in[0]), py = O::load(in[1]), pz = O::load(in[2]);
    V good = O::and_(O::and_(O::finite(px), O::finite(py)), O::finite(pz));
    // pc = rotate(p - centre): ((r0 d0 + r1 d1) + r2 d2)
    const V d0 = O::sub(px, O::set1(fv.c[0])), d1 = O::sub(py, O::set1(fv.c[1])),
                 d2 = O::sub(pz, O::set1(fv.c[2]));
    auto rot = [&](int i, V a, V b, V c) {
        return O::add(O::add(O::mul(O::set1(fv.r[i][0]), a), O::mul(O::set1(fv.r[i][1]), b)),
                          O::mul(O::set1(fv.r[i][2]), c));
    };
    const V pc0 = rot(0, d0, d1, d2), pc1 = rot(1, d0, d1, d2), pc2 = rot(2, d0, d1, d2);
    const V D = O::sub(O::set1(fv.distance), pc2);
    good = O::and_(good, O::gt(D, O::set1(fv.near_depth)));
    const V focal = O::set1(fv.focal);
    const V k = fv.perspective ? O::div(focal, D) : focal;
    const V sx = O::add(O::set1(fv.cx), O::mul(k, pc0));
    const V sy = O::sub(O::set1(fv.cy), O::mul(k, pc1));
    const V rad = O::load(in[6]);
    const V r = O::and_(O::finite(rad), O::max(zero, rad));  // std::max(radius, 0) = 0 > radius ? 0 : radius

    // oriented_normal(two_sided = false)
    V v0 = zero, v1 = zero, v2 = one;
    if (fv.perspective) {
        const V inv = O::div(one, O::sqrt(O::add(O::add(O::mul(pc0, pc0), O::mul(pc1, pc1)), O::mul(D, D))));
        const V neg = O::set1(-0.0f);
        v0 = O::mul(O::xor_(pc0, neg), inv);
        v1 = O::mul(O::xor_(pc1, neg), inv);
        v2 = O::mul(D, inv);
    }
    const V nr0 = O::load(in[3]), nr1 = O::load(in[4]), nr2 = O::load(in[5]);
    V n0 = rot(0, nr0, nr1, nr2), n1 = rot(1, nr0, nr1, nr2), n2 = rot(2, nr0, nr1, nr2);
    const V len2 = O::add(O::add(O::mul(n0, n0), O::mul(n1, n1)), O::mul(n2, n2));
    const V usable = O::and_(O::gt(len2, O::set1(1e-20f)), O::finite(len2));
    const V ninv = O::div(one, O::sqrt(len2));
    n0 = O::sel(usable, O::mul(n0, ninv), v0);
    n1 = O::sel(usable, O::mul(n1, ninv), v1);
    n2 = O::sel(usable, O::mul(n2, ninv), v2);

    // tangent axes
    const V ax = O::fabs(n0), ay = O::fabs(n1), az = O::fabs(n2);
    const V m0 = O::and_(O::le(ax, ay), O::le(ax, az));
    const V m1 = O::andnot(m0, O::le(ay, az));
    const V m2 = O::andnot(O::or_(m0, m1), O::ones());
    const V a0 = O::and_(m0, one), a1 = O::and_(m1, one), a2 = O::and_(m2, one);
    V u0 = O::sub(O::mul(n1, a2), O::mul(n2, a1));
    V u1 = O::sub(O::mul(n2, a0), O::mul(n0, a2));
    V u2 = O::sub(O::mul(n0, a1), O::mul(n1, a0));
    const V ul = O::div(r, O::sqrt(O::add(O::add(O::mul(u0, u0), O::mul(u1, u1)), O::mul(u2, u2))));
    u0 = O::mul(u0, ul);
    u1 = O::mul(u1, ul);
    u2 = O::mul(u2, ul);
    const V w0 = O::sub(O::mul(n1, u2), O::mul(n2, u1));
    const V w1 = O::sub(O::mul(n2, u0), O::mul(n0, u2));
    const V w2 = O::sub(O::mul(n0, u1), O::mul(n1, u0));

    // Jacobian
    V j00, j01, j10, j11;
    const V nk = O::xor_(k, O::set1(-0.0f));
    if (fv.perspective) {
        const V ex = O::div(pc0, D), ey = O::div(pc1, D);
        j00 = O::mul(k, O::add(u0, O::mul(ex, u2)));
        j01 = O::mul(k, O::add(w0, O::mul(ex, w2)));
        j10 = O::mul(nk, O::add(u1, O::mul(ey, u2)));
        j11 = O::mul(nk, O::add(w1, O::mul(ey, w2)));
    } else {
        j00 = O::mul(k, u0);
        j01 = O::mul(k, w0);
        j10 = O::mul(nk, u1);
        j11 = O::mul(nk, w1);
    }
    const V inv_c2 = O::set1(s.inv_c2), lowpass = O::set1(s.lowpass);
    const V v00 = O::add(O::mul(O::add(O::mul(j00, j00), O::mul(j01, j01)), inv_c2), lowpass);
    const V v01 = O::mul(O::add(O::mul(j00, j10), O::mul(j01, j11)), inv_c2);
    const V v11 = O::add(O::mul(O::add(O::mul(j10, j10), O::mul(j11, j11)), inv_c2), lowpass);
    const V det = O::sub(O::mul(v00, v11), O::mul(v01, v01));
    good = O::and_(good, O::and_(O::gt(det, zero), O::finite(det)));
    const V q00 = O::div(v11, det), q01 = O::div(O::xor_(v01, O::set1(-0.0f)), det),
                 q11 = O::div(v00, det);

    const V detj = O::sub(O::mul(j00, j11), O::mul(j01, j10));
    const V plane = O::and_(
        O::gt(O::fabs(detj), O::mul(O::set1(1e-6f), O::add(O::fabs(O::mul(j00, j11)), O::fabs(O::mul(j01, j10))))),
        O::neq(detj, zero));
    const V neg = O::set1(-0.0f);
    const V gx = O::and_(plane, O::div(O::xor_(O::sub(O::mul(u2, j11), O::mul(w2, j10)), neg), detj));
    const V gy = O::and_(plane, O::div(O::xor_(O::sub(O::mul(w2, j00), O::mul(u2, j01)), neg), detj));
    const V c = O::set1(std::sqrt(s.c2));
    const V exv = O::mul(c, O::sqrt(v00)), eyv = O::mul(c, O::sqrt(v11));

    alignas(32) float o[18][W];
    const V outs[18] = {sx, sy, q00, q01, q11, D, gx, gy, r, n0, n1, n2, exv, eyv, good, zero, zero, zero};
    for (int j = 0; j < 15; ++j) O::store(o[j], outs[j]);
    for (int i = 0; i < W; ++i) {
        ok[i] = false;
        if (std::bit_cast<std::uint32_t>(o[14][i]) == 0) continue;
        Footprint& g = f[i];
        g.sx = o[0][i];
        g.sy = o[1][i];
        g.q00 = o[2][i];
        g.q01 = o[3][i];
        g.q11 = o[4][i];
        g.depth = o[5][i];
        g.gx = o[6][i];
        g.gy = o[7][i];
        g.radius = o[8][i];
        g.n[0] = o[9][i];
        g.n[1] = o[10][i];
        g.n[2] = o[11][i];
        const float ex = o[12][i], ey = o[13][i];
        const float fx0 = std::ceil(g.sx - ex - 0.5f), fx1 = std::floor(g.sx + ex - 0.5f);
        const float fy0 = std::ceil(g.sy - ey - 0.5f), fy1 = std::floor(g.sy + ey - 0.5f);
        if (!(fx1 >= 0 && fy1 >= 0 && fx0 <= s.W - 1 && fy0 <= s.H - 1 && fx0 <= fx1 && fy0 <= fy1)) continue;
        g.x0 = static_cast<std::uint16_t>(std::max(fx0, 0.0f));
        g.x1 = static_cast<std::uint16_t>(std::min(fx1, float(s.W - 1)));
        g.y0 = static_cast<std::uint16_t>(std::max(fy0, 0.0f));
        g.y1 = static_cast<std::uint16_t>(std::min(fy1, float(s.H - 1)));
        g.base = 0;
        ok[i] = true;
    }
}
