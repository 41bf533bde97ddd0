// DICOM series through the meshless binary: the isosurface of a CT series (shuffled file names,
// per-slice rescale) equals byte for byte the isosurface of the same volume as an NRRD, directly and
// through `convert` (streamed slice by slice, against the NRRD's store); `info` describes it; a folder of two series is
// refused listing both and --series picks each; every defect exits 2 with one line, nothing written.
// The series are written at test time with pydicom (tests/dicom_test_data.hpp).
#include <catch2/catch.hpp>
#include <algorithm>
#include <filesystem>
#include <string>

#include "cli/cli_harness.hpp"
#include "dicom_test_data.hpp"

namespace fs = std::filesystem;
using namespace meshless::test;
using Catch::Matchers::Contains;

#if MESHLESS_DICOM

TEST_CASE("dicom cli: isosurface, convert and info of a CT series equal the NRRD's bytes", "[cli][dicom]") {
    if (!have_shared_data()) {
        WARN("shared data absent: skipping (the series is made from vtk_headsq/quarter)");
        return;
    }
    TempDir d("dicom-cli-ct");
    const auto ct = make_dicom_case("ct", d);
    if (!ct) return;
    // the NRRD under the series' name in another folder: the PLY's `source` comment is the same too
    fs::create_directories(d / "nrrd");
    fs::copy_file(ct->string() + ".nrrd", d / "nrrd" / "ct");
    const std::string s = ct->string(), n = (d / "nrrd" / "ct").string();
    const std::string o = d.path.string();
    RunResult r = sh("MESHLESS isosurface " + s + " --iso 1000.5 -o " + o + "/dicom.ply && MESHLESS isosurface " + n +
                         " --iso 1000.5 -o " + o + "/nrrd.ply && cmp " + o + "/dicom.ply " + o + "/nrrd.ply",
                     d);
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(fs::file_size(d / "dicom.ply") > 100000);
    // convert streams the series slice by slice: the store's isosurface is the NRRD store's
    r = sh("mkdir -p " + o + "/a " + o + "/b && MESHLESS convert " + s + " -o " + o + "/a/ct.mlb && MESHLESS convert " + n + " -o " + o +
               "/b/ct.mlb && MESHLESS isosurface " + o + "/a/ct.mlb --iso 1000.5 -o " + o + "/a.ply && MESHLESS isosurface " + o +
               "/b/ct.mlb --iso 1000.5 -o " + o + "/b.ply && cmp " + o + "/a.ply " + o + "/b.ply",
           d);
    INFO(r.err);
    CHECK(r.code == 0);
    r = sh("MESHLESS info " + s, d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Contains("dicom volume") && Contains("64 x 60 x 279") && Contains("float32") &&
                          Contains("series: 1 of 1: ") && Contains("CT head (quarter)") && Contains("patient axes: x L, y P, z S") &&
                          Contains("length unit: mm") && Contains("value unit: HU"));  // (a CT's values: Hounsfield units)
    CHECK_THAT(slurp(d / "dicom.ply"), Contains("comment value_unit HU\n") && Contains("comment length_unit mm\n"));
    r = sh("MESHLESS render " + s + " --size 64x64 -o " + o + "/ct.png", d);
    INFO(r.err);
    CHECK(r.code == 0);
}

TEST_CASE("dicom cli: two series are listed and refused, --series picks each by number or UID", "[cli][dicom]") {
    TempDir d("dicom-cli-two");
    const auto t = make_dicom_case("two-series", d);
    if (!t) return;
    const std::string p = t->string(), o = d.path.string();
    RunResult r = sh("MESHLESS isosurface " + p + " --iso 100 -o " + o + "/x.ply", d);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_THAT(r.err, Contains("holds 2 series") && Contains("'first'") && Contains("'second'") && Contains("--series"));
    CHECK_FALSE(fs::exists(d / "x.ply"));
    // info lists them (exit 0); with --series it describes one and names the others
    r = sh("MESHLESS info " + p, d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Contains(": DICOM, 2 series") && Contains("  1) 1.2.826.0.1.3680043.8.498.100 'first', 6 slices, 32 x 30") &&
                          Contains("  2) 1.2.826.0.1.3680043.8.498.200 'second', 5 slices, 16 x 16"));
    r = sh("MESHLESS info " + p + " --series 2", d);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Contains("16 x 16 x 5") && Contains("series: 2 of 2: 1.2.826.0.1.3680043.8.498.200 'second'"));
    r = sh("MESHLESS isosurface " + p + " --series 1.2.826.0.1.3680043.8.498.100 --iso 100 -o " + o + "/first.ply", d);
    INFO(r.err);
    CHECK(r.code == 0);
    r = sh("MESHLESS mc " + p + " --series 1 --iso 100 -o " + o + "/first_mc.ply", d);
    CHECK(r.code == 0);
    r = sh("MESHLESS sample " + p + " --series 2 --count 100 -o " + o + "/second.csv", d);
    INFO(r.err);
    CHECK(r.code == 0);
    r = sh("MESHLESS hierarchy " + p + " --series 2 -o " + o + "/second.mlh", d);
    INFO(r.err);
    CHECK(r.code == 0);
    // batch: each series of the folder once (named after its first file), not once per slice file
    r = sh("MESHLESS batch " + p + " -o " + o + "/nightly", d);
    INFO(r.err);
    CHECK(r.code == 0);
    CHECK(fs::exists(d / "nightly" / "a0.mlb"));
    CHECK(fs::exists(d / "nightly" / "b0.mlb"));
    std::size_t stores = 0;
    for (const auto& e : fs::directory_iterator(d / "nightly")) stores += e.path().extension() == ".mlb";
    CHECK(stores == 2);
    r = sh("MESHLESS convert " + p + " --series 7 -o " + o + "/none.mlb", d);
    CHECK(r.code == 1);
    CHECK_THAT(r.err, Contains("--series 7") && Contains("no such series"));
    CHECK_FALSE(fs::exists(d / "none.mlb"));
}

TEST_CASE("dicom cli: every defect exits 2 with one line naming the folder, nothing written", "[cli][dicom]") {
    TempDir d("dicom-cli-bad");
    const std::pair<const char*, const char*> cases[] = {
        {"tilt", "gantry tilt"},          {"gap", "missing slice"},
        {"duplicate", "duplicated slice"}, {"uneven", "uneven spacing: steps of 1.5, 1.8 mm"},
        {"mixed-sizes", "mixed sizes"},   {"mixed-orientation", "mixed orientations"},
        {"truncated", "slice0005.dcm: malformed DICOM at byte "},   {"no-pixels", "holds no image"},
    };
    for (const auto& [name, message] : cases) {
        const auto p = make_dicom_case(name, d);
        if (!p) return;
        for (const std::string cmd : {"info", "isosurface --iso 100 -o OUT.ply", "convert -o OUT.mlb"}) {
            std::string c = cmd;
            const std::size_t at = c.find("OUT");
            if (at != std::string::npos) c.replace(at, 3, (d / "out").string());
            const std::string verb = c.substr(0, c.find(' '));
            const std::string rest = c.size() > verb.size() ? c.substr(verb.size()) : "";
            const RunResult r = sh("MESHLESS " + verb + " " + p->string() + rest, d);
            INFO(name << ": " << c << ": " << r.err);
            CHECK(r.code == 2);
            CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
            CHECK_THAT(r.err, Contains(p->string()) && Contains(message));  // the folder, or a file in it
            CHECK_FALSE(fs::exists(d / "out.ply"));
            CHECK_FALSE(fs::exists(d / "out.mlb"));
        }
    }
}

#else

TEST_CASE("dicom cli: a build without GDCM says so in one line, exit 2", "[cli][dicom]") {
    TempDir d("dicom-cli-none");
    spit(d / "slice.dcm", std::string(128, '\0') + "DICM" + std::string(64, '\0'));
    const RunResult r = sh("MESHLESS info " + (d / "slice.dcm").string(), d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Contains("this build has no DICOM reader"));
}

#endif
