// Per-block min/max and the active-block box (framing of the surface, section 3.6) against brute
// force over every block, for each sample type, with NaN samples and edges that do not divide.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "kernels/block_minmax.hpp"

using namespace meshless;

namespace {

template <class T>
Volume random_volume(std::array<std::int64_t, 3> dims, SampleType t, std::uint64_t seed, bool nans) {
    GridSpec g;
    g.dims = dims;
    g.origin = {1, -2, 0.5};
    g.spacing = {0.5, 1, 2};
    Volume v(g, t);
    std::mt19937_64 rng(seed);
    T* p = reinterpret_cast<T*>(v.bytes.data());
    for (std::int64_t i = 0; i < g.voxel_count(); ++i) {
        p[i] = static_cast<T>(rng() % 200);
        if (nans && rng() % 17 == 0) p[i] = static_cast<T>(NAN);
    }
    return v;
}

void check_against_brute(const Volume& v, int edge) {
    const BlockMinMax b = block_minmax(v.view(), edge);
    const auto& d = v.grid.dims;
    std::size_t i = 0;
    for (std::int64_t bz = 0; bz < b.blocks[2]; ++bz)
        for (std::int64_t by = 0; by < b.blocks[1]; ++by)
            for (std::int64_t bx = 0; bx < b.blocks[0]; ++bx, ++i) {
                double lo = INFINITY, hi = -INFINITY;
                for (std::int64_t k = bz * edge; k <= std::min<std::int64_t>(bz * edge + edge, d[2] - 1); ++k)
                    for (std::int64_t j = by * edge; j <= std::min<std::int64_t>(by * edge + edge, d[1] - 1); ++j)
                        for (std::int64_t x = bx * edge; x <= std::min<std::int64_t>(bx * edge + edge, d[0] - 1); ++x) {
                            const double s = v.view().at(x, j, k);
                            if (!std::isfinite(s)) continue;
                            lo = std::min(lo, s);
                            hi = std::max(hi, s);
                        }
                if (lo > hi) {
                    CHECK(std::isnan(b.vmin[i]));
                } else {
                    CHECK(b.vmin[i] == lo);
                    CHECK(b.vmax[i] == hi);
                }
            }
    const auto r = b.range(), vr = v.value_range();
    CHECK(r[0] == vr[0]);
    CHECK(r[1] == vr[1]);
}

}  // namespace

TEST_CASE("block min/max equals brute force for every type and awkward sizes", "[block_minmax]") {
    for (int edge : {1, 3, 4, 32}) {
        check_against_brute(random_volume<std::uint8_t>({13, 9, 7}, SampleType::u8, 1, false), edge);
        check_against_brute(random_volume<std::int16_t>({5, 17, 9}, SampleType::i16, 2, false), edge);
        check_against_brute(random_volume<std::uint16_t>({9, 9, 1}, SampleType::u16, 3, false), edge);
        check_against_brute(random_volume<float>({10, 6, 11}, SampleType::f32, 4, true), edge);
    }
    // 8-bit volumes wide enough for whole 33-sample segments (the SSE2 path), with partial last blocks
    for (std::array<std::int64_t, 3> dims : {std::array<std::int64_t, 3>{97, 70, 40}, {64, 33, 33}, {65, 2, 34}, {33, 1, 1}})
        for (int edge : {32, 4}) {
            Volume v = random_volume<std::uint8_t>(dims, SampleType::u8, 5, false);
            v.bytes[static_cast<std::size_t>(dims[0] + 40) % v.bytes.size()] = std::byte{255};  // extremes inside some block
            v.bytes[v.bytes.size() / 2] = std::byte{0};
            check_against_brute(v, edge);
        }
}

TEST_CASE("active block box: union of the blocks the isovalue crosses, in world units", "[block_minmax]") {
    // a single bright voxel at (20, 5, 9) in a 40x16x12 volume: with edge 4 the active blocks are
    // those holding that voxel (it lies on block boundaries in x and y: two blocks each)
    GridSpec g;
    g.dims = {40, 16, 12};
    g.origin = {1, -2, 0.5};
    g.spacing = {0.5, 1, 2};
    Volume v(g, SampleType::u8);
    std::memset(v.bytes.data(), 0, v.bytes.size());
    v.bytes[static_cast<std::size_t>(g.index(20, 4, 9))] = std::byte{100};
    const BlockMinMax b = block_minmax(v.view(), 4);
    const auto box = active_block_box(b, g, 50.0);
    REQUIRE(box);
    CHECK(box->lo == std::array<std::int64_t, 3>{16, 0, 8});
    CHECK(box->hi == std::array<std::int64_t, 3>{24, 8, 11});
    const auto w = world_bounds(g, *box);
    CHECK(w[0].x == 1 + 16 * 0.5);
    CHECK(w[1].z == 0.5 + 11 * 2);
    CHECK_FALSE(active_block_box(b, g, 150.0));  // above everything
    CHECK_FALSE(active_block_box(b, g, 0.0));    // vmin < iso fails everywhere
}

TEST_CASE("BlockMinMaxBuilder: slices added in any grouping and order give block_minmax", "[kernels][block_minmax]") {
    const Volume f = random_volume<float>({13, 9, 21}, SampleType::f32, 7, true);
    const Volume u = random_volume<std::uint16_t>({13, 9, 21}, SampleType::u16, 8, false);
    // 8-bit and wide enough for whole 33-sample segments (the SSE2 path), slices added from k0 > 0
    const Volume b8 = random_volume<std::uint8_t>({97, 9, 21}, SampleType::u8, 9, false);
    for (const Volume* v : {&f, &u, &b8})
        for (int edge : {1, 4, 8, 32}) {
            if (v == &b8) check_against_brute(*v, edge);
            const BlockMinMax whole = block_minmax(v->view(), edge);
            const std::size_t slice = static_cast<std::size_t>(v->grid.dims[0] * v->grid.dims[1]) * sample_size(v->type);
            BlockMinMaxBuilder b(v->grid, v->type, edge);
            // groups of 5, 1, 5, 1, ... slices, the last group first
            std::vector<std::array<std::int64_t, 2>> groups;
            for (std::int64_t k = 0, g = 0; k < 21; ++g) {
                const std::int64_t n = std::min<std::int64_t>(g % 2 ? 1 : 5, 21 - k);
                groups.push_back({k, n});
                k += n;
            }
            std::rotate(groups.begin(), groups.end() - 1, groups.end());
            for (const auto& [k, n] : groups) b.add_slices(k, n, v->bytes.data() + slice * static_cast<std::size_t>(k));
            const BlockMinMax built = std::move(b).finish();
            INFO("edge " << edge);
            CHECK(built.blocks == whole.blocks);
            REQUIRE(built.vmin.size() == whole.vmin.size());
            for (std::size_t i = 0; i < whole.vmin.size(); ++i) {
                CHECK(std::isnan(built.vmin[i]) == std::isnan(whole.vmin[i]));
                if (!std::isnan(whole.vmin[i])) {
                    CHECK(built.vmin[i] == whole.vmin[i]);
                    CHECK(built.vmax[i] == whole.vmax[i]);
                }
            }
        }
}
