// The streaming splat sink (dissertation section 3.6) against the collect-all renderer: identical
// bytes for both kernels, any batch split, any thread count; bounded memory on a long synthetic
// stream (allocation counter); sample batches, an empty stream and an unusable spool directory.
// Also the tee sink and the PLY batch source.
#include <catch2/catch.hpp>
#include <malloc.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <numbers>
#include <random>
#include <optional>
#include <vector>

#include "formats/ply_points.hpp"
#include "kernels/errors.hpp"
#include "stream/record_vector_source.hpp"
#include "stream/ply_source.hpp"
#include "stream/point_sinks.hpp"
#include "stream/runner.hpp"
#include "stream/splat_sink.hpp"
#include "stream/tee_sink.hpp"
#include "test_paths.hpp"

// ---- live-byte counter for the bounded-memory test (whole test binary; cheap atomics) ----
namespace {
std::atomic<std::int64_t> g_live{0};
std::atomic<bool> g_counting{false};
}  // namespace

void* operator new(std::size_t n) {
    void* p = std::malloc(n ? n : 1);
    if (!p) throw std::bad_alloc();
    if (g_counting.load(std::memory_order_relaxed)) g_live += static_cast<std::int64_t>(malloc_usable_size(p));
    return p;
}
void operator delete(void* p) noexcept {
    if (p && g_counting.load(std::memory_order_relaxed)) g_live -= static_cast<std::int64_t>(malloc_usable_size(p));
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept { operator delete(p); }
// The nothrow forms too: AddressSanitizer brings its own, whose memory the free() above would
// release (alloc-dealloc mismatch; Catch2 allocates with new(std::nothrow)).
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
    try {
        return operator new(n);
    } catch (...) {
        return nullptr;
    }
}
void operator delete(void* p, const std::nothrow_t&) noexcept { operator delete(p); }

using namespace meshless;

namespace {

PointRecord rec(double x, double y, double z, double nx, double ny, double nz, float r) {
    PointRecord q{};
    q.pos[0] = float(x), q.pos[1] = float(y), q.pos[2] = float(z);
    q.normal[0] = float(nx), q.normal[1] = float(ny), q.normal[2] = float(nz);
    q.radius = r;
    return q;
}

// Two interleaved noisy spheres (overlapping depths, both orientations) plus a few degenerate
// records (NaN position, zero normal, zero radius): exercises ties, blending and the skips.
std::vector<PointRecord> test_points(int n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<PointRecord> pts;
    const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double y = 1.0 - 2.0 * (i + 0.5) / n, s = std::sqrt(1 - y * y);
        const double d[3] = {s * std::cos(golden * i), y, s * std::sin(golden * i)};
        const double rho = (i % 2 ? 0.8 : 0.6) + 0.01 * u(rng), sign = i % 3 ? 1.0 : -1.0;
        pts.push_back(rec(rho * d[0] + 0.1, rho * d[1], rho * d[2], sign * d[0], sign * d[1], sign * d[2],
                          float(0.03 + 0.01 * std::fabs(u(rng)))));
    }
    pts.push_back(rec(NAN, 0, 0, 0, 0, 1, 0.05f));
    pts.push_back(rec(0.2, 0.2, 0.9, 0, 0, 0, 0.05f));
    pts.push_back(rec(-0.3, 0.1, 0.7, 0, 0, 1, 0.0f));
    return pts;
}

Camera test_camera() {
    Camera c;
    c.width = 160;
    c.height = 120;
    c.azimuth_deg = 25;
    c.elevation_deg = 15;
    return c;
}

const std::array<Vec3, 2> kBox{Vec3{-1, -1, -1}, Vec3{1.2, 1, 1}};

class VectorSource final : public Source {
public:
    Payload gives() const override { return Payload::points; }
    VectorSource(const std::vector<PointRecord>& pts, std::vector<std::size_t> sizes) : pts_(pts), sizes_(std::move(sizes)) {}
    std::optional<Batch> next() override {
        if (at_ >= pts_.size() && !(pts_.empty() && seq_ == 0)) return std::nullopt;
        Batch b;
        b.kind = RecordKind::point;
        b.seq = seq_;
        const std::size_t n = std::min(sizes_[seq_ % sizes_.size()], pts_.size() - at_);
        b.points.assign(pts_.begin() + at_, pts_.begin() + at_ + n);
        at_ += n;
        ++seq_;
        if (pts_.empty()) at_ = 1;
        return b;
    }

private:
    const std::vector<PointRecord>& pts_;
    std::vector<std::size_t> sizes_;
    std::size_t at_ = 0;
    std::uint64_t seq_ = 0;
};

Image stream_render(const std::vector<PointRecord>& pts, SplatKernel k, std::vector<std::size_t> sizes, int threads,
                    bool staged, std::optional<std::size_t> spool_memory = {}) {
    SplatSink sink(test_camera(), k, ShadingParams{}, kBox, threads);
    if (spool_memory) sink.set_spool_memory(*spool_memory);
    VectorSource src(pts, std::move(sizes));
    std::vector<const Stage*> stages;
    if (staged) stages.push_back(&sink.stage());
    run_pipeline(src, stages, sink, {threads});
    return sink.image();
}

}  // namespace

TEST_CASE("splat sink: image identical to the collect-all renderer for any batch split and thread count", "[splat_sink]") {
    const auto pts = test_points(6000, 7);
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        const Image ref = render_splats(pts, test_camera(), k, ShadingParams{}, nullptr, kBox);
        // the reference is not trivial: both foreground and background present
        std::size_t bg = 0;
        for (std::size_t i = 0; i < ref.rgb.size(); i += 3) bg += ref.rgb[i] == 0 && ref.rgb[i + 1] == 0 && ref.rgb[i + 2] == 0;
        REQUIRE(bg > 1000);
        REQUIRE(bg < ref.rgb.size() / 3 - 1000);
        const std::vector<std::vector<std::size_t>> splits{{pts.size()}, {1}, {7, 1, 300}, {1000}, {65536}};
        for (const auto& split : splits)
            for (int threads : {1, 2, 3})
                for (bool staged : {false, true}) {
                    if (!staged && threads > 1 && split.size() > 1) continue;  // covered by the staged runs
                    INFO("kernel " << int(k) << " split " << split[0] << " threads " << threads << " staged " << staged);
                    CHECK(stream_render(pts, k, split, threads, staged).rgb == ref.rgb);
                }
        // EWA footprints all in the spool files, and split between memory and file (groups and
        // pass-2 parts that straddle the two tiers)
        for (const std::size_t tier : {std::size_t{0}, 777 * sizeof(EwaFootprint), 2500 * sizeof(EwaFootprint)})
            for (int threads : {1, 2}) {
                INFO("kernel " << int(k) << " spool memory " << tier << " threads " << threads);
                CHECK(stream_render(pts, k, {7, 1, 300}, threads, true, tier).rgb == ref.rgb);
            }
    }
}

TEST_CASE("splat sink: EWA pass 1 skips the splats behind nearer ones, whatever order they arrive in", "[splat_sink]") {
    // two parallel squares of overlapping splats, one behind the other as the camera sees them; the
    // far one arrives first (as Morton-ordered blocks often do), in batches that make several groups
    std::vector<PointRecord> pts;
    for (double z : {-0.5, 0.5})
        for (int j = 0; j <= 90; ++j)
            for (int i = 0; i <= 90; ++i) pts.push_back(rec(-0.6 + i * (1.2 / 90), -0.6 + j * (1.2 / 90), z, 0, 0, 1, 0.02f));
    Camera cam = test_camera();
    cam.azimuth_deg = 0;
    cam.elevation_deg = 0;
    const std::array<Vec3, 2> box{Vec3{-0.6, -0.6, -0.5}, Vec3{0.6, 0.6, 0.5}};
    const Image ref = render_splats(pts, cam, SplatKernel::ewa, ShadingParams{}, nullptr, box);
    for (bool reversed : {false, true}) {
        std::vector<PointRecord> in = pts;
        if (reversed) std::reverse(in.begin(), in.end());
        for (int threads : {1, 2}) {
            INFO("reversed " << reversed << " threads " << threads);
            SplatSink sink(cam, SplatKernel::ewa, ShadingParams{}, box, threads);
            VectorSource src(in, reversed ? std::vector<std::size_t>{97, 300, 4096} : std::vector<std::size_t>{4096});
            if (reversed) sink.set_spool_groups(100, 4);  // batches of 97..4096: groups merge 2 by 2
            const std::vector<const Stage*> stages{&sink.stage()};
            run_pipeline(src, stages, sink, {threads});
            CHECK(sink.image().rgb == ref.rgb);
            // every splat lands in the picture; with one thread, most of the far square is skipped
            if (threads == 1) CHECK(sink.stats().splats_drawn < static_cast<std::int64_t>(pts.size() * 3 / 4));
        }
    }
}

TEST_CASE("splat sink: a different point set gives a different image (the comparison can fail)", "[splat_sink]") {
    auto pts = test_points(3000, 7);
    const Image a = stream_render(pts, SplatKernel::ewa, {500}, 1, false);
    for (std::size_t i = 1; i < pts.size(); i += 40) pts[i].normal[1] = -pts[i].normal[1];  // a few tilted normals
    const Image b = stream_render(pts, SplatKernel::ewa, {500}, 1, false);
    std::size_t diff = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) diff += a.rgb[i] != b.rgb[i];
    std::size_t fg = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) fg += a.rgb[i] != 0;
    INFO("foreground bytes " << fg);
    CHECK(diff > 50);
}

TEST_CASE("splat sink: empty stream gives the background, samples are refused", "[splat_sink]") {
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        ShadingParams sh;
        sh.background = {12, 34, 56};
        SplatSink sink(test_camera(), k, sh, kBox);
        sink.finish();
        const Image& img = sink.image();
        REQUIRE(img.width == 160);
        REQUIRE(img.height == 120);
        for (std::size_t i = 0; i < img.rgb.size(); i += 3) {
            REQUIRE(img.rgb[i] == 12);
            REQUIRE(img.rgb[i + 2] == 56);
        }
        SplatSink s2(test_camera(), k, sh, kBox);
        RecordVectorSource samples(std::vector<SampleRecord>(3));  // a graph of samples into it is refused
        CHECK_THROWS_AS(run_pipeline(samples, {}, s2, {1}), GraphError);
    }
}

TEST_CASE("splat sink: an unusable spool directory is an IoError naming it", "[splat_sink]") {
    const char* old = std::getenv("TMPDIR");
    const std::string saved = old ? old : "";
    ::setenv("TMPDIR", "/nonexistent-meshless-dir", 1);
    try {
        SplatSink s(test_camera(), SplatKernel::ewa, ShadingParams{}, kBox);
        FAIL("no error");
    } catch (const IoError& e) {
        CHECK(std::string(e.what()).find("/nonexistent-meshless-dir/meshless-splat-spool") != std::string::npos);
    }
    CHECK_NOTHROW(SplatSink(test_camera(), SplatKernel::quad, ShadingParams{}, kBox));  // no spool needed
    if (old) ::setenv("TMPDIR", saved.c_str(), 1);
    else ::unsetenv("TMPDIR");
}

TEST_CASE("splat sink: memory does not grow with the number of points", "[splat_sink]") {
    // 400 batches of 8192 points (3.3 M points, 105 MB of records, 197 MB of EWA footprints)
    // streamed through the sink; the live heap may hold the buffers and about one batch, never the
    // stream; the EWA spool's memory tier (huge pages, not from operator new) stops at its budget.
    constexpr std::size_t kBatch = 8192, kBatches = 400;
    const std::int64_t batch_bytes = kBatch * sizeof(PointRecord);
    for (const std::size_t tier : {std::size_t{0}, std::size_t{10} << 20}) {
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa}) {
        INFO("spool memory " << tier);
        Camera cam = test_camera();
        cam.width = cam.height = 256;
        SplatSink sink(cam, k, ShadingParams{}, kBox);
        sink.set_spool_memory(tier);
        std::mt19937_64 rng(3);
        std::uniform_real_distribution<double> u(-0.9, 0.9);
        auto make_batch = [&](std::uint64_t seq) {
            Batch b;
            b.seq = seq;
            b.kind = RecordKind::point;
            b.points.resize(kBatch);
            for (auto& p : b.points) p = rec(u(rng), u(rng), u(rng), u(rng), u(rng), 1, 0.01f);
            return b;
        };
        for (std::uint64_t s = 0; s < 4; ++s) sink.consume(make_batch(s));  // warm-up: buffers allocated
        const std::size_t retained = sink.retained_bytes();
        // the whole heap (huge-page chunks come from aligned_alloc, which the counter does not see)
        const std::size_t heap0 = mallinfo2().uordblks + mallinfo2().hblkhd;
        g_live = 0;
        g_counting = true;
        std::int64_t peak = 0;
        for (std::uint64_t s = 4; s < kBatches; ++s) {
            sink.consume(make_batch(s));
            peak = std::max(peak, g_live.load());
        }
        g_counting = false;
        INFO("kernel " << int(k) << " peak live bytes above the warm-up " << peak);
        // the EWA spool's tier grew to its budget (less than a footprint short), never beyond it
        const std::size_t tier_used = k == SplatKernel::ewa ? tier - tier % sizeof(EwaFootprint) : 0;
        // the batch being built and moved in, nothing kept (but a short last chunk of the tier, below
        // the huge-page size, from operator new)
        CHECK(peak <= 2 * batch_bytes + static_cast<std::int64_t>(tier_used));
        const std::size_t heap1 = mallinfo2().uordblks + mallinfo2().hblkhd;
        CHECK(heap1 <= heap0 + tier_used + 2 * static_cast<std::size_t>(batch_bytes));
        CHECK(sink.retained_bytes() <= retained + tier_used);
        if (tier_used > 0) CHECK(sink.retained_bytes() >= tier_used - 3 * sizeof(EwaFootprint));
        CHECK(sink.points() == kBatch * kBatches);
        sink.finish();
        CHECK(sink.stats().splats_drawn > 0);
    }
    }
}

TEST_CASE("tee sink: both sinks see every batch, in order", "[splat_sink]") {
    const auto pts = test_points(2000, 11);
    CollectSink a, b;
    TeeSink tee(a, b);
    VectorSource src(pts, {333});
    run_pipeline(src, {}, tee, {2});
    REQUIRE(a.points.size() == pts.size());
    CHECK(std::memcmp(a.points.data(), pts.data(), pts.size() * sizeof(PointRecord)) == 0);
    CHECK(std::memcmp(b.points.data(), pts.data(), pts.size() * sizeof(PointRecord)) == 0);
}

TEST_CASE("PLY source: batches reproduce the file, a cut file names the file", "[splat_sink]") {
    meshless::test::TempDir dir("plysrc");
    const auto pts = test_points(70000, 5);  // more than one batch
    const std::string path = (dir / "p.ply").string();
    write_ply_points(path, pts, {"bounds_lo 0,0,0"});
    PlySource src(path);
    CHECK(src.count() == pts.size());
    REQUIRE(src.comments().size() == 1);
    std::vector<PointRecord> back;
    std::size_t batches = 0;
    while (auto b = src.next()) {
        CHECK(b->seq == batches);
        CHECK(b->points.size() <= kMaxBatchRecords);
        back.insert(back.end(), b->points.begin(), b->points.end());
        ++batches;
    }
    CHECK(batches == 2);
    REQUIRE(back.size() == pts.size());
    CHECK(std::memcmp(back.data(), pts.data(), pts.size() * sizeof(PointRecord)) == 0);

    // cut mid-record: the count check at open catches it
    std::filesystem::resize_file(path, std::filesystem::file_size(path) - 5);
    try {
        PlySource cut(path);
        while (cut.next()) {}
        FAIL("no error");
    } catch (const FormatError& e) {
        CHECK(std::string(e.what()).find(path) != std::string::npos);
    }
    // trailing bytes
    write_ply_points(path, pts, {});
    { std::ofstream(path, std::ios::app) << "xx"; }
    PlySource tail(path);
    CHECK_THROWS_AS([&] { while (tail.next()) {} }(), FormatError);
}

TEST_CASE("splat sink throughput (hidden, MESHLESS_SPLAT_BENCH_PLY=points.ply)", "[.splat_sink_bench]") {
    const char* path = std::getenv("MESHLESS_SPLAT_BENCH_PLY");
    std::vector<PointRecord> pts = path ? read_ply_points(path).points : test_points(1000000, 1);
    const auto bounds = point_bounds(pts);
    Camera cam;
    cam.width = cam.height = 1024;
    for (SplatKernel k : {SplatKernel::quad, SplatKernel::ewa})
        for (int threads : {1, 2}) {
            double best = 1e30, fin = 0;
            for (int rep = 0; rep < 3; ++rep) {
                const auto t0 = std::chrono::steady_clock::now();
                SplatSink sink(cam, k, ShadingParams{}, bounds, threads);
                VectorSource src(pts, {kMaxBatchRecords});
                const Stage* st[] = {&sink.stage()};
                run_pipeline(src, st, sink, {threads});
                const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                if (t < best) fin = sink.stats().seconds;
                best = std::min(best, t);
            }
            // the draw alone (one thread, no merge/resolve)
            SplatFrame f(cam, k, ShadingParams{}, bounds);
            std::vector<std::uint64_t> keys(f.npix(), SplatFrame::kEmptyKey);
            SplatStats s;
            const auto t1 = std::chrono::steady_clock::now();
            f.draw(pts, keys.data(), s);
            const double draw = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
            std::printf("%s %d thread(s): %zu points in %.3f s = %.2f M points/s (sink, best of 3); draw pass alone %.2f M points/s, %.2f fragments/splat; finish() %.3f s\n",
                        k == SplatKernel::quad ? "quad" : "ewa", threads, pts.size(), best, 1e-6 * pts.size() / best,
                        1e-6 * pts.size() / draw, double(s.fragments) / std::max<std::int64_t>(1, s.splats_drawn), fin);
        }
}
