// The point store (.mlc): conversion (in memory and spilled in sorted runs), round trip (every point
// once, Morton order, bricks as octree cells with exact bounds, counts and ranges, index order),
// determinism over --threads and --memory, NaN/Inf dropped and counted, and a must-fail case per
// defect class of the reader (formats/point_store_format.hpp).
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <thread>

#include "error_of.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/point_store.hpp"
#include "ooc/point_store_writer.hpp"
#include "ooc/verify_point_store.hpp"
#include "ooc_test_util.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;
using Catch::Matchers::Contains;

namespace {

/// n points (fixed seed) in three clusters of different density, values from the position.
std::vector<double> cluster_points(std::size_t n, unsigned seed = 3) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    std::vector<double> v;
    for (std::size_t i = 0; i < n; ++i) {
        const int c = static_cast<int>(i % 3);
        const double s = c == 0 ? 0.05 : (c == 1 ? 1.0 : 10.0);
        const double x = c * 7 + s * g(rng), y = -c * 3 + s * g(rng), z = 0.5 * c + s * g(rng);
        v.insert(v.end(), {x, y, z, std::sin(x) + y * z});
    }
    return v;
}

PointChunkProducer producer(const std::vector<double>& xyzv, std::uint64_t dropped = 0) {
    return [&xyzv, dropped](const std::function<void(std::span<const double>)>& chunk) {
        for (std::size_t k = 0; k < xyzv.size(); k += 4 * 1000)
            chunk(std::span<const double>(xyzv).subspan(k, std::min<std::size_t>(4 * 1000, xyzv.size() - k)));
        PointChunkTotals t;
        t.points = xyzv.size() / 4;
        t.dropped_nonfinite = dropped;
        t.value_name = "v";
        return t;
    };
}

PointStoreParams params(std::uint32_t b, int threads = 1, std::uint64_t memory = 256ull << 20) {
    PointStoreParams p;
    p.brick_points = b;
    p.threads = threads;
    p.memory_bytes = memory;
    return p;
}

template <class T>
void put_le(std::string& b, std::size_t off, T v) {
    std::memcpy(b.data() + off, &v, sizeof v);
}
template <class T>
T get_le(const std::string& b, std::size_t off) {
    T v;
    std::memcpy(&v, b.data() + off, sizeof v);
    return v;
}
void fix_header_crc(std::string& b) {
    put_le<std::uint32_t>(b, 508, point_store_crc32(b.data(), 508));
}
void fix_index_crc(std::string& b) {
    const std::uint64_t at = get_le<std::uint64_t>(b, b.size() - 32);
    put_le<std::uint32_t>(b, b.size() - 16, point_store_crc32(b.data() + at, b.size() - 32 - at));
}
std::size_t entry_at(const std::string& b, std::size_t i) {
    return static_cast<std::size_t>(get_le<std::uint64_t>(b, b.size() - 32)) + i * kPointStoreEntryBytes;
}

}  // namespace

TEST_CASE("point store round trip: every point once, in (Morton key, input order), bricks are octree cells", "[ooc][point_store]") {
    TempDir dir("mlc-roundtrip");
    const std::vector<double> in = cluster_points(20000);
    const std::string path = (dir / "p.mlc").string();
    const std::uint32_t B = 64;
    const PointStoreStats st = convert_points_to_point_store(producer(in), "test", path, params(B));
    CHECK(st.points == 20000);
    CHECK(st.runs == 0);
    const auto s = PointStore::open(path);
    const PointStoreInfo& info = s->info();
    CHECK(info.points == 20000);
    CHECK(info.brick_count == st.bricks);
    CHECK(info.value_name == "v");
    CHECK(info.source == "test");
    const PointStoreGrid grid = s->layout().grid();

    // expected order: (key, input index)
    std::vector<std::pair<std::uint64_t, std::size_t>> order;
    for (std::size_t i = 0; i < in.size() / 4; ++i) order.push_back({grid.key(in[4 * i], in[4 * i + 1], in[4 * i + 2]), i});
    std::sort(order.begin(), order.end());
    std::vector<double> pts, all;
    std::uint64_t first = 0;
    for (std::size_t i = 0; i < s->bricks().size(); ++i) {
        const PointBrickEntry& e = s->bricks()[i];
        INFO("brick " << i);
        s->read_brick(i, pts);
        CHECK(check_point_brick(s->layout(), i, pts).empty());
        CHECK(e.first == first);
        CHECK(e.count >= 1);
        CHECK(e.count <= B);
        first += e.count;
        // the octree rule: the parent cell holds more than B points (else the brick would be it)
        if (e.level > 0 && e.level < info.level) {
            const std::uint64_t pk = e.key >> 3;
            const std::uint64_t b0 = grid.cell_begin(e.level - 1, pk), b1 = grid.cell_end(e.level - 1, pk);
            const auto n = std::count_if(order.begin(), order.end(), [&](const auto& o) { return o.first >= b0 && o.first < b1; });
            CHECK(static_cast<std::uint64_t>(n) > B);
        }
        if (i > 0) {
            const PointBrickEntry& q = s->bricks()[i - 1];
            CHECK(grid.cell_begin(e.level, e.key) >= grid.cell_end(q.level, q.key));  // ascending, disjoint
        }
        all.insert(all.end(), pts.begin(), pts.end());
    }
    CHECK(first == 20000);
    REQUIRE(all.size() == in.size());
    bool same_order = true;
    for (std::size_t k = 0; k < order.size() && same_order; ++k)
        for (int c = 0; c < 4; ++c) same_order = same_order && all[4 * k + c] == in[4 * order[k].second + c];
    CHECK(same_order);
    // header totals
    double lo0 = in[0], hi0 = in[0];
    for (std::size_t i = 0; i < in.size(); i += 4) {
        lo0 = std::min(lo0, in[i]);
        hi0 = std::max(hi0, in[i]);
    }
    CHECK(info.lo[0] == lo0);
    CHECK(info.hi[0] == hi0);
    const PointStoreVerifyReport r = verify_point_store(path);
    CHECK(r.ok);
    CHECK(r.points_checked == 20000);
    // the in-memory parser agrees
    const std::string bytes = read_bytes(path);
    CHECK(parse_point_store_bytes(std::span(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()), "p").bricks.size() ==
          s->bricks().size());
    // read as a point set (every command's dispatch)
    const PointSet ps = read_point_set(path);
    CHECK(ps.size() == 20000);
    CHECK(ps.value_name == "v");
    CHECK(ps.pos[0].x == all[0]);
}

TEST_CASE("point store bytes do not depend on --threads or --memory: sorted runs spilled and merged in passes", "[ooc][point_store]") {
    TempDir dir("mlc-spill");
    const std::vector<double> in = cluster_points(40000, 9);
    const std::uint32_t B = 32;
    const std::string ref = (dir / "ref.mlc").string();
    convert_points_to_point_store(producer(in), "t", ref, params(B, 1));
    const std::string bytes = read_bytes(ref);
    const std::uint64_t least = point_store_min_memory(params(B, 1));
    for (const std::uint64_t memory : std::vector<std::uint64_t>{least, least + (1ull << 20), std::uint64_t{64} << 20})
        for (const int threads : {1, 2}) {
            INFO("memory " << memory << ", threads " << threads);
            const std::string out = (dir / "o.mlc").string();
            const PointStoreStats st = convert_points_to_point_store(producer(in), "t", out, params(B, threads, std::max(memory, point_store_min_memory(params(B, threads)))));
            CHECK(read_bytes(out) == bytes);
            if (memory == least) {
                CHECK(st.runs > 4);
                CHECK(st.merge_passes >= 1);  // more runs than one pass can merge with 48 KiB buffers
            }
            if (memory == (std::uint64_t{64} << 20)) CHECK(st.runs == 0);
            CHECK(std::distance(std::filesystem::directory_iterator(dir.path), std::filesystem::directory_iterator()) == 2);
        }
}

TEST_CASE("point store: NaN/Inf records dropped and counted at conversion", "[ooc][point_store]") {
    TempDir dir("mlc-nan");
    std::ofstream(dir / "p.csv") << "x,y,z,value\n0,0,0,1\n1,0,0,2\nnan,0,0,3\n0,1,0,4\n0,0,1,inf\n1,1,1,5\n2,2,2,-inf\n";
    const std::string out = (dir / "p.mlc").string();
    const PointStoreStats st = convert_to_point_store({(dir / "p.csv").string()}, {}, out, params(4));
    CHECK(st.points == 4);
    CHECK(st.dropped_nonfinite == 3);
    const auto s = PointStore::open(out);
    CHECK(s->info().dropped_nonfinite == 3);
    CHECK(s->info().value_name == "value");
    CHECK(s->info().source == "p.csv");
    CHECK(read_point_set(out).dropped_nonfinite == 3);
    // several files are one set; fewer than 4 finite points is refused naming the input
    const PointStoreStats two = convert_to_point_store({(dir / "p.csv").string(), (dir / "p.csv").string()}, {}, out, params(4));
    CHECK(two.points == 8);
    CHECK(two.dropped_nonfinite == 6);
    std::ofstream(dir / "few.csv") << "x,y,z,value\n0,0,0,1\nnan,0,0,3\n";
    CHECK_THAT(error_of([&] { convert_to_point_store({(dir / "few.csv").string()}, {}, (dir / "f.mlc").string(), params(4)); }),
               Contains("few.csv") && Contains("1 valid point"));
    CHECK_FALSE(std::filesystem::exists(dir / "f.mlc"));
}

TEST_CASE("point store: a grid cell with more than B points is cut into bricks of B sharing its key", "[ooc][point_store]") {
    TempDir dir("mlc-dup");
    std::vector<double> in;
    for (int i = 0; i < 100; ++i) in.insert(in.end(), {1.0, 2.0, 3.0, static_cast<double>(i)});
    for (int i = 0; i < 20; ++i) in.insert(in.end(), {1.0 + i, 2.0, 3.0 - i, 0.5});
    const std::string out = (dir / "d.mlc").string();
    convert_points_to_point_store(producer(in), "t", out, params(16));
    const auto s = PointStore::open(out);
    std::size_t full_leaf = 0;
    for (const auto& e : s->bricks())
        if (e.level == s->info().level) ++full_leaf;
    CHECK(full_leaf >= 100 / 16);
    CHECK(verify_point_store(out).ok);
    CHECK(read_point_set(out).size() == 120);
}

TEST_CASE("point store conversion: --memory too small for one brick and bad parameters are refused", "[ooc][point_store]") {
    TempDir dir("mlc-params");
    const std::vector<double> in = cluster_points(100);
    const std::string out = (dir / "p.mlc").string();
    CHECK_THAT(error_of<InvalidArgument>([&] { convert_points_to_point_store(producer(in), "t", out, params(4096, 1, 1u << 20)); }),
               Contains("--memory") && Contains("too small for bricks of 4096 points"));
    CHECK_THROWS_AS(convert_points_to_point_store(producer(in), "t", out, params(0)), InvalidArgument);
    CHECK_THROWS_AS(convert_points_to_point_store(producer(in), "t", out, params((1u << 20) + 1)), InvalidArgument);
    CHECK_FALSE(std::filesystem::exists(out));
}

TEST_CASE("damaged point stores: one line naming the file and the brick, per defect class", "[ooc][point_store]") {
    TempDir dir("mlc-damage");
    const std::string good = (dir / "good.mlc").string();
    convert_points_to_point_store(producer(cluster_points(3000)), "t", good, params(64));
    const std::string bytes = read_bytes(good);
    const std::string bad = (dir / "bad.mlc").string();
    auto open_error = [&](const std::string& b) {
        write_bytes(bad, b);
        const std::string m = error_of([&] { (void)PointStore::open(bad); });
        CHECK(m.find('\n') == std::string::npos);
        CHECK(m.rfind(bad, 0) == 0);
        // the in-memory parser and verify agree
        CHECK_THROWS_AS(parse_point_store_bytes(std::span(reinterpret_cast<const unsigned char*>(b.data()), b.size()), "x"), FormatError);
        CHECK_FALSE(verify_point_store(bad).ok);
        return m;
    };
    auto brick_error = [&](const std::string& b, std::size_t victim) {
        write_bytes(bad, b);
        const auto s = PointStore::open(bad);
        std::vector<double> pts;
        const std::string m = error_of([&] { s->read_brick(victim, pts); });
        CHECK(m.rfind(bad, 0) == 0);
        CHECK(m.find("brick " + std::to_string(victim) + " (cell level") != std::string::npos);
        const PointStoreVerifyReport r = verify_point_store(bad);
        CHECK_FALSE(r.ok);
        CHECK(r.first_bad_brick == std::optional<std::uint64_t>(victim));
        return m;
    };
    SECTION("bad magic") {
        std::string b = bytes;
        b[1] = 'X';
        CHECK_THAT(open_error(b), Contains("not a meshless point store"));
    }
    SECTION("unsupported version") {
        std::string b = bytes;
        put_le<std::uint32_t>(b, 8, 2);
        fix_header_crc(b);
        CHECK_THAT(open_error(b), Contains("unsupported point store version 2"));
    }
    SECTION("truncated") {
        for (std::size_t keep : {bytes.size() - 1, bytes.size() - 40, bytes.size() / 2, std::size_t{600}, std::size_t{100}, std::size_t{3}})
            CHECK_THAT(open_error(bytes.substr(0, keep)), Contains("truncated") || Contains("not a meshless point store"));
    }
    SECTION("header checksum") {
        std::string b = bytes;
        b[20] ^= 1;
        CHECK_THAT(open_error(b), Contains("header checksum mismatch"));
    }
    SECTION("index checksum") {
        std::string b = bytes;
        b[entry_at(b, 1) + 33] ^= 1;
        CHECK_THAT(open_error(b), Contains("index checksum mismatch"));
    }
    SECTION("non-finite bounds") {
        std::string b = bytes;
        put_le<double>(b, 48, std::numeric_limits<double>::quiet_NaN());
        fix_header_crc(b);
        CHECK_THAT(open_error(b), Contains("non-finite bounds"));
        b = bytes;
        put_le<double>(b, entry_at(b, 2) + 80, std::numeric_limits<double>::infinity());
        fix_index_crc(b);
        CHECK_THAT(open_error(b), Contains("index entry 2") && Contains("non-finite"));
    }
    SECTION("index offset out of range") {
        std::string b = bytes;
        put_le<std::uint64_t>(b, b.size() - 32, bytes.size() + 1000);
        CHECK_THAT(open_error(b), Contains("index offset"));
        b = bytes;
        put_le<std::uint64_t>(b, entry_at(b, 1) + 16, 1u << 30);  // a frame offset
        fix_index_crc(b);
        CHECK_THAT(open_error(b), Contains("index entry 1") && Contains("out of range"));
    }
    SECTION("count larger than the data") {
        std::string b = bytes;
        const std::size_t n = (get_le<std::uint64_t>(b, b.size() - 24));
        const std::size_t victim = 1;
        const std::uint64_t c = get_le<std::uint64_t>(b, entry_at(b, victim) + 32);
        if (c < 64) {
            put_le<std::uint64_t>(b, entry_at(b, victim) + 32, c + 1);
            for (std::size_t i = victim + 1; i < n; ++i) put_le<std::uint64_t>(b, entry_at(b, i) + 40, get_le<std::uint64_t>(b, entry_at(b, i) + 40) + 1);
            put_le<std::uint64_t>(b, 16, get_le<std::uint64_t>(b, 16) + 1);
            fix_header_crc(b);
            fix_index_crc(b);
            CHECK_THAT(brick_error(b, victim), Contains("the index says " + std::to_string(c + 1) + " points"));
        }
        b = bytes;  // a count the header's total does not match
        put_le<std::uint64_t>(b, 16, get_le<std::uint64_t>(b, 16) + 1);
        fix_header_crc(b);
        CHECK_THAT(open_error(b), Contains("points"));
    }
    SECTION("bad brick checksum") {
        std::string b = bytes;
        const std::size_t victim = 3;
        const std::uint64_t off = get_le<std::uint64_t>(b, entry_at(b, victim) + 16);
        b[off + 5] ^= 0x20;
        CHECK_THAT(brick_error(b, victim), Contains("checksum mismatch"));
    }
    SECTION("a point outside its brick (CRC recomputed): verify names the brick") {
        std::string b = bytes;
        // swap two bricks' bounds: every point then lies outside its brick's recorded bounds
        const std::size_t e1 = entry_at(b, 1), e2 = entry_at(b, 2);
        const std::string t = b.substr(e1 + 48, 48);
        b.replace(e1 + 48, 48, b.substr(e2 + 48, 48));
        b.replace(e2 + 48, 48, t);
        fix_index_crc(b);
        CHECK_THAT(brick_error(b, 1), Contains("outside the brick's bounds"));
    }
}

TEST_CASE("a point store rewritten while it is read: one line naming the file and the brick", "[ooc][point_store]") {
    TempDir dir("mlc-rewrite");
    const std::string path = (dir / "p.mlc").string();
    convert_points_to_point_store(producer(cluster_points(2000)), "t", path, params(64));
    const auto s = PointStore::open(path);
    std::vector<double> pts;
    s->read_brick(0, pts);
    std::this_thread::sleep_for(std::chrono::milliseconds(30));  // past the file system's timestamp granularity
    {
        const int fd = ::open(path.c_str(), O_WRONLY);
        REQUIRE(fd >= 0);
        const char z = 0;
        CHECK(::pwrite(fd, &z, 1, 600) == 1);  // same size, new contents
        ::close(fd);
    }
    CHECK_THAT(error_of([&] { s->read_brick(1, pts); }), Contains(path) && Contains("brick 1 (") && Contains("changed while it was read"));
}
