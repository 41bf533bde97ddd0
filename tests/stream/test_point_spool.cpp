// The point spool (stream/point_spool.hpp) alone: points round-trip through the unlinked file in
// any append split and any replay batch size, bounds equal point_bounds (non-finite positions
// skipped), the empty spool, the file gone from $TMPDIR from the start, errors naming the file, and
// a replaying source that holds at most one batch whatever the thread count.
#include <catch2/catch.hpp>
#include <bit>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "kernels/errors.hpp"
#include "formats/ply_points.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/point_sinks.hpp"
#include "stream/point_spool.hpp"
#include "stream/runner.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;
namespace fs = std::filesystem;

namespace {

std::vector<PointRecord> random_points(std::size_t n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> u(-3, 5);
    std::vector<PointRecord> pts(n);
    for (auto& p : pts)
        for (float* f : {&p.pos[0], &p.pos[1], &p.pos[2], &p.normal[0], &p.normal[1], &p.normal[2], &p.radius, &p.value})
            *f = u(rng);
    return pts;
}

bool same(const std::vector<PointRecord>& a, const std::vector<PointRecord>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(PointRecord)) == 0;
}

/// Sets TMPDIR for the scope of the object.
struct ScopedTmpdir {
    explicit ScopedTmpdir(const std::string& dir) {
        if (const char* old = std::getenv("TMPDIR")) saved = old;
        had = std::getenv("TMPDIR") != nullptr;
        ::setenv("TMPDIR", dir.c_str(), 1);
    }
    ~ScopedTmpdir() {
        if (had) ::setenv("TMPDIR", saved.c_str(), 1);
        else ::unsetenv("TMPDIR");
    }
    std::string saved;
    bool had = false;
};

}  // namespace

TEST_CASE("point spool: the value range keeps the first of equal extremes in any split", "[point_spool]") {
    // extremes +0 and -0 (the bits show which of the equal zeros is kept), non-finite values ignored
    const float values[] = {0.0f, -0.0f, NAN, INFINITY, -INFINITY, -0.0f, 0.0f};
    std::mt19937 rng(43);
    std::vector<PointRecord> pts(300);
    for (PointRecord& p : pts) p.value = values[rng() % 7];
    pts[5].value = -0.0f;  // at least one finite value
    double lo = 0, hi = 0;
    bool any = false;
    for (const PointRecord& p : pts) {
        if (!std::isfinite(p.value)) continue;
        lo = any ? std::min<double>(lo, p.value) : p.value;
        hi = any ? std::max<double>(hi, p.value) : p.value;
        any = true;
    }
    for (std::size_t split : {std::size_t{1}, std::size_t{5}, std::size_t{64}, pts.size()}) {
        INFO("appends of " << split);
        PointSpool spool("test-spool");
        for (std::size_t at = 0; at < pts.size(); at += split)
            spool.append(std::span(pts).subspan(at, std::min(split, pts.size() - at)));
        const auto range = spool.value_range();
        REQUIRE(range.has_value());
        CHECK(std::bit_cast<std::uint64_t>((*range)[0]) == std::bit_cast<std::uint64_t>(lo));
        CHECK(std::bit_cast<std::uint64_t>((*range)[1]) == std::bit_cast<std::uint64_t>(hi));
    }
}

TEST_CASE("point spool: round trip in any split, bounds as point_bounds", "[point_spool]") {
    auto pts = random_points(150000, 5);
    pts[17].pos[1] = NAN;  // skipped by the bounds, kept in the spool
    pts[99].pos[0] = -INFINITY;
    pts[1234].pos[2] = 1e6f;  // far outside: must widen the bounds
    PointSpool spool("test-spool");
    std::size_t at = 0;
    for (std::size_t n : {0, 1, 7, 65536, 3, 70000}) {  // uneven appends, the rest at the end
        spool.append(std::span(pts).subspan(at, n));
        at += n;
    }
    spool.append(std::span(pts).subspan(at));
    REQUIRE(spool.size() == pts.size());
    const auto want = point_bounds(pts);
    const auto got = spool.bounds();
    CHECK(got[1].z == 1e6);
    for (int i = 0; i < 2; ++i) {
        CHECK(got[i].x == want[i].x);
        CHECK(got[i].y == want[i].y);
        CHECK(got[i].z == want[i].z);
    }
    for (std::size_t per : {std::size_t{1000}, kMaxBatchRecords, std::size_t{1} << 30})
        for (int threads : {1, 2}) {
            INFO("batch " << per << " threads " << threads);
            PointSpoolSource source(spool, per);
            CollectSink out;
            run_pipeline(source, {}, out, {threads});
            CHECK(same(out.points, pts));
        }
    // batches are at most the requested size, with dense sequence numbers
    PointSpoolSource source(spool, 40000);
    std::uint64_t seq = 0;
    std::size_t total = 0;
    while (auto b = source.next()) {
        CHECK(b->seq == seq++);
        CHECK(b->kind == RecordKind::point);
        CHECK(b->points.size() == std::min<std::size_t>(40000, pts.size() - total));
        total += b->points.size();
    }
    CHECK(total == pts.size());
    // random access
    std::vector<PointRecord> mid(10);
    spool.read(140000, mid);
    CHECK(std::memcmp(mid.data(), pts.data() + 140000, sizeof(PointRecord) * 10) == 0);
}

TEST_CASE("point spool: empty, a graph can end in it, samples are refused", "[point_spool]") {
    PointSpool spool;
    CHECK(spool.size() == 0);
    CHECK(spool.bounds()[0].x == 0);
    CHECK(spool.bounds()[1].z == 0);
    PointSpoolSource empty(spool);
    CHECK_FALSE(empty.next());

    const auto pts = random_points(5000, 9);
    PointSpool sunk;
    std::vector<PointRecord> copy = pts;
    struct Once final : Source {
        Payload gives() const override { return Payload::points; }
        std::vector<PointRecord>* p;
        bool done = false;
        std::optional<Batch> next() override {
            if (done) return std::nullopt;
            done = true;
            Batch b;
            b.kind = RecordKind::point;
            b.points = *p;
            return b;
        }
    } src;
    src.p = &copy;
    run_pipeline(src, {}, sunk, {2});
    CollectSink out;
    PointSpoolSource replay(sunk);
    run_pipeline(replay, {}, out, {1});
    CHECK(same(out.points, pts));

    RecordVectorSource samples(std::vector<SampleRecord>(2));  // a graph of samples into it is refused
    CHECK(sunk.takes() == PayloadSet(Payload::points));
    CHECK_THROWS_AS(run_pipeline(samples, {}, sunk, {1}), GraphError);
}

TEST_CASE("point spool: the file is unlinked in $TMPDIR, errors name it", "[point_spool]") {
    TempDir d("spooldir");
    {
        ScopedTmpdir t(d.path.string());
        PointSpool spool("named");
        CHECK(spool.name().rfind((d.path / "meshless-named-").string(), 0) == 0);
        spool.append(random_points(1000, 1));
        spool.flush();
        CHECK(fs::is_empty(d.path));  // nothing to clean up, whatever happens to the process
        std::vector<PointRecord> past(10);
        try {
            spool.read(995, past);
            FAIL("no error");
        } catch (const IoError& e) {
            CHECK_THAT(e.what(), Catch::Contains(spool.name()) && Catch::Contains("holds 1000"));
        }
    }
    ScopedTmpdir t((d.path / "missing").string());
    try {
        PointSpool spool("named");
        FAIL("no error");
    } catch (const IoError& e) {
        CHECK_THAT(e.what(), Catch::Contains((d.path / "missing" / "meshless-named-").string()));
    }
}

TEST_CASE("point spool: the replaying source holds at most one batch", "[point_spool]") {
    const auto pts = random_points(20 * kMaxBatchRecords + 5, 3);
    PointSpool spool;
    spool.append(pts);
    for (int threads : {1, 2, 4}) {
        PointSpoolSource source(spool);
        CollectSink out(/*keep_chunks=*/true);  // takes the arrays: nothing comes back to recycle
        run_pipeline(source, {}, out, {threads});
        CHECK(source.retained_bytes() == 0);
        CHECK(out.size() == pts.size());

        // a sink that only reads: arrays come back and are reused, one kept at a time
        struct Count final : Sink {
            PayloadSet takes() const override { return Payload::points; }
            std::size_t n = 0;
            void consume(Batch&& b) override { n += b.points.size(); }
        } count;
        PointSpoolSource reused(spool);
        run_pipeline(reused, {}, count, {threads});
        CHECK(count.n == pts.size());
        CHECK(reused.retained_bytes() <= kMaxBatchRecords * sizeof(PointRecord));
        CHECK(reused.retained_bytes() > 0);
    }
}

TEST_CASE("point spool in place: a PLY of PointRecords replays itself, as a written spool would", "[point_spool]") {
    TempDir d("spool-in-place");
    auto pts = random_points(3 * kMaxBatchRecords + 123, 21);
    pts[5].value = NAN;       // not in the value range
    pts[6].pos[0] = INFINITY;  // not in the bounds
    pts[7].value = 1e9f;      // widens the value range
    const std::string ply = (d.path / "p.ply").string();
    write_ply_points(ply, pts, {"a comment"});
    REQUIRE(PointSpool::can_be_in_place(ply));
    PointSpool written("test");
    written.append(pts);
    for (int threads : {1, 2, 3}) {
        INFO("threads " << threads);
        PointSpool in(PointSpool::InPlace{}, ply, threads);
        CHECK(in.size() == pts.size());
        CHECK(in.name() == ply);
        CHECK_FALSE(in.has_blocks());
        REQUIRE(in.value_range().has_value());
        CHECK((*in.value_range())[0] == (*written.value_range())[0]);
        CHECK((*in.value_range())[1] == 1e9);
        for (int i = 0; i < 2; ++i) {
            CHECK(in.bounds()[i].x == written.bounds()[i].x);
            CHECK(in.bounds()[i].y == written.bounds()[i].y);
            CHECK(in.bounds()[i].z == written.bounds()[i].z);
        }
        PointSpoolSource source(in, 50000);
        CollectSink out;
        run_pipeline(source, {}, out, {threads});
        CHECK(same(out.points, pts));
        std::vector<PointRecord> mid(3);
        in.read(pts.size() - 3, mid);
        CHECK(std::memcmp(mid.data(), pts.data() + pts.size() - 3, sizeof(PointRecord) * 3) == 0);
        CHECK_THROWS_AS(in.append(std::span(pts).first(1)), std::logic_error);
        std::vector<PointRecord> past(4);
        CHECK_THROWS_WITH(in.read(pts.size() - 3, past), Catch::Contains(ply) && Catch::Contains("read in place"));
    }
    // an empty set
    const std::string empty = (d.path / "empty.ply").string();
    write_ply_points(empty, {}, {});
    PointSpool none(PointSpool::InPlace{}, empty);
    CHECK(none.size() == 0);
    CHECK_FALSE(none.value_range().has_value());
}

TEST_CASE("point spool in place: other PLY layouts are not, broken files are refused naming them", "[point_spool][mustfail]") {
    TempDir d("spool-in-place-bad");
    const auto pts = random_points(1000, 22);
    const std::string good = (d.path / "good.ply").string();
    write_ply_points(good, pts, {});
    const std::vector<std::uint32_t> ids(pts.size(), 3);
    const std::string blocks = (d.path / "blocks.ply").string();
    write_ply_points(blocks, pts, {}, std::span<const std::uint32_t>(ids));
    CHECK_FALSE(PointSpool::can_be_in_place(blocks));                      // 36-byte records
    CHECK_THROWS_WITH(PointSpool(PointSpool::InPlace{}, blocks), Catch::Contains(blocks) && Catch::Contains("cannot be read in place"));
    CHECK_FALSE(PointSpool::can_be_in_place((d.path / "none.ply").string()));  // no such file
    const std::string ascii = (d.path / "ascii.ply").string();
    {
        std::ofstream f(ascii);
        f << "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n";
    }
    CHECK_FALSE(PointSpool::can_be_in_place(ascii));
    // trailing bytes and a truncated body: the reader's errors, naming the file
    const std::string trailing = (d.path / "trailing.ply").string();
    fs::copy_file(good, trailing);
    {
        std::ofstream f(trailing, std::ios::app | std::ios::binary);
        f << "xyz";
    }
    REQUIRE(PointSpool::can_be_in_place(trailing));
    CHECK_THROWS_WITH(PointSpool(PointSpool::InPlace{}, trailing, 2), Catch::Contains(trailing) && Catch::Contains("trailing"));
    const std::string cut = (d.path / "cut.ply").string();
    fs::copy_file(good, cut);
    fs::resize_file(cut, fs::file_size(cut) - 40);
    CHECK_THROWS_AS(PointSpool(PointSpool::InPlace{}, cut, 2), FormatError);
}
