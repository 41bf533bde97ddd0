// An MPU field built part by part (kernels/field_region.hpp, docs/architecture.md "Fields out of
// core"): a build over the points of a slab and the balls its lists asked for, with the whole
// set's frame, evaluates in the slab's query box to the bits of the field built over every point
// (values and gradients), on data with dense clusters and sparse regions (grown and pruned leaves),
// with the points given in any order; a build that lacked points says so, names the balls it
// needs and holds no fits to evaluate.
#include <catch2/catch.hpp>

#include "test_size.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "kernels/errors.hpp"
#include "kernels/field_params.hpp"
#include "kernels/field_region.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/mpu_fit_cache.hpp"

using namespace meshless;
using meshless::test::test_size;

namespace {

PointSet points_of(const std::vector<Vec3>& pos) {
    PointSet ps;
    ps.pos = pos;
    for (const Vec3& p : pos) ps.value.push_back(100 * std::sqrt(p.x * p.x + 0.7 * p.y * p.y + 1.3 * p.z * p.z) + 20 * std::sin(9 * p.x));
    ps.blocks.push_back({"scattered", {static_cast<std::int64_t>(pos.size()), 1, 1}, 0, pos.size()});
    return ps;
}

// Dense blobs, a sparse background and an empty corner: leaves that split, grow and prune.
std::vector<Vec3> uneven_points(std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::normal_distribution<double> g(0.0, 0.08);
    std::vector<Vec3> p;
    // half the points in the sanitizer tier (tests/test_size.hpp): the same kinds of leaves
    for (int i = 0; i < test_size(4000, 2000); ++i) {
        const Vec3 v{u(rng), u(rng), 2 * u(rng)};
        if (!(v.x > 0.3 && v.y > 0.3)) p.push_back(v);
    }
    for (const Vec3 c : {Vec3{-0.5, -0.5, -0.1}, Vec3{0.2, -0.4, 0.3}, Vec3{-0.3, 0.5, 1.2}})
        for (int i = 0; i < test_size(6000, 3000); ++i) p.push_back({c.x + g(rng), c.y + g(rng), c.z + 2 * g(rng)});
    return p;
}

bool inside(const Vec3& p, const std::array<Vec3, 2>& b) {
    return p.x >= b[0].x && p.x <= b[1].x && p.y >= b[0].y && p.y <= b[1].y && p.z >= b[0].z && p.z <= b[1].z;
}

double dist(const Vec3& a, const Vec3& b) { return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z)); }

struct RegionRun {
    int builds = 0;
    std::size_t given = 0;
    std::uint64_t pruned = 0;
};

// Builds the region field of the z slab [z0, z1] (queries) as a caller with point counts would:
// the points of z0 - halo .. z1 + halo, then those of every lacking ball, until exact; compares
// it with `whole` at queries in the query box.
RegionRun check_slab(const std::vector<Vec3>& all, const MpuField& whole, const FieldParams& params, double z0, double z1,
                     double halo, bool with_counts, MpuFitCache* cache = nullptr, double keep_from = INFINITY,
                     bool falling = false) {
    const PointSet ws = points_of(all);
    FieldRegion region;
    region.frame = field_frame_of(all);
    region.query = {Vec3{-2, -2, z0}, Vec3{2, 2, z1}};
    region.loaded = {Vec3{-INFINITY, -INFINITY, z0 - halo}, Vec3{INFINITY, INFINITY, z1 + halo}};
    std::vector<char> given(all.size(), 0);
    for (std::size_t i = 0; i < all.size(); ++i) given[i] = inside(all[i], region.loaded);
    if (with_counts) {
        region.missing = [&](const Vec3& c, double r) {
            std::uint64_t n = 0;
            for (std::size_t i = 0; i < all.size(); ++i) n += !given[i] && dist(all[i], c) <= r;
            return n;
        };
        region.present = [&](const Vec3& c, double r) {  // a lower bound: half of those there are
            std::uint64_t n = 0;
            for (const Vec3& p : all) n += dist(p, c) <= r;
            return n / 2;
        };
    }
    RegionRun run;
    std::mt19937_64 rng(5);
    for (;;) {
        REQUIRE(run.builds < 30);
        std::vector<Vec3> part;
        for (std::size_t i = 0; i < all.size(); ++i)
            if (given[i]) part.push_back(all[i]);
        std::shuffle(part.begin(), part.end(), rng);  // (any order)
        if (cache) cache->begin(keep_from, falling);
        const MpuField f(points_of(part), params, nullptr, {}, nullptr, &region, cache);
        ++run.builds;
        if (!f.region_exact()) {
            REQUIRE(!f.lacking_balls().empty());
            std::vector<double> v(1);
            std::vector<Vec3> q{Vec3{0, 0, 0.5 * (z0 + z1)}}, gr(1);
            CHECK_THROWS_AS(f.evaluate(q, v, gr), InvalidArgument);
            std::size_t added = 0;
            for (const auto& [c, r] : f.lacking_balls())
                for (std::size_t i = 0; i < all.size(); ++i)
                    if (!given[i] && dist(all[i], c) <= r) given[i] = 1, ++added;
            if (!with_counts && added == 0) {  // without counts: widen the loaded box
                halo *= 2;
                region.loaded = {Vec3{-INFINITY, -INFINITY, z0 - halo}, Vec3{INFINITY, INFINITY, z1 + halo}};
                for (std::size_t i = 0; i < all.size(); ++i) given[i] = given[i] || inside(all[i], region.loaded);
            }
            REQUIRE((added > 0 || !with_counts));
            continue;
        }
        if (cache) cache->advance();
        run.given = part.size();
        run.pruned = f.pruned_nodes();
        std::uniform_real_distribution<double> ux(-1.0, 1.0), uz(z0, z1);
        std::vector<Vec3> q(3000);
        for (Vec3& p : q) p = {ux(rng), ux(rng), uz(rng)};
        std::vector<double> a(q.size()), b(q.size());
        std::vector<Vec3> ga(q.size()), gb(q.size());
        whole.evaluate(q, a, ga);
        f.evaluate(q, b, gb);
        std::size_t differ = 0;
        for (std::size_t i = 0; i < q.size(); ++i)
            differ += !(a[i] == b[i] && ga[i].x == gb[i].x && ga[i].y == gb[i].y && ga[i].z == gb[i].z);
        CHECK(differ == 0);
        return run;
    }
}

}  // namespace

TEST_CASE("an MPU field built over a slab evaluates there to the whole field's bits", "[kernels][mpu][region]") {
    const std::vector<Vec3> all = uneven_points(3);
    FieldParams params;
    params.kind = FieldKind::mpu;
    const MpuField whole(points_of(all), params);
    SECTION("with the store's counts: only the lacking balls are added") {
        const RegionRun lo = check_slab(all, whole, params, -1.5, -0.8, 0.1, true);
        const RegionRun mid = check_slab(all, whole, params, -0.1, 0.4, 0.1, true);
        CHECK(lo.given < all.size());
        CHECK(mid.given < all.size());
        CHECK(lo.builds + mid.builds > 2);  // (the sparse background asks for far points)
        CHECK(lo.pruned > 0);
        CHECK(mid.pruned > 0);
    }
    SECTION("without counts: the loaded box widens until every list lies inside it") {
        const RegionRun mid = check_slab(all, whole, params, 0.9, 1.3, 0.05, false);
        CHECK(mid.builds >= 1);
    }
}

TEST_CASE("a region build with an unbounded loaded box is exact at once", "[kernels][mpu][region]") {
    const std::vector<Vec3> all = uneven_points(4);
    FieldParams params;
    params.kind = FieldKind::mpu;
    const MpuField whole(points_of(all), params);
    const RegionRun r = check_slab(all, whole, params, -2, 2, INFINITY, false);
    CHECK(r.builds == 1);
    CHECK(r.given == all.size());
}

TEST_CASE("fits kept from one slab serve the next with the same bits", "[kernels][mpu][region]") {
    const std::vector<Vec3> all = uneven_points(6);
    FieldParams params;
    params.kind = FieldKind::mpu;
    const MpuField whole(points_of(all), params);
    MpuFitCache cache;
    check_slab(all, whole, params, -1.5, -0.6, 0.1, true, &cache, -0.9);
    CHECK(cache.bytes() > 0);
    CHECK(cache.hits() == 0);
    check_slab(all, whole, params, -0.9, 0.0, 0.1, true, &cache, INFINITY);  // compared with the whole field's bits
    CHECK(cache.hits() > 0);
    const std::uint64_t hits = cache.hits();
    cache.clear();
    CHECK(cache.bytes() == 0);
    check_slab(all, whole, params, 0.0, 0.5, 0.1, true, &cache, INFINITY);  // nothing kept: every fit solved
    CHECK(cache.hits() == hits);
    // slabs taken from the top down keep the fits reaching down into the next one
    MpuFitCache down;
    check_slab(all, whole, params, 0.0, 0.9, 0.1, true, &down, 0.0, /*falling=*/true);
    CHECK(down.bytes() > 0);
    check_slab(all, whole, params, -0.9, 0.0, 0.1, true, &down, -INFINITY, true);  // compared with the whole field's bits
    CHECK(down.hits() > 0);
}

TEST_CASE("a fit is known by its cube and the bits of its list", "[kernels][mpu][region]") {
    const std::vector<Vec3> pos{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    std::vector<double> val{1, 2, 3, 4};
    const std::vector<std::uint32_t> idx{0, 1, 2, 3}, swapped{0, 2, 1, 3};
    const MpuFitCache::Key k = MpuFitCache::key_of({0.5, 0.5, 0.5}, 0.5, pos, val, idx);
    CHECK(k == MpuFitCache::key_of({0.5, 0.5, 0.5}, 0.5, pos, val, idx));
    CHECK(!(k == MpuFitCache::key_of({0.5, 0.5, 0.5}, 0.25, pos, val, idx)));
    CHECK(!(k == MpuFitCache::key_of({0.5, 0.5, 0.5}, 0.5, pos, val, swapped)));
    CHECK(!(k == MpuFitCache::key_of({0.5, 0.5, 0.5}, 0.5, pos, val, std::vector<std::uint32_t>{0, 1, 2})));
    val[3] = std::nextafter(4.0, 5.0);
    CHECK(!(k == MpuFitCache::key_of({0.5, 0.5, 0.5}, 0.5, pos, val, idx)));
    MpuFitCache cache;
    cache.begin(0);
    CHECK(cache.keeps(-1, 0.0));
    CHECK(!cache.keeps(-1, -0.1));
    cache.begin(0, /*falling=*/true);
    CHECK(cache.keeps(0.0, 1));
    CHECK(!cache.keeps(0.1, 1));
    cache.begin(0);
    cache.keep(k, MpuFitCache::Fit{MultiquadricLocal{}, {1, 2, 3, 4}, MultiquadricOutcome::interpolated, 0});
    CHECK(cache.find(k) == nullptr);  // (kept for the next build)
    cache.advance();
    REQUIRE(cache.find(k) != nullptr);
    CHECK(cache.find(k)->lambda.size() == 4);
}

TEST_CASE("a region build whose field would exceed its budget stops before the fits and says its size", "[kernels][mpu][region]") {
    const std::vector<Vec3> all = uneven_points(7);
    FieldParams params;
    params.kind = FieldKind::mpu;
    FieldRegion region;
    region.frame = field_frame_of(all);
    region.query = {Vec3{-2, -2, -0.5}, Vec3{2, 2, 0.5}};
    FieldBuildStats free_st;
    const MpuField free_field(points_of(all), params, &free_st, {}, nullptr, &region);
    REQUIRE(free_field.region_exact());
    CHECK(!free_field.over_budget());
    region.max_field_bytes = free_st.memory_bytes / 2;
    FieldBuildStats st;
    const MpuField tight(points_of(all), params, &st, {}, nullptr, &region);
    CHECK(tight.over_budget());
    CHECK(st.memory_bytes > region.max_field_bytes);
    CHECK(st.memory_bytes <= free_st.memory_bytes);  // (the octree's share: the lookup grid comes with the fits)
    CHECK(st.locals == free_st.locals);
    std::vector<double> v(1);
    std::vector<Vec3> q{Vec3{0, 0, 0}}, gr(1);
    CHECK_THROWS_AS(tight.evaluate(q, v, gr), InvalidArgument);
    region.max_field_bytes = free_st.memory_bytes;
    const MpuField roomy(points_of(all), params, nullptr, {}, nullptr, &region);
    CHECK(!roomy.over_budget());
    std::vector<double> a(1), b(1);
    std::vector<Vec3> ga(1), gb(1);
    free_field.evaluate(q, a, ga);
    roomy.evaluate(q, b, gb);
    CHECK(a[0] == b[0]);
}
