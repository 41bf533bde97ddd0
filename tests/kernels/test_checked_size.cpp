// kernels/checked_size.hpp and the grid checks built on it (size arithmetic from headers).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <limits>

#include "kernels/checked_size.hpp"
#include "kernels/flip_axes.hpp"
#include "kernels/grid.hpp"

using namespace meshless;

TEST_CASE("checked_mul and checked_add refuse what does not fit, naming the context", "[kernels][checked]") {
    CHECK(checked_mul(1u << 20, 1u << 20, "f: x") == (std::uint64_t{1} << 40));
    CHECK_THROWS_AS(checked_mul(std::uint64_t{1} << 32, std::uint64_t{1} << 32, "f: sizes"), FormatError);
    CHECK_THROWS_WITH(checked_mul(std::uint64_t{1} << 32, std::uint64_t{1} << 32, "a.nrrd: sizes"),
                      Catch::StartsWith("a.nrrd: sizes: 4294967296 x 4294967296"));
    CHECK_THROWS_AS(checked_mul(kMaxPayloadBytes, 2, "f"), FormatError);  // below 2^64 but above the cap
    CHECK(checked_add(kMaxPayloadBytes - 1, 1, "f") == kMaxPayloadBytes);
    CHECK_THROWS_AS(checked_add(std::numeric_limits<std::uint64_t>::max(), 1, "f"), FormatError);
    CHECK_THROWS_AS(checked_count(-1, "f"), FormatError);
    CHECK(checked_count(7, "f") == 7);
}

TEST_CASE("checked_extent: hi - lo + 1 without signed overflow", "[kernels][checked]") {
    CHECK(checked_extent(0, 9, "f") == 10);
    CHECK(checked_extent(-5, -5, "f") == 1);
    CHECK_THROWS_AS(checked_extent(3, 2, "f"), FormatError);
    CHECK_THROWS_AS(checked_extent(std::numeric_limits<std::int64_t>::min(), std::numeric_limits<std::int64_t>::max(), "f"),
                    FormatError);
    CHECK_THROWS_AS(checked_extent(0, std::numeric_limits<std::int64_t>::max(), "f"), FormatError);
}

TEST_CASE("GridSpec::voxel_count never wraps, validate_grid refuses nonsense geometry", "[kernels][checked]") {
    GridSpec g;
    g.dims = {std::int64_t{1} << 32, std::int64_t{1} << 32, 1};
    CHECK_THROWS_AS(g.voxel_count(), FormatError);  // used to wrap to 0
    CHECK_THROWS_WITH(validate_grid(g, "big.raw"), Catch::StartsWith("big.raw: dimensions 4294967296x4294967296x1"));
    g.dims = {4, 4, 4};
    CHECK(g.voxel_count() == 64);
    CHECK_NOTHROW(validate_grid(g, "ok"));
    for (const double bad : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
        GridSpec h = g;
        h.spacing[1] = bad;
        CHECK_THROWS_WITH(validate_grid(h, "s.nrrd"), Catch::StartsWith("s.nrrd: bad spacing along y"));
    }
    GridSpec o = g;
    o.origin[2] = std::nan("");
    CHECK_THROWS_WITH(validate_grid(o, "o.mha"), Catch::StartsWith("o.mha: bad origin along z"));
    // finite doubles whose sample positions overflow the float32 records, or whose spacing underflows them
    GridSpec far = g;
    far.spacing[0] = 1e308;
    CHECK_THROWS_WITH(validate_grid(far, "f.nrrd"), Catch::StartsWith("f.nrrd: origin 0 and spacing 1e+308 along x put samples at") &&
                                                        Catch::Contains("beyond the float32 range"));
    far.spacing[0] = 1e38;  // 3e38 at the last sample: past FLT_MAX (3.4e38) only with an origin
    CHECK_NOTHROW(validate_grid(far, "f.nrrd"));
    far.origin[0] = 1e38;
    CHECK_THROWS_WITH(validate_grid(far, "f.nrrd"), Catch::Contains("beyond the float32 range"));
    GridSpec off = g;
    off.origin[1] = -1e39;
    CHECK_THROWS_WITH(validate_grid(off, "f.vti"), Catch::Contains("along y") && Catch::Contains("beyond the float32 range"));
    GridSpec tiny = g;
    tiny.spacing[2] = 1e-39;
    CHECK_THROWS_WITH(validate_grid(tiny, "t.mhd"), Catch::StartsWith("t.mhd: bad spacing along z (1e-39): below"));
    tiny.spacing[2] = 1e-30;
    CHECK_NOTHROW(validate_grid(tiny, "t.mhd"));
    GridSpec empty;
    CHECK(empty.voxel_count() == 0);
}

TEST_CASE("flip_axes and honour_signed_spacing keep every world position's value", "[kernels][checked]") {
    // a 3x2x2 uint8 volume whose value is 100*k + 10*j + i, read as if the file had spacing
    // (-2, 1, -0.5): sample (i,j,k) of the file sits at origin + (i*-2, j, k*-0.5)
    GridSpec file;
    file.dims = {3, 2, 2};
    file.origin = {10, 20, 30};
    const std::array<double, 3> s{-2, 1, -0.5};
    Volume v(file, SampleType::u8);
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) v.bytes[static_cast<std::size_t>(file.index(i, j, k))] = std::byte(100 * k + 10 * j + i);
    GridSpec g = file;
    std::array<bool, 3> flip{};
    for (int a = 0; a < 3; ++a) honour_signed_spacing(g, flip, a, s[a]);
    CHECK(flip == std::array<bool, 3>{true, false, true});
    CHECK(g.spacing == std::array<double, 3>{2, 1, 0.5});
    CHECK(g.origin == std::array<double, 3>{6, 20, 29.5});
    v.grid = g;
    flip_axes(v, flip);
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) {
                // the file's sample (i,j,k) at its world position; find it in the flipped grid
                const double x = file.origin[0] + i * s[0], z = file.origin[2] + k * s[2];
                const auto fi = static_cast<std::int64_t>(std::lround((x - g.origin[0]) / g.spacing[0]));
                const auto fk = static_cast<std::int64_t>(std::lround((z - g.origin[2]) / g.spacing[2]));
                CHECK(static_cast<int>(v.bytes[static_cast<std::size_t>(g.index(fi, j, fk))]) == 100 * k + 10 * j + i);
            }
}
