// meshless batch, the nightly job, as a user runs it: outputs and sidecars, bad inputs reported
// with exit 2, reruns that skip what is up to date with byte-identical outputs, only changed inputs
// redone, a run killed with SIGKILL and restarted ends identical to a clean run, manifests with
// missing entries and raw options, and a file size limit hit mid-run leaves no partial output.
// Oracles: the PLY written by batch equals `meshless isosurface NAME.mlb` and `meshless write
// NAME.mlp`; a manifest entry with --dims/--type gives the same store as the name convention;
// reruns and restarted runs are compared byte for byte with a clean run.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <thread>

#include "cli/cli_harness.hpp"
#include "kernels/analytic_volumes.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

/// An n^3 uint8 analytic volume (value*200 clamped), written as NAME_nxnxn_uint8.raw (or `file`).
std::string write_volume(const fs::path& dir, AnalyticField field, int n, const std::string& stem,
                         const std::string& file = "") {
    const Volume v = make_analytic_volume(field, n);
    const float* f = reinterpret_cast<const float*>(v.bytes.data());
    std::string bytes(static_cast<std::size_t>(v.grid.voxel_count()), '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<char>(static_cast<unsigned char>(std::clamp(std::lround(f[i] * 200.0 + 60), 0L, 255L)));
    const std::string name = file.empty() ? stem + "_" + std::to_string(n) + "x" + std::to_string(n) + "x" +
                                                std::to_string(n) + "_uint8.raw"
                                          : file;
    spit(dir / name, bytes);
    return (dir / name).string();
}

/// Every file under dir (relative path -> bytes), without the lock file.
std::map<std::string, std::string> snapshot(const fs::path& dir) {
    std::map<std::string, std::string> m;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.is_regular_file() && e.path().filename().string().rfind(".meshless-batch", 0) != 0)  // (the lock files)
            m[e.path().lexically_relative(dir).string()] = slurp(e.path());
    return m;
}

std::map<std::string, fs::file_time_type> mtimes(const fs::path& dir) {
    std::map<std::string, fs::file_time_type> m;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file()) m[e.path().filename().string()] = e.last_write_time();
    return m;
}

bool has_temporaries(const fs::path& dir) {
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos) return true;
    return false;
}

/// The summary table row of a volume.
std::string row(const std::string& out, const std::string& name) {
    const auto p = out.find("\n" + name + " ");
    if (p == std::string::npos) return "";
    return out.substr(p + 1, out.find('\n', p + 1) - p - 1);
}

/// Every output in dir is complete: it has a sidecar recording its size.
void check_outputs_recorded(const fs::path& dir) {
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (n.front() == '.' || n.size() < 5 || n.substr(n.size() - 5) == ".meta") continue;
        INFO(n);
        REQUIRE(fs::exists(e.path().string() + ".meta"));
        CHECK_THAT(slurp(e.path().string() + ".meta"),
                   Catch::Contains("output_size=" + std::to_string(fs::file_size(e.path()))));
    }
}

}  // namespace

TEST_CASE("batch converts an archive, reports the bad input, and a rerun is up to date", "[batch]") {
    TempDir d("batch-archive");
    const fs::path arch = d / "arch", out = d / "out";
    fs::create_directories(arch);
    write_volume(arch, AnalyticField::sphere, 20, "sphere");
    write_volume(arch, AnalyticField::torus, 24, "torus");
    spit(arch / "garbage_16x16x16_uint8.raw", "not a volume at all");
    spit(arch / "notes.txt", "not a volume by name: ignored");
    // a detached NRRD header: its payload file is part of it, not a volume of its own
    write_volume(arch, AnalyticField::sphere, 20, "", "payload.raw");
    spit(arch / "detached.nhdr", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 20 20 20\nencoding: raw\ndata file: payload.raw\n");
    const std::string cmd = "MESHLESS batch " + arch.string() + " -o " + out.string() + " --iso 100.5 --iso 180 --formats ply,stream";

    auto r = sh(cmd, d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("garbage_16x16x16_uint8.raw"));
    CHECK_THAT(row(r.out, "garbage_16x16x16_uint8"), Catch::Contains("FAILED"));
    CHECK_THAT(row(r.out, "sphere_20x20x20_uint8"), Catch::Contains("done"));
    CHECK_THAT(row(r.out, "torus_24x24x24_uint8"), Catch::Contains("done"));
    CHECK_THAT(row(r.out, "detached"), Catch::Contains("done"));
    CHECK(row(r.out, "payload").empty());
    CHECK(row(r.out, "notes").empty());
    CHECK_THAT(r.out, Catch::Contains("4 volume(s): 3 done, 0 up to date, 1 failed; 15 output(s) written"));
    for (const char* name : {"sphere_20x20x20_uint8", "torus_24x24x24_uint8", "detached"}) {
        for (const char* iso : {"100.5", "180"}) {
            INFO(name << " iso " << iso);
            const std::string stem = (out / name).string();
            const std::string ply = stem + "_iso" + iso + ".ply";
            REQUIRE(fs::exists(ply));
            CHECK(fs::file_size(ply) > 1000);
            // the same bytes as the single commands on the store
            REQUIRE(sh("MESHLESS isosurface " + stem + ".mlb --iso " + iso + " -o " + (d / "ref.ply").string(), d).code == 0);
            CHECK(slurp(ply) == slurp(d / "ref.ply"));
            REQUIRE(sh("MESHLESS write " + stem + "_iso" + iso + ".mlp -o " + (d / "ref2.ply").string(), d).code == 0);
            CHECK(slurp(ply) == slurp(d / "ref2.ply"));
        }
    }
    CHECK(!fs::exists(out / "garbage_16x16x16_uint8.mlb"));
    check_outputs_recorded(out);
    CHECK(!has_temporaries(out));

    // rerun: everything up to date, nothing rewritten, the exit status still reports the bad input
    const auto before = snapshot(out);
    const auto times = mtimes(out);
    r = sh(cmd, d);
    CHECK(r.code == 2);
    CHECK_THAT(row(r.out, "sphere_20x20x20_uint8"), Catch::Contains("up to date"));
    CHECK_THAT(row(r.out, "torus_24x24x24_uint8"), Catch::Contains("up to date"));
    CHECK_THAT(r.out, Catch::Contains("0 done, 3 up to date, 1 failed; 0 output(s) written, 15 up to date"));
    CHECK(snapshot(out) == before);
    CHECK(mtimes(out) == times);

    // without the bad input the run succeeds
    fs::remove(arch / "garbage_16x16x16_uint8.raw");
    r = sh(cmd, d);
    CHECK(r.code == 0);
    CHECK(r.err.empty());
}

TEST_CASE("batch redoes only what changed: modified input, new parameters, a deleted output", "[batch]") {
    TempDir d("batch-change");
    const fs::path arch = d / "arch", out = d / "out";
    fs::create_directories(arch);
    const std::string sphere = write_volume(arch, AnalyticField::sphere, 20, "sphere");
    write_volume(arch, AnalyticField::torus, 24, "torus");
    const std::string cmd = "MESHLESS batch " + arch.string() + " -o " + out.string() + " --iso 100.5";
    REQUIRE(sh(cmd, d).code == 0);
    const auto clean = snapshot(out);

    // touched, same bytes: up to date (the content hash decides), the sidecar records the new time
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    fs::last_write_time(sphere, fs::file_time_type::clock::now());
    auto r = sh(cmd, d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("0 done, 2 up to date"));
    auto now = snapshot(out);
    CHECK(now.at("sphere_20x20x20_uint8_iso100.5.ply") == clean.at("sphere_20x20x20_uint8_iso100.5.ply"));
    CHECK(now.at("sphere_20x20x20_uint8.mlb.meta") != clean.at("sphere_20x20x20_uint8.mlb.meta"));
    CHECK(now.at("torus_24x24x24_uint8.mlb.meta") == clean.at("torus_24x24x24_uint8.mlb.meta"));

    // modified: only that volume is redone, and its outputs change
    std::string bytes = slurp(sphere);
    for (std::size_t i = 0; i < bytes.size(); i += 7) bytes[i] = static_cast<char>(255 - static_cast<unsigned char>(bytes[i]));
    spit(sphere, bytes);
    const auto torus_times = mtimes(out);
    r = sh(cmd, d);
    CHECK(r.code == 0);
    CHECK_THAT(row(r.out, "sphere_20x20x20_uint8"), Catch::Contains("done"));
    CHECK_THAT(row(r.out, "torus_24x24x24_uint8"), Catch::Contains("up to date"));
    now = snapshot(out);
    CHECK(now.at("sphere_20x20x20_uint8.mlb") != clean.at("sphere_20x20x20_uint8.mlb"));
    CHECK(now.at("sphere_20x20x20_uint8_iso100.5.ply") != clean.at("sphere_20x20x20_uint8_iso100.5.ply"));
    CHECK(mtimes(out).at("torus_24x24x24_uint8.mlb") == torus_times.at("torus_24x24x24_uint8.mlb"));
    CHECK(mtimes(out).at("torus_24x24x24_uint8_iso100.5.ply") == torus_times.at("torus_24x24x24_uint8_iso100.5.ply"));
    check_outputs_recorded(out);

    // a deleted output: only it is redone, with the same bytes
    const auto before = snapshot(out);
    fs::remove(out / "torus_24x24x24_uint8_iso100.5.ply");
    r = sh(cmd, d);
    CHECK(r.code == 0);
    CHECK_THAT(row(r.out, "torus_24x24x24_uint8"), Catch::Contains("done"));
    CHECK_THAT(r.out, Catch::Contains("1 output(s) written, 3 up to date"));
    CHECK(snapshot(out) == before);

    // another brick edge: stores and point sets are redone, a new isovalue adds only its outputs
    r = sh(cmd + " --brick 8 --iso 150", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("6 output(s) written, 0 up to date"));
    CHECK_THAT(slurp(out / "torus_24x24x24_uint8.mlb.meta"), Catch::Contains("param.brick=8"));
    r = sh(cmd + " --brick 8 --iso 150 --iso 70", d);
    CHECK_THAT(r.out, Catch::Contains("2 output(s) written, 6 up to date"));
}

TEST_CASE("batch killed with SIGKILL and run again ends identical to a clean run", "[batch]") {
    TempDir d("batch-kill");
    const fs::path arch = d / "arch";
    fs::create_directories(arch);
    write_volume(arch, AnalyticField::gyroid, 112, "gyroid");
    write_volume(arch, AnalyticField::torus, 112, "torus");
    write_volume(arch, AnalyticField::marschner_lobb, 112, "ml");
    const std::string args = " --iso 100.5 --iso 140 --iso 170 --formats ply,stream --brick 16";
    const auto t0 = std::chrono::steady_clock::now();
    REQUIRE(sh("MESHLESS batch " + arch.string() + " -o " + (d / "clean").string() + args, d).code == 0);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto clean = snapshot(d / "clean");
    REQUIRE(clean.size() == 3 * 14);

    // kills spread over the run: early (converting), middle, late (point sets)
    int interrupted = 0;
    for (double fraction : {0.1, 0.3, 0.5}) {
        const std::string delay = std::to_string(fraction * seconds);
        INFO("killed after " << delay << " s of " << seconds);
        const fs::path out = d / ("k" + std::to_string(fraction));
        sh("MESHLESS batch " + arch.string() + " -o " + out.string() + args + " > /dev/null & pid=$!; sleep " + delay +
               "; kill -9 $pid; wait $pid; true",
           d);
        // (killed before it made its output folder: the sanitizer build starts slower)
        if (!fs::exists(out) || snapshot(out) != clean) ++interrupted;
        const auto r = sh("MESHLESS batch " + arch.string() + " -o " + out.string() + args, d);
        CHECK(r.code == 0);
        CHECK(snapshot(out) == clean);
        CHECK(!has_temporaries(out));
    }
    CHECK(interrupted > 0);  // at least one kill landed mid-run (otherwise the test proves nothing)
}

TEST_CASE("batch manifest: relative paths, raw options, comments, a missing entry fails alone", "[batch]") {
    TempDir d("batch-manifest");
    const fs::path arch = d / "arch", out = d / "out";
    fs::create_directories(arch / "sub");
    write_volume(arch, AnalyticField::sphere, 20, "sphere");
    write_volume(arch / "sub", AnalyticField::sphere, 20, "", "plain.raw");
    spit(arch / "list.txt",
         "# nightly archive\n"
         "sphere_20x20x20_uint8.raw\n"
         "\n"
         "sub/plain.raw --dims 20,20,20 --type uint8   # no name convention: options\n"
         "gone_8x8x8_uint8.raw\n"
         "sub/plain.raw --bogus 3\n");
    const auto r = sh("MESHLESS batch " + (arch / "list.txt").string() + " -o " + out.string() + " --iso 100.5", d);
    CHECK(r.code == 2);
    CHECK_THAT(row(r.out, "sphere_20x20x20_uint8"), Catch::Contains("done"));
    CHECK_THAT(row(r.out, "plain"), Catch::Contains("done"));
    CHECK_THAT(row(r.out, "gone_8x8x8_uint8"), Catch::Contains("FAILED"));
    CHECK_THAT(row(r.out, "gone_8x8x8_uint8"), Catch::Contains("missing input"));
    CHECK_THAT(r.err, Catch::Contains("gone_8x8x8_uint8.raw: missing input"));
    CHECK_THAT(r.err, Catch::Contains("list.txt:6: unknown option '--bogus'"));
    CHECK_THAT(r.out, Catch::Contains("4 volume(s): 2 done, 0 up to date, 2 failed"));
    // same voxels through the options as through the name convention: the same store
    CHECK(slurp(out / "plain.mlb") == slurp(out / "sphere_20x20x20_uint8.mlb"));
    CHECK_THAT(slurp(out / "plain.mlb.meta"), Catch::Contains("param.raw=dims=20,20,20 type=uint8"));
}

TEST_CASE("batch manifest: a header naming a file out of the manifest's folder is refused alone, the others done",
          "[batch]") {
    TempDir d("batch-escape");
    const fs::path arch = d / "arch", elsewhere = d / "elsewhere", out = d / "out";
    fs::create_directories(arch / "sub");
    fs::create_directories(elsewhere);
    write_volume(arch, AnalyticField::sphere, 20, "sphere");
    write_volume(elsewhere, AnalyticField::sphere, 20, "", "outside.raw");
    // the payload a header may name: beside it, in a subfolder, but not above the manifest's folder
    write_volume(arch / "sub", AnalyticField::sphere, 20, "", "inside.raw");
    const std::string fields = "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 20 20 20\nencoding: raw\n";
    spit(arch / "inside.nhdr", fields + "data file: sub/inside.raw\n\n");
    spit(arch / "up.nhdr", fields + "data file: ../elsewhere/outside.raw\n\n");
    spit(arch / "abs.nhdr", fields + "data file: " + (elsewhere / "outside.raw").string() + "\n\n");
    spit(arch / "list.txt", "sphere_20x20x20_uint8.raw\ninside.nhdr\nup.nhdr\nabs.nhdr\n");
    const auto r = sh("MESHLESS batch " + (arch / "list.txt").string() + " -o " + out.string() + " --iso 100.5", d);
    INFO(r.out << r.err);
    CHECK(r.code == 2);
    CHECK_THAT(row(r.out, "sphere_20x20x20_uint8"), Catch::Contains("done"));
    CHECK_THAT(row(r.out, "inside"), Catch::Contains("done"));
    for (const char* name : {"up", "abs"}) {
        CHECK_THAT(row(r.out, name), Catch::Contains("REFUSED"));
        CHECK_THAT(row(r.out, name), Catch::Contains("outside.raw"));
        CHECK(!fs::exists(out / (std::string(name) + ".mlb")));
        CHECK(!fs::exists(out / (std::string(name) + "_iso100.5.ply")));
    }
    CHECK_THAT(r.out, Catch::Contains("4 volume(s): 2 done, 0 up to date, 0 failed, 2 refused"));
    // the same header given to another command is followed, as NRRD allows
    CHECK(sh("MESHLESS isosurface " + (arch / "up.nhdr").string() + " --iso 100.5 -o " + (d / "up.ply").string(), d).code == 0);
}

TEST_CASE("batch over the file size limit: exit 2, a clear message, no partial output, rerun finishes", "[batch]") {
    TempDir d("batch-full");
    const fs::path arch = d / "arch";
    fs::create_directories(arch);
    write_volume(arch, AnalyticField::sphere, 16, "a_small");
    write_volume(arch, AnalyticField::gyroid, 48, "b_big");
    write_volume(arch, AnalyticField::torus, 20, "c_mid");
    const std::string args = " --iso 100.5 --iso 150 --stream";
    REQUIRE(sh("MESHLESS batch " + arch.string() + " -o " + (d / "clean").string() + args, d).code == 0);
    const auto clean = snapshot(d / "clean");

    const fs::path out = d / "out";
    auto r = sh("trap \"\" XFSZ; ulimit -f 24; MESHLESS batch " + arch.string() + " -o " + out.string() + args, d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("File too large"));
    CHECK_THAT(r.err, Catch::Contains("file size limit"));
    CHECK_THAT(row(r.out, "b_big_48x48x48_uint8"), Catch::Contains("FAILED"));
    CHECK(!has_temporaries(out));
    check_outputs_recorded(out);
    for (const auto& [name, bytes] : snapshot(out)) {
        INFO(name);
        CHECK(bytes == clean.at(name));
    }
    CHECK(snapshot(out).size() < clean.size());

    r = sh("MESHLESS batch " + arch.string() + " -o " + out.string() + args, d);
    CHECK(r.code == 0);
    CHECK(snapshot(out) == clean);
}

TEST_CASE("batch usage errors", "[batch]") {
    TempDir d("batch-usage");
    const std::string vol = write_volume(d.path, AnalyticField::sphere, 8, "s");
    CHECK(sh("MESHLESS batch " + d.path.string() + " --iso 1", d).code == 1);                    // no -o
    CHECK(sh("MESHLESS batch " + vol + " -o " + (d / "o").string(), d).code == 1);               // a volume, not an archive
    CHECK(sh("MESHLESS batch " + (d / "nope").string() + " -o " + (d / "o").string(), d).code == 2);
    CHECK(sh("MESHLESS batch " + d.path.string() + " -o " + (d / "o").string() + " --iso 1 --iso 1.0", d).code == 1);
    CHECK(sh("MESHLESS batch " + d.path.string() + " -o " + (d / "o").string() + " --formats obj", d).code == 1);
    // a second run on the same output folder is refused while the first holds its lock
    fs::create_directories(d / "o");
    auto r = sh("flock " + (d / "o" / ".meshless-batch.lock").string() + " MESHLESS batch " + d.path.string() + " -o " +
                    (d / "o").string(),
                d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("another meshless batch is writing to this folder"));
    r = sh("MESHLESS batch --help", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("ARCHIVE_DIR|MANIFEST"));
}

TEST_CASE("batch and demo say why they cannot make their output folder", "[batch]") {
    TempDir d("batch-outdir");
    spit(d / "taken", "a file");
    std::filesystem::create_directories(d / "arch");
    for (const std::string& cmd : {"MESHLESS batch " + (d / "arch").string() + " --iso 1 -o " + (d / "taken").string(),
                                  "MESHLESS demo -o " + (d / "taken").string()}) {
        INFO(cmd);
        const auto r = sh(cmd, d);
        CHECK(r.code == 2);
        CHECK_THAT(r.err, Catch::Contains((d / "taken").string() + ": cannot create output folder: a file of that name exists"));
    }
}

TEST_CASE("batch --shard K/N: every volume in one shard, largest first, shards side by side give one run's outputs", "[batch]") {
    TempDir d("batch-shard");
    const fs::path arch = d / "arch";
    fs::create_directories(arch);
    // sizes 24^3 > 20^3 > 16^3 > 12^3 > 8^3: dealt round-robin to 2 shards, shard 1 gets the 24^3, 16^3, 8^3
    int n_of[] = {16, 24, 8, 20, 12};
    const char* stem[] = {"a", "b", "c", "d", "e"};
    for (int i = 0; i < 5; ++i) write_volume(arch, AnalyticField::sphere, n_of[i], stem[i]);
    const std::string A = arch.string(), D = d.path.string();
    auto whole = sh("MESHLESS batch " + A + " -o " + D + "/whole --iso 100.5", d);
    REQUIRE(whole.code == 0);
    // the two shards at once into one folder
    auto r = sh("( MESHLESS batch " + A + " -o " + D + "/sharded --iso 100.5 --shard 1/2 > " + D + "/s1.txt & "
                "MESHLESS batch " + A + " -o " + D + "/sharded --iso 100.5 --shard 2/2 > " + D + "/s2.txt; "
                "s2=$?; wait $!; s1=$?; exit $((s1 | s2)) )", d);
    INFO(r.err);
    REQUIRE(r.code == 0);
    const std::string s1 = slurp(d / "s1.txt"), s2 = slurp(d / "s2.txt");
    CHECK_THAT(s1, Catch::Contains("shard 1/2: 3 of the archive's 5 volume(s)"));
    CHECK_THAT(s2, Catch::Contains("shard 2/2: 2 of the archive's 5 volume(s)"));
    for (const char* v : {"b_24x24x24_uint8", "a_16x16x16_uint8", "c_8x8x8_uint8"}) {
        CHECK_FALSE(row(s1, v).empty());
        CHECK(row(s2, v).empty());
    }
    for (const char* v : {"d_20x20x20_uint8", "e_12x12x12_uint8"}) {
        CHECK_FALSE(row(s2, v).empty());
        CHECK(row(s1, v).empty());
    }
    CHECK(snapshot(d / "sharded") == snapshot(d / "whole"));  // outputs and sidecars: one run's
    // a whole-archive run over the shards' outputs finds everything up to date
    r = sh("MESHLESS batch " + A + " -o " + D + "/sharded --iso 100.5", d);
    REQUIRE(r.code == 0);
    CHECK_THAT(r.out, Catch::Contains("5 volume(s): 0 done, 5 up to date"));
    // a shard already running, and a shard beside a whole-archive run, are refused (exit 2, nothing written)
    r = sh("flock " + D + "/sharded/.meshless-batch-shard-1-of-2.lock MESHLESS batch " + A + " -o " + D +
               "/sharded --iso 60.5 --shard 1/2",
           d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("shard 1/2 is already running into this folder"));
    r = sh("flock " + D + "/sharded/.meshless-batch.lock MESHLESS batch " + A + " -o " + D + "/sharded --iso 60.5 --shard 2/2", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("a meshless batch of the whole archive is writing to this folder"));
    CHECK(fs::exists(d / "whole" / "b_24x24x24_uint8_iso100.5.ply"));
    CHECK_FALSE(fs::exists(d / "sharded" / "b_24x24x24_uint8_iso60.5.ply"));
    for (const char* bad : {"0/2", "3/2", "1", "1/0", "a/b"}) {
        r = sh(std::string("MESHLESS batch ") + A + " -o " + D + "/x --iso 100.5 --shard " + bad, d);
        CHECK(r.code == 1);
    }
}
