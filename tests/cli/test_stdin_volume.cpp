// `-` as a volume input (formats/stdin_spool.hpp): raw with --dims/--type and NRRD with attached data
// piped in give the same points as the file; errors name "- (stdin)", never the spool's
// /proc path; nothing is left in $TMPDIR.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <string>

#include "cli/cli_harness.hpp"
#include "formats/ply_points.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {
/// A 24^3 uint8 ball (value 200 - 10 r about the centre).
std::string ball_bytes() {
    const int n = 24;
    std::string b(static_cast<std::size_t>(n) * n * n, '\0');
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double r = std::sqrt((i - 11.5) * (i - 11.5) + (j - 11.0) * (j - 11.0) + (k - 12.0) * (k - 12.0));
                b[static_cast<std::size_t>(i + n * (j + n * k))] = static_cast<char>(static_cast<unsigned char>(std::max(0.0, 200.0 - 10.0 * r)));
            }
    return b;
}

bool same_points(const std::string& a, const std::string& b) {
    const PlyPoints pa = read_ply_points(a), pb = read_ply_points(b);
    if (pa.points.size() != pb.points.size() || pa.points.empty()) return false;
    for (std::size_t i = 0; i < pa.points.size(); ++i)
        for (int c = 0; c < 3; ++c)
            if (pa.points[i].pos[c] != pb.points[i].pos[c]) return false;
    return true;
}
}  // namespace

TEST_CASE("volumes from standard input: raw and NRRD piped in, errors name stdin, no temporaries", "[cli][stdin]") {
    TempDir d("stdin-volume");
    const std::string D = d.path.string() + "/";
    std::filesystem::create_directory(d / "tmp");
    const std::string env = "TMPDIR=" + D + "tmp ";
    spit(d / "ball_24x24x24_uint8.raw", ball_bytes());
    spit(d / "ball.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 24 24 24\nencoding: raw\n\n" + ball_bytes());
    REQUIRE(sh("MESHLESS isosurface " + D + "ball_24x24x24_uint8.raw --iso 100.5 -o " + D + "file.ply", d).code == 0);
    for (const char* threads : {"1", "2"}) {
        INFO("threads " << threads);
        REQUIRE(sh(env + "MESHLESS isosurface - --dims 24,24,24 --type uint8 --iso 100.5 --threads " + threads + " -o " + D +
                       "raw.ply < " + D + "ball_24x24x24_uint8.raw", d).code == 0);
        CHECK(same_points(D + "file.ply", D + "raw.ply"));
        REQUIRE(sh(env + "MESHLESS isosurface - --iso 100.5 --threads " + threads + " -o " + D + "nrrd.ply < " + D + "ball.nrrd", d).code == 0);
        CHECK(same_points(D + "file.ply", D + "nrrd.ply"));
    }
    REQUIRE(sh(env + "cat " + D + "ball.nrrd | MESHLESS mc - --iso 100.5 -o " + D + "mesh.ply", d).code == 0);
    if (have_shared_data()) {  // a gzipped NIfTI piped in: recognised by its gzip magic (no .gz name on stdin)
        const std::string mni = (shared_data() / "mni152_brain" / "avg152T1_RL_nifti.nii.gz").string();
        REQUIRE(sh("MESHLESS isosurface " + mni + " --iso 80.5 -o " + D + "mni_file.ply", d).code == 0);
        const auto g = sh(env + "cat " + mni + " | MESHLESS isosurface - --iso 80.5 -o " + D + "mni_stdin.ply", d);
        INFO(g.err);
        REQUIRE(g.code == 0);
        CHECK(same_points(D + "mni_file.ply", D + "mni_stdin.ply"));
    }
    REQUIRE(sh(env + "MESHLESS sample - --count 50 -o " + D + "s.csv < " + D + "ball.nrrd", d).code == 0);
    // not a volume: exit 2, named as stdin
    spit(d / "junk.bin", std::string(100, 'x'));
    const auto r = sh(env + "MESHLESS isosurface - --iso 1 -o " + D + "j.ply < " + D + "junk.bin", d);
    CHECK(r.code == 2);
    CHECK_THAT(r.err, Catch::Contains("- (stdin)"));
    CHECK_THAT(r.err, !Catch::Contains("/proc/"));
    CHECK(!std::filesystem::exists(d / "j.ply"));
    // a truncated NRRD payload
    spit(d / "short.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 24 24 24\nencoding: raw\n\n" + std::string(100, 'a'));
    const auto s = sh(env + "MESHLESS isosurface - --iso 1 -o " + D + "k.ply < " + D + "short.nrrd", d);
    CHECK(s.code == 2);
    CHECK_THAT(s.err, Catch::Contains("- (stdin)"));
    // a gzip payload cut short: found while the slabs stream, long after the volume was opened
    spit(d / "gz.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 24 24 24\nencoding: gzip\n\n");
    REQUIRE(sh("gzip -c " + D + "ball_24x24x24_uint8.raw | head -c 400 >> " + D + "gz.nrrd", d).code == 0);
    const auto g = sh(env + "MESHLESS isosurface - --iso 100.5 -o " + D + "g.ply < " + D + "gz.nrrd", d);
    CHECK(g.code == 2);
    CHECK_THAT(g.err, Catch::Contains("- (stdin)"));
    CHECK_THAT(g.err, !Catch::Contains("/proc/"));
    CHECK(!std::filesystem::exists(d / "g.ply"));
    // a header naming a separate data file cannot find it from stdin: said so, not a made-up path
    for (const std::string name : {"v.raw", "3d.raw", "4d.raw"}) {  // (a name that begins like the spool's fd)
        spit(d / "v.mhd", "ObjectType = Image\nNDims = 3\nDimSize = 24 24 24\nElementType = MET_UCHAR\nElementDataFile = " + name + "\n");
        const auto m = sh(env + "MESHLESS isosurface - --iso 1 -o " + D + "m.ply < " + D + "v.mhd", d);
        CHECK(m.code == 2);
        CHECK_THAT(m.err, Catch::Contains("- (stdin): the header names a separate data file '" + name + "'"));
        CHECK_THAT(m.err, !Catch::Contains("/proc/"));
    }
    CHECK(std::filesystem::is_empty(d / "tmp"));
}
