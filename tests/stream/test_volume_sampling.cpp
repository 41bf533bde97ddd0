// The sample recipe (stream/volume_sampling.hpp): the points are the first `count` finite draws of the
// seed's sequence, so any chunk size, the streamed file writer and a brick store give the very points
// of sample_volume; positions in cells with NaN corners are redrawn and counted the same way.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>

#include "formats/point_set_reader.hpp"
#include "kernels/trilinear_field.hpp"
#include "ooc/brick_store.hpp"
#include "stream/volume_sampling.hpp"
#include "test_paths.hpp"
#include "ooc/ooc_test_util.hpp"

using namespace meshless;

namespace {

/// A smooth float volume with a band of NaN samples (a fifth of the cells have a NaN corner).
Volume nan_volume() {
    GridSpec g;
    g.dims = {23, 17, 11};
    g.origin = {0.5, -1, 2};
    g.spacing = {0.5, 0.25, 1};
    Volume v(g, SampleType::f32);
    auto* f = reinterpret_cast<float*>(v.bytes.data());
    for (std::int64_t k = 0; k < g.dims[2]; ++k)
        for (std::int64_t j = 0; j < g.dims[1]; ++j)
            for (std::int64_t i = 0; i < g.dims[0]; ++i)
                f[g.index(i, j, k)] = i == 5 || j == 9 ? std::numeric_limits<float>::quiet_NaN()
                                                       : static_cast<float>(std::sin(0.3 * i) + 0.1 * j * k);
    return v;
}

}  // namespace

TEST_CASE("sample: any chunk gives sample_volume's points, NaN cells redrawn the same", "[stream][sample]") {
    const Volume v = nan_volume();
    const VolumeSample want = sample_volume(v, 5000, 17, "nan.raw");
    REQUIRE(want.points.size() == 5000);
    CHECK(want.redrawn > 500);
    for (std::size_t chunk : {std::size_t{1}, std::size_t{7}, std::size_t{4096}, std::size_t{1} << 20}) {
        INFO("chunk " << chunk);
        std::vector<Vec3> pos;
        std::vector<double> val;
        std::size_t calls = 0;
        const TrilinearField f(v.view());
        const std::uint64_t redrawn = sample_volume_chunks(
            v.grid, [&](std::span<const Vec3> p, std::span<double> out) { f.evaluate(p, out, {}); }, 5000, 17, "nan.raw", chunk,
            [&](std::span<const Vec3> p, std::span<const double> x) {
                CHECK(p.size() <= chunk);
                ++calls;
                pos.insert(pos.end(), p.begin(), p.end());
                val.insert(val.end(), x.begin(), x.end());
            });
        CHECK(redrawn == want.redrawn);
        REQUIRE(pos.size() == 5000);
        CHECK(std::memcmp(pos.data(), want.points.pos.data(), pos.size() * sizeof(Vec3)) == 0);
        CHECK(val == want.points.value);
        if (chunk == 7) CHECK(calls > 700);
    }
    // too many NaN cells: refused, naming the file
    Volume all_nan = v;
    for (std::size_t i = 0; i < static_cast<std::size_t>(v.grid.voxel_count()); ++i)
        reinterpret_cast<float*>(all_nan.bytes.data())[i] = std::numeric_limits<float>::quiet_NaN();
    CHECK_THROWS_WITH(sample_volume(all_nan, 10, 1, "void.raw"), Catch::Contains("void.raw: too many NaN/Inf cells"));
}

TEST_CASE("sample to a file: streamed PLY, CSV and VTP of a volume and of its brick store hold the same points", "[stream][sample]") {
    test::TempDir d("sampling");
    const Volume v = nan_volume();
    const std::string mlb = (d / "v.mlb").string();
    test::convert_volume(v, mlb, 8);
    const auto store = BrickStore::open(mlb);
    const VolumeSample want = sample_volume(v, 3000, 5, "v");
    for (const char* ext : {".ply", ".csv", ".vtp"}) {
        SampleInput mem;
        mem.volume = &v;
        SampleInput bricks;
        bricks.store = store.get();
        bricks.memory_bytes = 1;  // (the cache raised to one brick)
        const std::string a = (d / (std::string("a") + ext)).string(), b = (d / (std::string("b") + ext)).string();
        double progressed = 0;
        CHECK(sample_volume_to_file(mem, 3000, 5, "v", a, {"producer test"}, [&](double k) { progressed += k; }, 1000) == want.redrawn);
        CHECK(progressed == 3000);
        CHECK(sample_volume_to_file(bricks, 3000, 5, "v", b, {"producer test"}, {}, 512) == want.redrawn);
        CHECK(test::read_bytes(a) == test::read_bytes(b));
        const PointSet got = read_point_set(a);
        REQUIRE(got.size() == 3000);
        if (std::string(ext) != ".vtp") {  // (VTP keeps float32)
            CHECK(std::memcmp(got.pos.data(), want.points.pos.data(), 3000 * sizeof(Vec3)) == 0);
            CHECK(got.value == want.points.value);
        }
    }
}
