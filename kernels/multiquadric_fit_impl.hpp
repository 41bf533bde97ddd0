// The body of MultiquadricSolver::fit (kernels/multiquadric.hpp: the method, its outcomes and
// bounds), included by the instruction-set builds of kernels/multiquadric_fit_isa.hpp only:
// multiquadric_fit_generic.cpp and multiquadric_fit_avx2.cpp. Everything here has internal
// linkage; the including file defines its Kernel from mqfit_create/mqfit_destroy/mqfit_fit.
// Uses only Eigen's storage (no std::vector), so the AVX2 build instantiates no std template.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <Eigen/QR>

#include "kernels/multiquadric_fit_isa.hpp"
#include "kernels/vec3.hpp"

namespace meshless {
namespace {

constexpr double kGrowthMax = 1e8;        // sum|lambda| * max phi over the data range: bounds the
                                          // cancellation error of evaluating H to ~1e-8 of the range
constexpr double kRcondRidge = 1e-10;     // a ridge-regularised system must be at least this well conditioned
constexpr double kLinearRel = 1e-12;      // data this close to its least-squares linear fit is linear
constexpr double kResidualRel = 1e-8;     // exact solve must interpolate to this fraction of the data range
constexpr double kRankThreshold = 1e-10;  // relative pivot threshold of the polynomial QR
// outcomes, as meshless::MultiquadricOutcome
constexpr int kInterpolated = 0, kRegularised = 1, kLinearFallback = 2, kPolynomialOnly = 3;

using MapM = Eigen::Map<Eigen::MatrixXd>;

// Scratch kept at the largest size seen: the n x n matrices live in buffers that only grow, viewed
// through Maps, so consecutive fits of different sizes neither reallocate nor touch fresh pages
// (per-fit reallocation of the ~n^2 x 8-byte matrices cost ~40% of a fit in page faults).
struct Workspace {
    Eigen::VectorXd a_buf, m_buf, s_buf;
    Eigen::MatrixXd P;
    Eigen::VectorXd g, rhs, mu, lam, t, r;
    Eigen::VectorXd li_buf, inv_tmp;  // leave-one-out: L^-1 (m x m) and lower_inverse's scratch
    Eigen::MatrixXd V, U, Y, X; // the reflectors as a block (n x h): V, V T, A V T, Y_b - V_b K / 2
    Eigen::MatrixXd W, B;       // leave-one-out: V_b T^T and L^-1 of it (m x h)
    Eigen::VectorXd y;          // leave-one-out: L^-1 z_k
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr;
    static double* square(Eigen::VectorXd& b, Eigen::Index n) {
        if (b.size() < n * n) b.resize(n * n);
        return b.data();
    }
};

// X = L^-1 for the lower triangle L of an k x k block (X: k x k; only its lower triangle is written,
// and zeros above the diagonal inside the diagonal blocks of <= 16 columns), by
// halves: [L11 0; L21 L22]^-1 = [X11 0; -X22 L21 X11, X22], so the work is the m^3/3 flops of the
// inverse in matrix products, where one triangular solve of the identity does m^3 (it does not
// know the right-hand side's zeros). tmp: scratch that only grows.
using RefM = Eigen::Ref<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
using RefCM = Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
void lower_inverse(RefCM L, RefM X, Eigen::VectorXd& tmp) {
    const Eigen::Index k = L.rows();
    if (k <= 16) {
        X.setIdentity();
        L.triangularView<Eigen::Lower>().solveInPlace(X);
        return;
    }
    const Eigen::Index a = k / 2, b = k - a;
    lower_inverse(L.topLeftCorner(a, a), X.topLeftCorner(a, a), tmp);
    lower_inverse(L.bottomRightCorner(b, b), X.bottomRightCorner(b, b), tmp);
    if (tmp.size() < a * b) tmp.resize(a * b);
    MapM P(tmp.data(), b, a);
    P.noalias() = L.bottomLeftCorner(b, a) * X.topLeftCorner(a, a).triangularView<Eigen::Lower>();
    X.bottomLeftCorner(b, a).noalias() = -(X.bottomRightCorner(b, b).triangularView<Eigen::Lower>() * P);
    // (the top-right block is left as it was: every reader takes the lower triangle)
}

void* mqfit_create() { return new Workspace; }
void mqfit_destroy(void* w) { delete static_cast<Workspace*>(w); }

inline Vec3 point_at(const meshless_mqfit::Io& io, std::uint32_t i) {
    const double* q = io.pos + 3 * static_cast<std::size_t>(i);
    return {q[0], q[1], q[2]};
}

void mqfit_fit(void* ws, meshless_mqfit::Io& io) {
    Workspace& w = *static_cast<Workspace*>(ws);
    const Eigen::Index n = static_cast<Eigen::Index>(io.n);
    const std::uint32_t* idx = io.idx;
    const double c = io.c;
    io.c2 = c * c;
    io.count = 0;
    io.a[0] = io.a[1] = io.a[2] = 0;
    io.outcome = kInterpolated;
    io.poly_rank = 4;
    io.rcond = 0;
    io.loo = -1;
    auto set_a = [&](const Vec3& a) { io.a[0] = a.x; io.a[1] = a.y; io.a[2] = a.z; };

    // Centre and scale.
    Vec3 o{0, 0, 0};
    double fbar = 0;
    for (Eigen::Index k = 0; k < n; ++k) { o += point_at(io, idx[k]); fbar += io.value[idx[k]]; }
    o = o * (1.0 / static_cast<double>(n));
    fbar /= static_cast<double>(n);
    double L = 0, gmax = 0;
    for (Eigen::Index k = 0; k < n; ++k) {
        L = std::max(L, norm(point_at(io, idx[k]) - o));
        gmax = std::max(gmax, std::abs(io.value[idx[k]] - fbar));
    }
    io.origin[0] = o.x;
    io.origin[1] = o.y;
    io.origin[2] = o.z;
    io.a0 = fbar;
    if (n == 1 || !(L > 0)) {
        io.outcome = kPolynomialOnly;
        io.poly_rank = 1;
        return;
    }
    const double invL = 1.0 / L;
    w.P.resize(n, 4);
    w.g.resize(n);
    for (Eigen::Index k = 0; k < n; ++k) {
        const Vec3 q = (point_at(io, idx[k]) - o) * invL;
        w.P(k, 0) = 1;
        w.P(k, 1) = q.x;
        w.P(k, 2) = q.y;
        w.P(k, 3) = q.z;
        w.g(k) = io.value[idx[k]] - fbar;
    }
    w.qr.setThreshold(kRankThreshold);
    w.qr.compute(w.P);
    const Eigen::Index r = w.qr.rank();
    io.poly_rank = static_cast<int>(r);

    auto set_poly = [&](const Eigen::VectorXd& rhs) {
        const Eigen::Vector4d a = w.qr.solve(rhs);
        io.a0 = fbar + a(0);
        set_a(Vec3{a(1), a(2), a(3)} * invL);
    };
    if (gmax == 0) {  // constant data: exact with the constant alone
        io.outcome = kInterpolated;
        return;
    }
    if (n <= r) {
        set_poly(w.g);
        io.outcome = kPolynomialOnly;
        return;
    }
    {   // Linear data (to rounding): the polynomial alone interpolates it exactly. Solving the
        // (possibly ill-conditioned) RBF part would only amplify rounding noise.
        const Eigen::Vector4d a = w.qr.solve(w.g);
        if ((w.P * a - w.g).cwiseAbs().maxCoeff() <= kLinearRel * (std::abs(fbar) + gmax)) {
            set_poly(w.g);
            io.outcome = kInterpolated;
            return;
        }
    }

    // Multiquadric matrix in scaled coordinates.
    const double cs2 = (c * invL) * (c * invL);
    MapM A(Workspace::square(w.a_buf, n), n, n);
    {   // lower triangle column by column, packet-wide (sqrt is correctly rounded in every lane,
        // the sum is left to right as written: the same bits as a scalar loop)
        const auto qx = w.P.col(1).array(), qy = w.P.col(2).array(), qz = w.P.col(3).array();
        for (Eigen::Index j = 0; j < n; ++j) {
            const Eigen::Index len = n - j;
            A.col(j).tail(len).array() = ((qx.tail(len) - qx(j)).square() + (qy.tail(len) - qy(j)).square() +
                                          (qz.tail(len) - qz(j)).square() + cs2)
                                             .sqrt();
        }
    }  // only the lower triangle of A (and of M below) is ever read
    // Null-space reduction: Z = trailing n-r columns of Q; S = -Z^T A Z is SPD.
    const auto Q = w.qr.householderQ();
    // The h <= 4 reflectors H_k = I - tau_k v_k v_k^T as one block (LAPACK's larft): Q = H_0 .. H_{h-1}
    // = I - V T V^T, V unit lower trapezoidal (n x h), T upper triangular. Then Z = E - U V_b^T
    // (E: the last m columns of I, U = V T, V_b = the last m rows of V) and, with Y = A U,
    // K = U^T Y and X = Y_b - V_b K / 2 (Y_b: the last m rows of Y),
    //   Z^T A Z = A_bb - X V_b^T - V_b X^T      (A_bb: A's trailing m x m block),
    // a rank-2h update of the lower triangle of A_bb: one pass over the matrix, where applying the
    // reflectors one by one from both sides (symmetric rank-2 updates) took four over all of A.
    const Eigen::Index h = w.qr.hCoeffs().size();
    const Eigen::Index m = n - r;
    Eigen::Matrix4d T = Eigen::Matrix4d::Zero();
    w.V.setZero(n, h);
    for (Eigen::Index k = 0; k < h; ++k) {
        w.V(k, k) = 1;
        w.V.col(k).tail(n - k - 1) = w.qr.matrixQR().col(k).tail(n - k - 1);
        const double tau = w.qr.hCoeffs()(k);
        T(k, k) = tau;
        for (Eigen::Index i = 0; i < k; ++i) {  // T(0:k, k) = -tau T(0:k, 0:k) V(:, 0:k)^T v_k
            double acc = 0;
            for (Eigen::Index j = i; j < k; ++j) acc += T(i, j) * w.V.col(j).dot(w.V.col(k));
            T(i, k) = -tau * acc;
        }
    }
    w.U.noalias() = w.V * T.topLeftCorner(h, h);
    w.Y.noalias() = A.selfadjointView<Eigen::Lower>() * w.U;
    const Eigen::Matrix4d K = [&] {
        Eigen::Matrix4d k4 = Eigen::Matrix4d::Zero();
        k4.topLeftCorner(h, h).noalias() = w.U.transpose() * w.Y;
        return k4;
    }();
    w.X.noalias() = w.Y.bottomRows(m) - 0.5 * (w.V.bottomRows(m) * K.topLeftCorner(h, h));
    MapM M(Workspace::square(w.m_buf, m), m, m);  // Z^T A Z, lower triangle
    M.triangularView<Eigen::Lower>() = A.bottomRightCorner(m, m);
    M.triangularView<Eigen::Lower>() -= w.X * w.V.bottomRows(m).transpose();
    M.triangularView<Eigen::Lower>() -= w.V.bottomRows(m) * w.X.transpose();
    w.t = Q.adjoint() * w.g;
    w.rhs = -w.t.tail(m);
    const double diag_mean = -M.diagonal().mean();

    MapM S(Workspace::square(w.s_buf, m), m, m);
    using InPlaceLlt = Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>>;  // factors S in place (lower triangle)
    auto fill_s = [&](double ridge) {
        S.triangularView<Eigen::Lower>() = -M;
        if (ridge != 0) S.diagonal().array() += ridge;
    };
    auto finish = [&](const InPlaceLlt& llt, int oc) -> bool {
        w.mu = llt.solve(w.rhs);
        if (!w.mu.allFinite()) return false;
        w.t.setZero(n);
        w.t.tail(m) = w.mu;
        w.lam = Q * w.t;
        w.r = w.g - A.selfadjointView<Eigen::Lower>() * w.lam;  // what the polynomial must carry
        const Eigen::Vector4d a = w.qr.solve(w.r);
        if (!a.allFinite() || !w.lam.allFinite()) return false;
        // Amplified rounding noise shows up as large, cancelling coefficients.
        if (!(w.lam.cwiseAbs().sum() * (3.0 + std::sqrt(cs2)) <= kGrowthMax * gmax)) return false;
        if (oc == kInterpolated) {
            const double resid = (w.P * a - w.r).cwiseAbs().maxCoeff();
            if (!(resid <= kResidualRel * gmax)) return false;
        }
        io.a0 = fbar + a(0);
        set_a(Vec3{a(1), a(2), a(3)} * invL);
        io.count = static_cast<std::uint32_t>(n);
        for (Eigen::Index k = 0; k < n; ++k) io.lambda[k] = w.lam(k) * invL;
        io.outcome = oc;
        if (io.want_loo) {
            // Rippa's leave-one-out error of the whole augmented system [A P; P^T 0]: e_k =
            // lambda_k / (its inverse)_kk, whose top-left block is Z (Z^T A Z)^-1 Z^T = -Z S^-1 Z^T,
            // so (inverse)_kk = -|L^-1 z_k|^2 with S = L L^T (z_k: row k of Z).
            // Q = I - V T V^T (the h <= 4 reflectors as one block: V unit lower trapezoidal, T upper
            // triangular, LAPACK's larft), so z_k = e_{k-r} [k >= r] - W V(k, :)^T with W = V(r:, :) T^T,
            // and L^-1 z_k = (column k - r of L^-1) - (L^-1 W) V(k, :)^T: L^-1 costs m^3/3 (its
            // columns start on the diagonal), where L^-1 Z^T over the dense Z took m^2 n.
            w.W.noalias() = w.V.bottomRows(m) * T.topLeftCorner(h, h).transpose();
            MapM Li(Workspace::square(w.li_buf, m), m, m);  // L^-1 (its lower triangle; read only as such)
            lower_inverse(S, Li, w.inv_tmp);
            w.B.noalias() = Li.triangularView<Eigen::Lower>() * w.W;
            double sum = 0;
            for (Eigen::Index k = 0; k < n; ++k) {
                w.y.noalias() = -(w.B * w.V.row(k).transpose());
                if (k >= r) w.y.tail(m - (k - r)) += Li.col(k - r).tail(m - (k - r));
                const double d = w.y.squaredNorm();
                const double e = d > 0 ? w.lam(k) / d : 0.0;
                sum += e * e;
            }
            io.loo = std::sqrt(sum / static_cast<double>(n));
        }
        return true;
    };

    fill_s(0);
    {
        InPlaceLlt llt(S);
        if (llt.info() == Eigen::Success && finish(llt, kInterpolated)) return;
    }
    // a plain array, not an initializer_list: the AVX2 build of this file may define no std:: symbol
    // (an -O1 sanitizer build leaves initializer_list<double>::end() out of line, a weak symbol)
    static constexpr double kRidges[] = {1e-12, 1e-10, 1e-8, 1e-6, 1e-4};
    for (double eps : kRidges) {
        fill_s(eps * std::max(diag_mean, 1e-300));
        InPlaceLlt llt(S);
        if (llt.info() != Eigen::Success) continue;
        io.rcond = llt.rcond();
        if (io.rcond >= kRcondRidge && finish(llt, kRegularised)) return;
    }
    // Linear least squares.
    set_poly(w.g);
    io.count = 0;
    io.outcome = kLinearFallback;
}

}  // namespace
}  // namespace meshless
