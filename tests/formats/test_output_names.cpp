// formats/output_names.hpp and formats/input_kind.hpp: outputs are chosen by extension (any case;
// streams pass; the message names the option, the path and what the output is, exit code 1 as
// InvalidArgument), stream outputs refuse the names of other formats, and the positionals of an
// isosurface command name blocks, scattered points or a volume as the files say.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "formats/binary_stream_output.hpp"
#include "formats/input_kind.hpp"
#include "formats/output_names.hpp"
#include "kernels/errors.hpp"
#include "tests/error_of.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

TEST_CASE("output names: the extension decides, in any case", "[formats]") {
    CHECK(require_output_extension("a/pic.PNG", ".png", "--png", "a PNG image") == "a/pic.PNG");
    CHECK_THROWS_AS(require_output_extension("pic.ppm", ".png", "--png", "a PNG image"), InvalidArgument);
    CHECK(error_of<InvalidArgument>([] { require_output_extension("t.mlh.bak", ".mlh", "-o", "a cluster tree", false); }) ==
          "-o 't.mlh.bak': this output is a cluster tree, written to a .mlh file (outputs are chosen by extension)");
    CHECK(error_of<InvalidArgument>([] { require_output_extension("x.txt", ".csv", "-o", "CSV"); }) ==
          "-o 'x.txt': this output is CSV, written to a .csv file (outputs are chosen by extension; '-' for stdout)");
    CHECK_NOTHROW(require_point_set_output("lod.VTP", "a level of detail"));
    CHECK_THROWS_AS(require_point_set_output("lod.nrrd", "a level of detail"), InvalidArgument);
}

TEST_CASE("output names: the geometry format from the name or --format", "[formats]") {
    CHECK(geometry_output_format("m.Vtp", std::nullopt, "a mesh") == GeometryFormat::vtp);
    CHECK(geometry_output_format("m.out", std::string("vtp"), "a mesh") == GeometryFormat::vtp);
    CHECK(error_of<InvalidArgument>([] { geometry_output_format("m.ply", std::string("vtp"), "a mesh"); }) ==
          "-o 'm.ply': the name says ply but --format says vtp");
    CHECK(error_of<InvalidArgument>([] { geometry_output_format("m.ply", std::string("obj"), "a mesh"); }) == "--format: expected ply or vtp, got 'obj'");
    CHECK_THROWS_AS(geometry_output_format("m.out", std::nullopt, "a mesh"), InvalidArgument);
}

TEST_CASE("output names: a binary stream refuses the names of other formats", "[formats]") {
    for (const char* name : {"s.ply", "dir.d/s.PNG", "s.csv", "s.mlb"})
        CHECK_THROWS_AS(check_stream_output_name(name, "a sample stream"), InvalidArgument);
    for (const char* name : {"s.mlp", "s.mls", "dir.ply/stream", ".ply", "-"}) CHECK_NOTHROW(check_stream_output_name(name, "a sample stream"));
    TempDir dir("output-names");
    CHECK_THROWS_AS(BinaryStreamOutput((dir / "s.ply").string(), "a seed stream"), InvalidArgument);
    BinaryStreamOutput out((dir / "s.mlp").string(), "a seed stream");
    std::fputs("x", out.f);
    out.commit();
    CHECK(std::filesystem::file_size(dir / "s.mlp") == 1);
}

TEST_CASE("input kind: blocks, scattered points or a volume, as the files say", "[formats]") {
    TempDir dir("input-kind");
    const std::string csv = (dir / "pts.csv").string(), raw = (dir / "vol_4x4x4_uint8.raw").string(),
                      records = (dir / "records.raw").string();
    std::ofstream(csv) << "x,y,z,v\n0,0,0,1\n1,0,0,2\n0,1,0,3\n0,0,1,4\n";
    std::ofstream(raw) << std::string(64, '\1');
    std::ofstream(records) << std::string(4 * 4 * 8, '\0');  // 8 float32 x,y,z,v records
    CHECK(names_scattered_points({csv}, false));
    CHECK_FALSE(names_blocks({csv}));
    CHECK_FALSE(names_scattered_points({raw}, false));  // the name convention: a volume
    CHECK_FALSE(names_blocks({raw}));
    CHECK(names_blocks({csv, csv}));  // several inputs, the first not a volume: pieces of blocks
    CHECK_FALSE(names_blocks({raw, csv}));  // the volume command reports the extra argument
    CHECK_FALSE(names_scattered_points({records}, true));  // --dims: a .raw is a volume
    CHECK_FALSE(names_scattered_points({}, false));
}
