// The batch job as a front end other than the CLI calls it (stream/batch_job.hpp): results per
// volume with a bad one among good ones, the callbacks (progress steps, the isovalue's range, each
// volume's end), a rerun up to date, a name claimed twice, leftovers of a killed run swept quietly;
// manifests read through the caller's raw-option parser (stream/batch_archive.hpp); output names.
// The CLI's own tests (tests/cli/test_batch.cpp) check the outputs byte for byte.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <optional>
#include <thread>
#include <string>
#include <vector>

#include "formats/temporary_files.hpp"
#include "kernels/errors.hpp"
#include "stream/batch_archive.hpp"
#include "stream/batch_job.hpp"
#include "stream/batch_shard.hpp"
#include "stream/batch_summary.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;
namespace fs = std::filesystem;

namespace {

/// A 16^3 uint8 ball, 255 - 16 x the distance to the centre in voxels (the file name or the
/// manifest gives the layout).
void write_ball(const fs::path& path) {
    std::string bytes(16 * 16 * 16, '\0');
    for (int z = 0; z < 16; ++z)
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) {
                const double r = std::sqrt((x - 7.5) * (x - 7.5) + (y - 7.5) * (y - 7.5) + (z - 7.5) * (z - 7.5));
                bytes[static_cast<std::size_t>((z * 16 + y) * 16 + x)] = static_cast<char>(std::lround(std::max(0.0, 255 - 16 * r)));
            }
    std::ofstream(path, std::ios::binary) << bytes;
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

}  // namespace

TEST_CASE("batch job: a bad volume among good ones, the callbacks, a rerun up to date", "[stream][batch]") {
    TempDir d("batch-job");
    fs::create_directories(d / "arch");
    write_ball(d / "arch" / "a_16x16x16_uint8.raw");
    write_ball(d / "arch" / "b_16x16x16_uint8.raw");
    write_text(d / "arch" / "c_16x16x16_uint8.raw", "short");  // truncated
    BatchSettings s;
    s.out_dir = (d / "out").string();
    s.isos = {100.5, 1000};
    s.stream = true;
    // a killed run's leftovers beside a planned output and a planned sidecar: removed, nobody told
    fs::create_directories(d / "out");
    const std::string dead = "999999999";  // above any pid_max (at most 2^22): no such process
    const fs::path stale1 = d / "out" / ("a_16x16x16_uint8.mlb.tmp-" + dead),
                   stale2 = d / "out" / ("b_16x16x16_uint8_iso100.5.ply.meta.tmp-" + dead + ".spool");
    write_text(stale1, "x");
    write_text(stale2, "x");
    write_text(d / "out" / ("unplanned.mlb.tmp-" + dead), "x");
    static int reported = 0;
    set_stale_temporary_reporter([](const char*, long) { ++reported; });

    std::vector<BatchProgress> steps;
    std::vector<std::string> ranges, done;
    BatchCallbacks cb;
    cb.progress = [&](const BatchProgress& p) { steps.push_back(p); };
    // the ball's largest sample: 255 - 16 x sqrt(3)/2 (the voxels nearest the centre) = 241
    cb.iso_range = [&](double iso, const std::array<double, 2>& range, const std::string& input) {
        ranges.push_back(fs::path(input).filename().string() + " " + batch_iso_name(iso) + " " + batch_iso_name(range[1]));
    };
    cb.item_done = [&](const BatchItemResult& r) { done.push_back(r.name); };
    const BatchRun run = run_batch((d / "arch").string(), s, cb);
    set_stale_temporary_reporter(nullptr);
    CHECK(reported == 0);
    CHECK_FALSE(fs::exists(stale1));
    CHECK_FALSE(fs::exists(stale2));
    CHECK(fs::exists(d / "out" / ("unplanned.mlb.tmp-" + dead)));

    REQUIRE(run.items.size() == 3);
    CHECK(run.items[0].status == BatchStatus::done);
    CHECK(run.items[0].written == 5);  // the store, and a PLY and a stream per isovalue
    CHECK(run.items[1].status == BatchStatus::done);
    CHECK(run.items[2].status == BatchStatus::failed);
    CHECK(run.items[2].written == 0);
    CHECK_THAT(run.items[2].message, Catch::Contains("c_16x16x16_uint8.raw"));
    CHECK(run.any_failed());
    CHECK(run.items[0].empty == 1);  // isovalue 1000: no brick crosses it
    CHECK(done == std::vector<std::string>{"a_16x16x16_uint8", "b_16x16x16_uint8", "c_16x16x16_uint8"});
    CHECK(ranges == std::vector<std::string>{"a_16x16x16_uint8.raw 100.5 241", "a_16x16x16_uint8.raw 1000 241",
                                             "b_16x16x16_uint8.raw 100.5 241", "b_16x16x16_uint8.raw 1000 241"});
    for (const char* f : {"a_16x16x16_uint8.mlb", "a_16x16x16_uint8_iso100.5.ply", "a_16x16x16_uint8_iso100.5.mlp",
                          "b_16x16x16_uint8_iso1000.ply", "b_16x16x16_uint8_iso1000.mlp.meta"})
        CHECK(fs::exists(d / "out" / f));
    REQUIRE_FALSE(steps.empty());
    CHECK(steps.front().index == 0);
    CHECK(steps.front().count == 3);
    CHECK(steps.front().what == "hashing input");
    for (std::size_t i = 1; i < steps.size(); ++i) CHECK(steps[i].batch >= steps[i - 1].batch);
    CHECK(steps.back().batch < 1);  // c's bytes are never counted as done while it runs

    const BatchRun again = run_batch((d / "arch").string(), s, {});
    CHECK(again.items[0].status == BatchStatus::up_to_date);
    CHECK(again.items[0].current == 5);
    CHECK(again.items[2].status == BatchStatus::failed);

    std::FILE* table = std::tmpfile();
    print_batch_summary(table, again);
    std::rewind(table);
    std::string text(4096, '\0');
    text.resize(std::fread(text.data(), 1, text.size(), table));
    std::fclose(table);
    CHECK(text.rfind("volume            result      written  up to date   seconds\n"
                     "a_16x16x16_uint8  up to date        0           5  ", 0) == 0);
    // isovalue 1000 lies above the ball's 241: an empty point set per volume, counted up to date too
    CHECK(again.items[0].empty == 1);
    CHECK(again.items[1].empty == 1);
    CHECK(again.any_empty());
    CHECK_THAT(text, Catch::Contains("a_16x16x16_uint8  up to date        0           5      0.00  empty at 1 isovalue(s)\n"));
    CHECK_THAT(text, Catch::Contains("\n3 volume(s): 0 done, 2 up to date, 1 failed, 2 with empty point sets; 0 output(s) written, "
                                     "10 up to date; "));

    CHECK_THROWS_AS(run_batch((d / "arch" / "a_16x16x16_uint8.raw").string(), s, {}), InvalidArgument);
    CHECK_THROWS_AS(run_batch((d / "missing").string(), s, {}), IoError);
}

TEST_CASE("batch job: manifests through the caller's parser, a name claimed twice fails the second", "[stream][batch]") {
    TempDir d("batch-manifest");
    fs::create_directories(d / "x");
    write_ball(d / "ball.raw");
    write_ball(d / "x" / "ball_16x16x16_uint8.raw");
    write_text(d / "list.txt",
               "# comment\n"
               "ball.raw --dims 16,16,16 --type uint8\n"
               "x/ball_16x16x16_uint8.raw\n"
               "\"unterminated.raw\n"
               "ball.raw --bad\n");
    const auto parse = [](const std::vector<std::string>& words) {
        if (words != std::vector<std::string>{"--dims", "16,16,16", "--type", "uint8"}) throw InvalidArgument("bad options");
        RawOptions r;
        r.dims = std::array<std::int64_t, 3>{16, 16, 16};
        r.type = SampleType::u8;
        return r;
    };
    const std::vector<BatchItem> items = read_manifest((d / "list.txt").string(), parse);
    REQUIRE(items.size() == 4);
    CHECK(items[0].name == "ball");
    CHECK(items[0].raw_text == "dims=16,16,16 type=uint8");
    CHECK(items[0].raw.references.root == d.path.string());
    CHECK(items[1].name == "ball_16x16x16_uint8");
    CHECK(items[1].error.empty());
    CHECK(items[2].name == "line 4");
    CHECK_THAT(items[2].error, Catch::EndsWith("list.txt:4: unterminated quote"));
    CHECK_THAT(items[3].error, Catch::EndsWith("list.txt:5: bad options"));
    CHECK_THAT(read_manifest((d / "list.txt").string(), {})[0].error, Catch::Contains("list.txt:2: "));

    BatchSettings s;
    s.out_dir = (d / "out").string();
    BatchCallbacks cb;
    cb.parse_raw = parse;
    write_text(d / "twice.txt", "ball.raw --dims 16,16,16 --type uint8\n./ball.raw --dims 16,16,16 --type uint8\n");
    const BatchRun run = run_batch((d / "twice.txt").string(), s, cb);
    REQUIRE(run.items.size() == 2);
    CHECK(run.items[0].status == BatchStatus::done);
    CHECK(run.items[0].written == 1);  // the store alone: no isovalue
    CHECK(run.items[1].status == BatchStatus::failed);
    CHECK_THAT(run.items[1].message, Catch::Contains("its outputs would be named 'ball'"));
}

TEST_CASE("batch output names: volume_stem and batch_iso_name", "[stream][batch]") {
    CHECK(volume_stem("fuel_64x64x64_uint8.raw") == "fuel_64x64x64_uint8");
    CHECK(volume_stem("dir/a.nii.gz") == "a");
    CHECK(volume_stem("A.VTK.GZ") == "A");
    CHECK(volume_stem("d/index.json") == "d");
    CHECK(volume_stem(".nii.gz") == ".nii");
    CHECK(volume_stem("noext") == "noext");
    CHECK(batch_iso_name(100.5) == "100.5");
    CHECK(batch_iso_name(1.0 / 3) == "0.333333333");
}

TEST_CASE("batch job: a dynamic deal converts what it is dealt, largest first, two ranks as threads give one run's outputs", "[stream][batch]") {
    TempDir d("batch-deal");
    fs::create_directories(d / "arch");
    // sizes: big (24^3) > b, c, e (16^3) > a short file (a failure)
    {
        std::string big(24 * 24 * 24, '\0');
        for (std::size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>((i * 7) % 256);
        write_text(d / "arch" / "big_24x24x24_uint8.raw", big);
    }
    for (const char* n : {"b", "c", "e"}) write_ball(d / "arch" / (std::string(n) + "_16x16x16_uint8.raw"));
    write_text(d / "arch" / "a_16x16x16_uint8.raw", "short");
    BatchSettings s;
    s.isos = {100.5};
    s.out_dir = (d / "one").string();
    const BatchRun one = run_batch((d / "arch").string(), s, {});
    REQUIRE(one.items.size() == 5);

    // the deal's order: positions in the size order, taken by two "ranks" (threads) from one counter
    std::vector<BatchItem> listed = list_archive_dir((d / "arch").string(), false, "");
    const std::vector<std::size_t> order = size_order(listed);
    CHECK(listed[order[0]].name == "big_24x24x24_uint8");  // the largest is dealt first
    CHECK(listed[order.back()].name == "a_16x16x16_uint8");
    std::mutex m;
    std::size_t next = 0;
    std::vector<std::pair<int, std::size_t>> dealt;
    auto deal_to = [&](int rank) {
        return [&, rank]() -> std::optional<std::size_t> {
            std::lock_guard lock(m);
            if (next >= order.size()) return std::nullopt;
            dealt.emplace_back(rank, next);
            return next++;
        };
    };
    BatchRun runs[2];
    {
        std::vector<std::jthread> ranks;
        for (int r = 0; r < 2; ++r)
            ranks.emplace_back([&, r] {
                BatchSettings t = s;
                t.out_dir = (d / "two").string();
                t.shard = static_cast<std::uint32_t>(r);
                t.shards = 2;
                t.deal = deal_to(r);
                runs[r] = run_batch((d / "arch").string(), t, {});
            });
    }
    CHECK(dealt.size() == 5);
    CHECK(runs[0].items.size() + runs[1].items.size() == 5);
    std::vector<std::string> names;
    for (const BatchRun& r : runs)
        for (const BatchItemResult& x : r.items) names.push_back(x.name);
    std::sort(names.begin(), names.end());
    CHECK(std::adjacent_find(names.begin(), names.end()) == names.end());  // each volume converted once
    for (const auto& e : fs::directory_iterator(d / "one")) {
        if (e.path().extension() != ".ply" && e.path().extension() != ".mlb") continue;
        INFO(e.path().filename());
        REQUIRE(fs::exists(d / "two" / e.path().filename()));
        std::ifstream a(e.path(), std::ios::binary), b(d / "two" / e.path().filename(), std::ios::binary);
        CHECK(std::string(std::istreambuf_iterator<char>(a), {}) == std::string(std::istreambuf_iterator<char>(b), {}));
    }
    // a deal beyond the archive is a programming error
    BatchSettings bad = s;
    bad.out_dir = (d / "bad").string();
    bad.deal = [calls = 0]() mutable -> std::optional<std::size_t> { return calls++ == 0 ? std::optional<std::size_t>(99) : std::nullopt; };
    CHECK_THROWS_AS(run_batch((d / "arch").string(), bad, {}), std::logic_error);
}
