// The brick-store field (ooc/brick_field.hpp): the same values and gradients as the trilinear field
// of the whole volume, bit for bit, anywhere (inside, on brick faces, outside: clamped), with a
// cache budget of one brick; the same values at scattered positions grouped by brick (each brick
// read once a call); and the store's bricks as exact value bounds.
#include <catch2/catch.hpp>

#include <random>

#include "kernels/trilinear_field.hpp"
#include "ooc/brick_field.hpp"
#include "ooc/brick_store_values.hpp"
#include "ooc_test_util.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;

TEST_CASE("brick-store field evaluates exactly as the trilinear field of the whole volume", "[render]") {
    test::TempDir d("brickfield");
    for (SampleType t : {SampleType::u8, SampleType::i16, SampleType::f32}) {
        const Volume v = test::random_volume({37, 20, 9}, t);
        const std::string path = (d / "v.mlb").string();
        test::convert_volume(v, path, 8);
        const auto store = BrickStore::open(path);
        BrickCache cache(*store, store->max_brick_bytes());  // one brick: every change of brick is a miss
        const BrickStoreField bf(*store, cache);
        const TrilinearField tf(v.view());
        CHECK(bf.bounds()[0].x == tf.bounds()[0].x);
        CHECK(bf.bounds()[1].z == tf.bounds()[1].z);
        std::mt19937 rng(5);
        const auto [lo, hi] = tf.bounds();
        std::vector<Vec3> p;
        for (int i = 0; i < 4000; ++i) {
            std::uniform_real_distribution<double> x(lo.x - 2, hi.x + 2), y(lo.y - 2, hi.y + 2), z(lo.z - 2, hi.z + 2);
            p.push_back({x(rng), y(rng), z(rng)});
        }
        // brick faces: voxel planes 8, 16, 24, 32 along x
        for (int i = 0; i <= 36; i += 4) p.push_back({v.grid.origin[0] + i * v.grid.spacing[0], lo.y + 3.3, lo.z + 1.1});
        std::vector<double> a(p.size()), b(p.size());
        std::vector<Vec3> ga(p.size()), gb(p.size());
        bf.evaluate(p, a, ga);
        tf.evaluate(p, b, gb);
        for (std::size_t i = 0; i < p.size(); ++i) {
            if (std::isnan(b[i])) {
                CHECK(std::isnan(a[i]));
                continue;
            }
            CHECK(a[i] == b[i]);
            CHECK(ga[i].x == gb[i].x);
            CHECK(ga[i].z == gb[i].z);
        }
        CHECK(cache.stats().misses > 1);
    }
}

TEST_CASE("brick store values at scattered positions: the trilinear field's bits, each brick read once a call", "[render]") {
    test::TempDir d("brickvalues");
    for (SampleType t : {SampleType::u8, SampleType::f32}) {
        const Volume v = test::random_volume({37, 20, 9}, t);
        const std::string path = (d / "v.mlb").string();
        test::convert_volume(v, path, 8);
        const auto store = BrickStore::open(path);
        BrickCache cache(*store, store->max_brick_bytes());  // one brick: a position out of turn would be a miss
        const BrickStoreField bf(*store, cache);
        const TrilinearField tf(v.view());
        std::mt19937 rng(9);
        const auto [lo, hi] = tf.bounds();
        std::uniform_real_distribution<double> x(lo.x - 2, hi.x + 2), y(lo.y - 2, hi.y + 2), z(lo.z - 2, hi.z + 2);
        std::vector<Vec3> p;
        for (int i = 0; i < 5000; ++i) p.push_back({x(rng), y(rng), z(rng)});
        std::vector<double> a(p.size()), b(p.size());
        brick_store_values(*store, bf, p, a);
        tf.evaluate(p, b, {});
        for (std::size_t i = 0; i < p.size(); ++i) {
            if (std::isnan(b[i])) {
                CHECK(std::isnan(a[i]));
                continue;
            }
            CHECK(a[i] == b[i]);
        }
        // 5,000 positions over every brick: one miss a brick, not one a position
        CHECK(cache.stats().misses == store->bricks().size());
        CHECK(cache.stats().misses < 100);
    }
}

TEST_CASE("a store's bricks bound the values of the field inside them", "[render]") {
    test::TempDir d("brickfield");
    const Volume v = test::random_volume({30, 17, 12}, SampleType::u16);
    const std::string path = (d / "v.mlb").string();
    test::convert_volume(v, path, 8);
    const auto store = BrickStore::open(path);
    BrickCache cache(*store, 1 << 20);
    const BrickStoreField bf(*store, cache);
    const ValueBoundsGrid g = store_value_bounds(*store);
    CHECK(g.dims == store->info().bricks_per_axis);
    std::mt19937 rng(2);
    const auto [lo, hi] = bf.bounds();
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < 3000; ++i) {
        const Vec3 p{lo.x + u(rng) * (hi.x - lo.x), lo.y + u(rng) * (hi.y - lo.y), lo.z + u(rng) * (hi.z - lo.z)};
        const double f = bf.value(p);
        std::int64_t c[3];
        for (int a = 0; a < 3; ++a) c[a] = std::min<std::int64_t>(static_cast<std::int64_t>((p[a] - g.origin[a]) / g.cell[a]), g.dims[a] - 1);
        const auto k = static_cast<std::size_t>(g.index(c[0], c[1], c[2]));
        CHECK(f >= g.vmin[k]);
        CHECK(f <= g.vmax[k]);
    }
}
