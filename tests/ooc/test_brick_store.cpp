// Brick store: round trips for every sample type and odd dims, Morton order, brick boxes cover
// every cell once, deterministic bytes (repeat, threads), and must-fail damaged stores.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "kernels/errors.hpp"
#include "kernels/morton.hpp"
#include "ooc/verify_brick_store.hpp"
#include "ooc_test_util.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> dir_entries(const fs::path& d) {
    std::vector<std::string> r;
    for (const auto& e : fs::directory_iterator(d)) r.push_back(e.path().filename().string());
    std::sort(r.begin(), r.end());
    return r;
}

template <class T>
T get_le(const std::string& b, std::size_t off) {
    T v;
    std::memcpy(&v, b.data() + off, sizeof v);
    return v;
}

}  // namespace

TEST_CASE("brick store round trip: every sample type, odd dims, small and tiny volumes", "[ooc]") {
    TempDir dir("ooc-roundtrip");
    const SampleType types[] = {SampleType::u8, SampleType::i16, SampleType::u16, SampleType::f32};
    struct Case {
        std::array<std::int64_t, 3> dims;
        std::uint32_t brick;
    };
    const Case cases[] = {{{37, 20, 9}, 8}, {{5, 3, 2}, 8}, {{1, 1, 1}, 4}, {{17, 1, 9}, 4}, {{9, 9, 9}, 8}, {{33, 17, 5}, 2}};
    for (SampleType t : types)
        for (const Case& c : cases) {
            INFO(to_string(t) << " " << c.dims[0] << "x" << c.dims[1] << "x" << c.dims[2] << " brick " << c.brick);
            const Volume v = random_volume(c.dims, t);
            const std::string path = (dir / "v.mlb").string();
            const ConvertStats st = convert_volume(v, path, c.brick);
            CHECK(st.output_bytes == fs::file_size(path));
            const auto store = BrickStore::open(path);
            const BrickStoreInfo& in = store->info();
            CHECK(in.grid == v.grid);
            CHECK(in.type == t);
            CHECK(in.brick_edge == c.brick);
            const auto range = v.value_range();
            CHECK(in.value_min == range[0]);
            CHECK(in.value_max == range[1]);

            std::vector<int> covered;
            const Volume back = reassemble(*store, &covered);
            CHECK(back.bytes == v.bytes);  // bit-exact, NaN payloads included
            CHECK(std::count(covered.begin(), covered.end(), 0) == 0);

            // Each brick's index range is the range of its finite samples.
            std::vector<std::byte> buf;
            for (std::size_t b = 0; b < store->bricks().size(); ++b) {
                store->read_brick(b, buf);
                Volume bv(store->brick_grid(b), t);
                bv.bytes = buf;
                const auto r = bv.value_range();
                const auto& e = store->bricks()[b];
                if (std::isnan(e.vmin)) {
                    CHECK(t == SampleType::f32);
                } else {
                    CHECK(e.vmin == r[0]);
                    CHECK(e.vmax == r[1]);
                }
                CHECK(e.raw_bytes == buf.size());
            }
            CHECK(verify_brick_store(path, std::uint64_t{256} << 20).ok);
        }
}

TEST_CASE("brick store: Morton order, brick boxes own every cell exactly once", "[ooc]") {
    TempDir dir("ooc-morton");
    for (auto dims : {std::array<std::int64_t, 3>{37, 20, 9}, std::array<std::int64_t, 3>{65, 3, 40}}) {
        const std::uint32_t B = 8;
        const Volume v = random_volume(dims, SampleType::u8);
        const std::string path = (dir / "m.mlb").string();
        convert_volume(v, path, B);
        const auto store = BrickStore::open(path);
        const auto& bricks = store->bricks();
        const auto bpa = store->info().bricks_per_axis;
        for (int a = 0; a < 3; ++a) CHECK(bpa[a] == (dims[a] - 1 + B - 1) / B);
        REQUIRE(bricks.size() == static_cast<std::size_t>(bpa[0] * bpa[1] * bpa[2]));
        for (std::size_t i = 0; i < bricks.size(); ++i) {
            CHECK(bricks[i].key == morton_encode(bricks[i].coord[0], bricks[i].coord[1], bricks[i].coord[2]));
            if (i) {
                CHECK(bricks[i].key > bricks[i - 1].key);
                CHECK(bricks[i].offset == bricks[i - 1].offset + bricks[i - 1].stored_bytes);
            }
        }
        // Brute force: every cell belongs to exactly one brick's owned range [first, first+dims-1).
        const std::int64_t cx = dims[0] - 1, cy = dims[1] - 1, cz = dims[2] - 1;
        std::vector<int> owner(static_cast<std::size_t>(cx * cy * cz), 0);
        for (std::size_t b = 0; b < bricks.size(); ++b) {
            const auto f = store->brick_first_voxel(b);
            const GridSpec g = store->brick_grid(b);
            for (int a = 0; a < 3; ++a) {
                CHECK(g.dims[a] <= B + 1);
                CHECK(g.origin[a] == v.grid.origin[a] + f[a] * v.grid.spacing[a]);
            }
            for (std::int64_t k = f[2]; k < f[2] + g.dims[2] - 1; ++k)
                for (std::int64_t j = f[1]; j < f[1] + g.dims[1] - 1; ++j)
                    for (std::int64_t i = f[0]; i < f[0] + g.dims[0] - 1; ++i) ++owner[static_cast<std::size_t>(i + cx * (j + cy * k))];
        }
        CHECK(std::all_of(owner.begin(), owner.end(), [](int c) { return c == 1; }));
    }
}

TEST_CASE("brick store bytes do not depend on repetition or thread count", "[ooc]") {
    TempDir dir("ooc-determinism");
    const Volume v = random_volume({70, 45, 38}, SampleType::i16);
    const auto a = (dir / "a.mlb").string(), b = (dir / "b.mlb").string(), c = (dir / "c.mlb").string();
    convert_volume(v, a, 16, 1);
    convert_volume(v, b, 16, 1);
    convert_volume(v, c, 16, 2);
    CHECK(read_bytes(a) == read_bytes(b));
    CHECK(read_bytes(a) == read_bytes(c));
    // No temporaries left behind.
    CHECK(dir_entries(dir.path) == std::vector<std::string>{"a.mlb", "b.mlb", "c.mlb"});
}

TEST_CASE("a conversion interrupted mid-way leaves no output and a rerun gives the same bytes", "[ooc]") {
    TempDir dir("ooc-killed");
    const Volume v = random_volume({40, 40, 60}, SampleType::u8);
    const std::string ref = (dir / "ref.mlb").string();
    convert_volume(v, ref, 8);
    const std::string out = (dir / "out.mlb").string();
    for (double stop_at : {0.1, 0.5, 1.0}) {
        auto src = make_volume_source(v, "memory");
        ConvertParams p;
        p.brick_edge = 8;
        struct Stop {};
        CHECK_THROWS_AS(convert_to_brick_store(*src, out, p,
                                               [&](double f) {
                                                   if (f >= stop_at) throw Stop{};
                                               }),
                        Stop);
        CHECK_FALSE(fs::exists(out));
        CHECK(dir_entries(dir.path) == std::vector<std::string>{"ref.mlb"});
    }
    // A stale, half-written store at the output path is replaced.
    write_bytes(out, read_bytes(ref).substr(0, 1000));
    convert_volume(v, out, 8);
    CHECK(read_bytes(out) == read_bytes(ref));
}

TEST_CASE("damaged brick stores are detected by every reader", "[ooc]") {
    TempDir dir("ooc-damage");
    const Volume v = random_volume({37, 20, 9}, SampleType::u16);
    const std::string good = (dir / "good.mlb").string();
    convert_volume(v, good, 8);
    const std::string bytes = read_bytes(good);
    const auto store = BrickStore::open(good);
    const std::string bad = (dir / "bad.mlb").string();
    const std::uint64_t index_offset = get_le<std::uint64_t>(bytes, bytes.size() - 32);

    SECTION("flipped bit in a brick") {
        const std::size_t victim = 3;
        const auto& e = store->bricks()[victim];
        std::string b = bytes;
        b[e.offset + e.stored_bytes / 2] ^= 0x10;
        write_bytes(bad, b);
        const auto s = BrickStore::open(bad);  // header/index are intact
        std::vector<std::byte> buf;
        for (std::size_t i = 0; i < victim; ++i) CHECK_NOTHROW(s->read_brick(i, buf));
        const std::string range = voxel_range_string(s->box(victim));
        try {
            s->read_brick(victim, buf);
            FAIL("read_brick accepted a corrupt brick");
        } catch (const FormatError& err) {
            const std::string m = err.what();
            CHECK(m.find(bad) != std::string::npos);
            CHECK(m.find("brick 3 ") != std::string::npos);
            CHECK(m.find(range) != std::string::npos);
        }
        const VerifyReport r = verify_brick_store(bad, std::uint64_t{256} << 20);
        CHECK_FALSE(r.ok);
        REQUIRE(r.first_bad_brick);
        CHECK(*r.first_bad_brick == victim);
        CHECK(r.message.find(range) != std::string::npos);
    }
    SECTION("truncated store") {
        for (std::size_t keep : {bytes.size() - 1, bytes.size() - 32, bytes.size() / 2, std::size_t{300}, std::size_t{100},
                                 std::size_t{7}, std::size_t{0}}) {
            INFO("kept " << keep << " bytes");
            write_bytes(bad, bytes.substr(0, keep));
            CHECK_THROWS_AS(BrickStore::open(bad), FormatError);
            CHECK_FALSE(verify_brick_store(bad, std::uint64_t{256} << 20).ok);
        }
        write_bytes(bad, bytes.substr(0, bytes.size() - 1));
        CHECK_THROWS_WITH(BrickStore::open(bad), Catch::Contains("truncated"));
    }
    SECTION("wrong magic") {
        std::string b = bytes;
        b[1] = 'X';
        write_bytes(bad, b);
        CHECK_THROWS_WITH(BrickStore::open(bad), Catch::Contains("not a brick store"));
        CHECK_FALSE(is_brick_store(bad));
        CHECK(is_brick_store(good));
    }
    SECTION("wrong version, even with a valid header checksum") {
        BrickStoreInfo in = store->info();
        auto h = encode_brick_store_header(in);
        const std::uint32_t v2 = 2;
        std::memcpy(h.data() + 8, &v2, 4);
        const std::uint32_t crc = brick_store_crc32(h.data(), 252);
        std::memcpy(h.data() + 252, &crc, 4);
        std::string b = bytes;
        std::memcpy(b.data(), h.data(), h.size());
        write_bytes(bad, b);
        CHECK_THROWS_WITH(BrickStore::open(bad), Catch::Contains("unsupported brick store version 2"));
    }
    SECTION("header the writer did not write (header checksum)") {
        std::string b = bytes;
        b[20] ^= 1;  // dims
        write_bytes(bad, b);
        CHECK_THROWS_WITH(BrickStore::open(bad), Catch::Contains("header checksum"));
    }
    SECTION("corrupt index") {
        std::string b = bytes;
        b[index_offset + 64 * 2 + 40] ^= 4;  // vmin of entry 2
        write_bytes(bad, b);
        CHECK_THROWS_WITH(BrickStore::open(bad), Catch::Contains("index checksum"));
        CHECK_FALSE(verify_brick_store(bad, std::uint64_t{256} << 20).ok);
    }
    SECTION("corrupt footer checksum") {
        std::string b = bytes;
        b[bytes.size() - 32 + 16] ^= 0x80;
        write_bytes(bad, b);
        CHECK_THROWS_WITH(BrickStore::open(bad), Catch::Contains("index checksum"));
    }
    SECTION("corrupt footer index offset") {
        std::string b = bytes;
        b[bytes.size() - 32] ^= 0x08;
        write_bytes(bad, b);
        CHECK_THROWS_AS(BrickStore::open(bad), FormatError);
    }
    SECTION("an index that lies about a brick's range is caught by verify") {
        std::string b = bytes;
        const std::size_t e = index_offset + 64 * 5;
        double vmax = get_le<double>(b, e + 48) + 1;
        std::memcpy(b.data() + e + 48, &vmax, 8);
        const std::string idx = b.substr(index_offset, store->bricks().size() * 64);
        const std::uint32_t crc = brick_store_crc32(idx.data(), idx.size());
        std::memcpy(b.data() + b.size() - 32 + 16, &crc, 4);
        write_bytes(bad, b);
        const VerifyReport r = verify_brick_store(bad, std::uint64_t{256} << 20);
        CHECK_FALSE(r.ok);
        REQUIRE(r.first_bad_brick);
        CHECK(*r.first_bad_brick == 5);
    }
    SECTION("missing file and directory are I/O errors") {
        CHECK_THROWS_AS(BrickStore::open((dir / "nope.mlb").string()), IoError);
        CHECK_THROWS_AS(BrickStore::open(dir.path.string()), IoError);
    }
}

TEST_CASE("converter parameters are validated", "[ooc]") {
    TempDir dir("ooc-params");
    const Volume v = random_volume({5, 5, 5}, SampleType::u8);
    auto src = make_volume_source(v, "memory");
    ConvertParams p;
    p.brick_edge = 1;
    CHECK_THROWS_AS(convert_to_brick_store(*src, (dir / "x.mlb").string(), p), InvalidArgument);
    p.brick_edge = 8;
    p.zstd_level = 0;
    CHECK_THROWS_AS(convert_to_brick_store(*src, (dir / "x.mlb").string(), p), InvalidArgument);
    p.zstd_level = 1;
    CHECK_THROWS_AS(convert_to_brick_store(*src, (dir / "no-such-dir" / "x.mlb").string(), p), IoError);
    CHECK(dir_entries(dir.path).empty());
}

TEST_CASE("verify reads no brick bigger than its memory budget", "[ooc]") {
    // a store of highly compressible bricks is small on disk whatever its bricks take decompressed:
    // verify, like the brick cache of the other readers, refuses bricks beyond its budget unread
    TempDir dir("ooc-verify-budget");
    const Volume v = random_volume({40, 40, 40}, SampleType::f32);
    const std::string path = (dir / "v.mlb").string();
    convert_volume(v, path, 32);
    const auto store = BrickStore::open(path);
    const std::uint64_t need = store->max_brick_bytes();
    CHECK(verify_brick_store(path, need).ok);
    const VerifyReport r = verify_brick_store(path, need - 1);
    CHECK_FALSE(r.ok);
    CHECK(r.bricks_checked == 0);
    CHECK_THAT(r.message, Catch::Contains("v.mlb: its bricks take up to " + std::to_string(need) + " bytes") &&
                              Catch::Contains("(--memory); not checked"));
}
