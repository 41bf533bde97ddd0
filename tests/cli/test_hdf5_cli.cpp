// HDF5 datasets through the volume commands (formats/hdf5_volume.hpp): the tooth CT written as HDF5
// datasets (tests/hdf5_test_data.hpp: contiguous uint8, chunked deflate+shuffle uint8, chunked
// big-endian float64 in a group beside another volume) gives the raw file's isosurface points, mc
// mesh and convert brick store byte for byte (less the PLY comment naming the input); info lists
// the file's volumes; the dataset is chosen by FILE:/PATH or --array; a file of several volumes
// without a choice, and each defect class, are refused with one line naming the file and exit 2.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli/cli_harness.hpp"
#include "formats/ply_points.hpp"
#include "test_paths.hpp"

#if MESHLESS_HDF5
#include "hdf5_test_data.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

const std::string& kTooth = kToothRaw;

}  // namespace

TEST_CASE("hdf5 datasets: isosurface, mc and convert give the raw file's bytes, info lists the volumes", "[cli][hdf5]") {
    if (!std::filesystem::exists(kTooth)) {
        WARN("skipped: " << kTooth << " is absent");
        return;
    }
    TempDir d("hdf5-cli");
    const std::string D = d.path.string() + "/";
    const std::string bytes = slurp(kTooth);
    Hdf5WriteOptions plain;
    for (char c : bytes) plain.values.push_back(static_cast<unsigned char>(c));
    write_hdf5_volume(D + "plain.h5", "/ct", 103, 94, 161, plain);
    Hdf5WriteOptions chunked = plain;
    chunked.chunk = {16, 40, 48};  // none divides 161 x 94 x 103
    chunked.deflate = 4;
    chunked.shuffle = true;
    write_hdf5_volume(D + "chunked.h5", "/ct", 103, 94, 161, chunked);
    Hdf5WriteOptions wide = plain;
    wide.file_type = H5T_IEEE_F64BE;
    wide.chunk = {7, 94, 103};
    write_hdf5_volume(D + "two.h5", "/scans/tooth", 103, 94, 161, wide);
    write_hdf5_volume(D + "two.h5", "/other", 103, 94, 161, plain, /*append=*/true);
    const std::vector<std::string> inputs = {D + "plain.h5", D + "chunked.h5:/ct", D + "two.h5:/scans/tooth", D + "two.h5 --array other"};
    struct Cmd {
        std::string args, out;
    };
    const Cmd cmds[] = {
        {"isosurface IN --iso 100.5 -o OUT", "i.ply"},
        {"isosurface IN --iso 60.5 --threads 2 -o OUT", "t.ply"},
        {"mc IN --iso 100.5 -o OUT", "m.ply"},
        {"convert IN -o OUT", "c.mlb"},
    };
    for (const Cmd& c : cmds) {
        std::string line = "MESHLESS " + c.args;
        line.replace(line.find("IN"), 2, kTooth);
        line.replace(line.find("OUT"), 3, D + "raw" + c.out);
        const RunResult r = sh(line, d);
        INFO(line << ": " << r.err);
        REQUIRE(r.code == 0);
        const std::string want = slurp(D + "raw" + c.out);
        REQUIRE(!want.empty());
        int n = 0;
        for (const std::string& in : inputs) {
            std::string hl = "MESHLESS " + c.args;
            hl.replace(hl.find("IN"), 2, in);
            const std::string out = D + std::to_string(n++) + c.out;
            hl.replace(hl.find("OUT"), 3, out);
            const RunResult h = sh(hl, d);
            INFO(hl << ": " << h.err);
            REQUIRE(h.code == 0);
            CHECK(h.err.find("warning") == std::string::npos);
            const std::string got = slurp(out);
            if (c.out != "c.mlb") CHECK(without_tooth_names(got) == without_tooth_names(want));
            else if (in.find("two.h5:/scans") == std::string::npos) CHECK(got == want);  // float64 is stored as float32
        }
    }
    const RunResult info = sh("MESHLESS info " + D + "two.h5:/scans/tooth", d);
    INFO(info.err);
    REQUIRE(info.code == 0);
    CHECK(info.out.find("two.h5:/scans/tooth: hdf5 volume") != std::string::npos);
    CHECK(info.out.find("/other: uint8 little-endian, 1 component") != std::string::npos);
    CHECK(info.out.find("/scans/tooth: float64 big-endian, 1 component; read") != std::string::npos);
    CHECK(info.out.find("encoding: HDF5 dataset /scans/tooth, shape (161, 94, 103) float64 big-endian, chunked (7, 94, 103)") !=
          std::string::npos);
    // several volumes and no choice: exit 2 naming them; a choice that disagrees: exit 1
    const RunResult many = sh("MESHLESS isosurface " + D + "two.h5 --iso 100.5 -o " + D + "w.ply", d);
    CHECK(many.code == 2);
    CHECK(many.err.find("two.h5: holds 2 volumes (/other, /scans/tooth): name one as") != std::string::npos);
    const RunResult both = sh("MESHLESS isosurface " + D + "two.h5:/other --array /scans/tooth --iso 100.5 -o " + D + "w.ply", d);
    CHECK(both.code == 1);
    CHECK(both.err.find("names the dataset /other, --array another (/scans/tooth)") != std::string::npos);
    // --spacing where the file gives none
    const RunResult sp = sh("MESHLESS info " + D + "plain.h5 --spacing 0.5,1,2", d);
    CHECK(sp.out.find("spacing: 0.5 1 2") != std::string::npos);
}

TEST_CASE("hdf5 datasets: each defect class is refused with one line naming the file and exit 2", "[cli][hdf5]") {
    TempDir d("hdf5-cli-bad");
    const std::string D = d.path.string() + "/";
    std::ofstream(D + "text.h5") << "not HDF5\n";
    write_hdf5_volume(D + "ok.h5", "/v", 8, 8, 8);
    std::ofstream(D + "outside.raw") << "12345678";
    write_hdf5_external_data(D + "ext.h5", D + "outside.raw");
    write_hdf5_external_link(D + "link.h5", D + "ok.h5");
    write_hdf5_unavailable_filter(D + "blosc.h5");
    write_hdf5_strings(D + "strings.h5");
    Hdf5WriteOptions far;
    far.attributes = {{"spacing", {1e308, 1, 1}}};
    write_hdf5_volume(D + "far.h5", "/v", 8, 8, 8, far);
    struct Bad {
        std::string input, message;
    };
    const Bad bad[] = {
        {"text.h5", "text.h5: libhdf5 cannot open it (libhdf5: "},
        {"ok.h5:/w", "ok.h5:/w: no object named '/w' in the file"},
        {"ext.h5:/v", "ext.h5:/v: its raw data are in 1 external file(s): refused"},
        {"link.h5:/v", "link.h5:/v: '/v' is an external or user-defined link to another file: refused"},
        {"blosc.h5:/v", "blosc.h5:/v: compressed with filter 32001"},
        {"strings.h5:/v", "strings.h5:/v: type string is not read"},
        {"far.h5", "far.h5:/v"},
    };
    for (const Bad& b : bad) {
        for (const char* cmd : {"info IN", "isosurface IN --iso 1.5 -o OUT", "convert IN -o OUT"}) {
            std::string line = std::string("MESHLESS ") + cmd;
            line.replace(line.find("IN"), 2, D + b.input);
            if (line.find("OUT") != std::string::npos) line.replace(line.find("OUT"), 3, D + "out" + (line.find("convert") != std::string::npos ? ".mlb" : ".ply"));
            const RunResult r = sh(line, d);
            INFO(line << ": " << r.err);
            CHECK(r.code == 2);
            CHECK(r.err.find(b.message) != std::string::npos);
            CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
            CHECK_FALSE(std::filesystem::exists(D + "out.ply"));
            CHECK_FALSE(std::filesystem::exists(D + "out.mlb"));
        }
    }
}

TEST_CASE("hdf5 datasets: isosurface FILE.h5:/ct --color-by /other colours by another dataset of the file", "[cli][hdf5]") {
    TempDir d("hdf5-colorby");
    const std::string D = d.path.string() + "/";
    write_hdf5_volume(D + "two.h5", "/ct", 24, 20, 16);  // the oracle's values, (i + 5j + 20k) % 113
    Hdf5WriteOptions height;
    for (int k = 0; k < 16; ++k)
        for (int j = 0; j < 20; ++j)
            for (int i = 0; i < 24; ++i) height.values.push_back(k * 10);
    write_hdf5_volume(D + "two.h5", "/height", 24, 20, 16, height, /*append=*/true);
    for (const std::string& in : {D + "two.h5:/ct", D + "two.h5 --array /ct"}) {
        INFO(in);
        const RunResult r = sh("MESHLESS isosurface " + in + " --iso 40.5 --color-by /height -o " + D + "c.ply", d);
        INFO(r.err);
        REQUIRE(r.code == 0);
        const PlyPoints p = read_ply_points(D + "c.ply");
        REQUIRE(p.points.size() > 10);
        // the height array is 10 z, sampled clamped into the grid's box (points may lie a little outside it)
        for (const PointRecord& q : p.points) CHECK(q.value == Approx(10 * std::clamp(static_cast<double>(q.pos[2]), 0.0, 15.0)).margin(1e-3));
        CHECK(slurp(D + "c.ply").find("comment value_name /height\n") != std::string::npos);
    }
}

#else

TEST_CASE("hdf5 datasets: a build without libhdf5 says so in one line", "[cli][hdf5]") {
    meshless::test::TempDir d("hdf5-cli-none");
    const std::string f = d.path.string() + "/x.h5";
    std::ofstream(f) << "\x89HDF\r\n\x1a\n";
    const meshless::test::RunResult r = meshless::test::sh("MESHLESS info " + f, d);
    CHECK(r.code == 2);
    CHECK(r.err.find("this build has no HDF5 reader") != std::string::npos);
}

#endif
