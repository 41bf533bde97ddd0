// Hardy's c sized to each local fit (kernels/local_spacing.hpp, FieldParams::hardy_c_spacing) and the
// MPU fit sphere (kernels/mpu_field.hpp): oracles are a lattice whose spacing is known, the data
// itself (interpolation), and the count of ill-conditioned locals on dense data with a sharp edge.
#include <catch2/catch.hpp>

#include "test_size.hpp"

#include <cmath>
#include <random>
#include <vector>

#include "kernels/field_params.hpp"
#include "kernels/local_spacing.hpp"
#include "kernels/make_field.hpp"
#include "kernels/multiquadric.hpp"
#include "kernels/point_set.hpp"

using namespace meshless;
using meshless::test::test_size;

namespace {

std::vector<Vec3> uniform(std::size_t n, unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Vec3> out(n);
    for (auto& p : out) p = {u(rng), u(rng), u(rng)};
    return out;
}

// A CT-like step: 0 on one side of a tilted plane, 100 on the other, plus a gentle ramp.
double step(const Vec3& p) { return (p.x + 0.3 * p.y - 0.2 * p.z > 0.55 ? 100.0 : 0.0) + 5 * p.z; }

PointSet make_points(const std::vector<Vec3>& pos) {
    PointSet ps;
    ps.pos = pos;
    for (const Vec3& p : pos) ps.value.push_back(step(p));
    ps.blocks.push_back({"scattered", {static_cast<std::int64_t>(pos.size()), 1, 1}, 0, pos.size()});
    return ps;
}

double worst_at_data(const Field& f, const PointSet& ps) {
    std::vector<double> v(ps.pos.size());
    f.evaluate(ps.pos, v, {});
    double worst = 0;
    for (std::size_t i = 0; i < v.size(); ++i) worst = std::max(worst, std::abs(v[i] - ps.value[i]));
    return worst;
}

}  // namespace

TEST_CASE("mean_neighbour_spacing: a lattice's spacing, a pair's distance, nothing for one point", "[rbf][hardy-c]") {
    std::vector<Vec3> pos;
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 5; ++j)
            for (int i = 0; i < 6; ++i) pos.push_back({0.25 * i + 3, 0.25 * j - 1, 0.25 * k});
    std::vector<std::uint32_t> all(pos.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    CHECK(mean_neighbour_spacing(pos, all) == Approx(0.25).epsilon(1e-12));
    const std::vector<std::uint32_t> pair{0, 29};  // (3,-1,0) and (3.25,-1,0.25)... the 30th point
    const Vec3 d = pos[29] - pos[0];
    CHECK(mean_neighbour_spacing(pos, pair) == Approx(norm(d)).epsilon(1e-12));
    CHECK(mean_neighbour_spacing(pos, std::vector<std::uint32_t>{7}) == 0.0);
    CHECK(mean_neighbour_spacing(pos, std::vector<std::uint32_t>{}) == 0.0);
    // the cap: min(global c, K x spacing); off with K = 0 or an unknown spacing
    FieldParams p;
    p.hardy_c_spacing = 2;
    CHECK(hardy_c_local(p, 1.0, 0.1) == Approx(0.2));
    CHECK(hardy_c_local(p, 0.1, 1.0) == 0.1);
    CHECK(hardy_c_local(p, 0.5, 0.0) == 0.5);
    p.hardy_c_spacing = 0;
    CHECK(hardy_c_local(p, 1.0, 0.1) == 1.0);
}

TEST_CASE("dense data with a sharp edge: local c keeps the locals well conditioned, and interpolating", "[rbf][hardy-c]") {
    // 60,000 points in the unit cube, nearest-neighbour spacing ~0.0086. A c of 0.15 x diagonal
    // (0.26, ~30x the spacing: what the paper's relative c becomes on ~10^7 points) makes many locals
    // ill-conditioned; capped at 8x each local's spacing, and refitted at 1x where still
    // ill-conditioned, the locals interpolate.
    const PointSet ps = make_points(uniform(test_size(60000, 20000), 11));  // (tests/test_size.hpp)
    for (FieldKind kind : {FieldKind::mpu, FieldKind::rbf_grid}) {
        INFO(field_kind_name(kind));
        FieldParams local;
        local.kind = kind;
        // a third of the points in the sanitizer tier: c grown as their spacing, (60000 / 20000)^(1/3)
        local.hardy_c_rel = test_size(0.15, 0.22);
        FieldParams global = local;
        global.hardy_c_spacing = 0;
        global.hardy_c_rough = 0;
        FieldBuildStats sl, sg;
        const auto fl = make_field(ps, local, &sl);
        const auto fg = make_field(ps, global, &sg);
        REQUIRE(sl.locals == sg.locals);
        CHECK(sg.c_lowered == 0);
        CHECK(sg.refitted == 0);
        CHECK(sg.mean_local_c == Approx(sg.hardy_c_world).epsilon(1e-9));
        CHECK(sg.regularised * 30 > sg.locals);  // the premise: the global c is too large here (4-6 %)
        CHECK(sl.c_lowered > sl.locals / 2);
        CHECK(sl.mean_local_c < sl.hardy_c_world / 2);
        // at most 1 % of the locals need a ridge (so they interpolate), and far fewer than with the global c
        CHECK(sl.regularised * 100 <= sl.locals);
        CHECK(sl.regularised * 10 < sg.regularised);
        CHECK(sl.linear_fallback == 0);
        // interpolation: every local that weighs at a data point was fitted to it
        CHECK(worst_at_data(*fl, ps) <= 1e-6 * 105);
    }
}

TEST_CASE("mpu: a local fits its blend sphere's points, or its nearest min points, at any density", "[rbf][hardy-c]") {
    // Two densities a factor 8 apart end at the same octree depth in some regions and one deeper in
    // others; the fits stay about mpu_min_points large instead of up to N (the MPU sphere's count).
    for (std::size_t n : {test_size(20000u, 5000u), test_size(70000u, 17500u)}) {  // (tests/test_size.hpp)
        INFO(n);
        const PointSet ps = make_points(uniform(n, 12));
        FieldParams p;
        p.kind = FieldKind::mpu;
        FieldBuildStats st;
        const auto f = make_field(ps, p, &st);
        CHECK(st.mean_local_points >= p.mpu_min_points);
        CHECK(st.mean_local_points <= 1.25 * p.mpu_min_points);
        CHECK(st.max_local_points < p.mpu_max_points);
        CHECK(worst_at_data(*f, ps) <= 1e-6 * 105);
    }
}

TEST_CASE("leave-one-out error of a multiquadric fit: Rippa's formula equals refitting without each point", "[rbf][hardy-c]") {
    const auto pos = uniform(40, 21);
    std::vector<double> val;
    for (const Vec3& p : pos) val.push_back(step(p) + 30 * std::sin(4 * p.y));
    std::vector<std::uint32_t> all(pos.size());
    for (std::uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    for (const char* isa : {"generic", "avx2"}) {
        if (!multiquadric_fit_isa_available(isa)) continue;
        INFO(isa);
        MultiquadricSolver solver(isa);
        for (double c : {0.05, 0.2}) {
            INFO("c " << c);
            MultiquadricLocal h;
            std::vector<double> lambda(all.size());
            const MultiquadricFitResult res = solver.fit(pos, val, all, c, h, lambda, true);
            REQUIRE(res.outcome == MultiquadricOutcome::interpolated);
            double sum = 0;
            for (std::uint32_t k = 0; k < all.size(); ++k) {  // brute force: fit the other 39, predict point k
                std::vector<std::uint32_t> others;
                for (std::uint32_t i : all)
                    if (i != k) others.push_back(i);
                MultiquadricLocal hk;
                std::vector<double> lk(others.size());
                REQUIRE(solver.fit(pos, val, others, c, hk, lk).outcome == MultiquadricOutcome::interpolated);
                const double e = val[k] - multiquadric_evaluate(hk, pos.data(), others.data(), lk.data(), pos[k], nullptr);
                sum += e * e;
            }
            const double brute = std::sqrt(sum / static_cast<double>(all.size()));
            CHECK(brute > 0.1);
            CHECK(res.loo == Approx(brute).epsilon(1e-6));
            // not asked: not computed
            CHECK(solver.fit(pos, val, all, c, h, lambda).loo == -1);
        }
    }
}

TEST_CASE("the second, narrow c is kept at sharp edges and rarely on smooth data", "[rbf][hardy-c]") {
    const auto pos = uniform(test_size(30000, 8000), 31);  // (tests/test_size.hpp)
    PointSet smooth = make_points(pos);
    for (std::size_t i = 0; i < pos.size(); ++i)
        smooth.value[i] = std::sin(3 * pos[i].x) * std::cos(2 * pos[i].y) + pos[i].z * pos[i].z;
    const PointSet edge = make_points(pos);
    for (FieldKind kind : {FieldKind::mpu, FieldKind::rbf_grid}) {
        INFO(field_kind_name(kind));
        FieldParams p;
        p.kind = kind;
        FieldParams one = p;
        one.hardy_c_rough = 0;
        FieldBuildStats ss, se, s1;
        const auto fs = make_field(smooth, p, &ss);
        const auto fe = make_field(edge, p, &se);
        const auto f1 = make_field(smooth, one, &s1);
        CHECK(ss.refitted * 10 < ss.locals);
        CHECK(se.refitted > ss.refitted);
        CHECK(s1.refitted == 0);
        // on smooth data the choice costs no accuracy: within 5 % of the single wide fit's error
        const auto at = uniform(5000, 32);
        std::vector<double> vs(at.size()), v1(at.size());
        fs->evaluate(at, vs, {});
        f1->evaluate(at, v1, {});
        double es = 0, e1 = 0;
        for (std::size_t i = 0; i < at.size(); ++i) {
            if (at[i].x < 0.05 || at[i].x > 0.95 || at[i].y < 0.05 || at[i].y > 0.95 || at[i].z < 0.05 || at[i].z > 0.95) continue;
            const double t = std::sin(3 * at[i].x) * std::cos(2 * at[i].y) + at[i].z * at[i].z;
            es += (vs[i] - t) * (vs[i] - t);
            e1 += (v1[i] - t) * (v1[i] - t);
        }
        CHECK(std::sqrt(es) <= 1.05 * std::sqrt(e1));
        CHECK(worst_at_data(*fe, edge) <= 1e-6 * 105);
    }
}
