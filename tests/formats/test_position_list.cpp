// The positions of `probe --at-file` (formats/position_list.hpp): what a good list holds, and one
// must-fail case per defect class, each a one-line error naming the file (and line).
#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include "error_of.hpp"
#include "formats/position_list.hpp"
#include "test_paths.hpp"

using namespace meshless;
using meshless::test::TempDir;

namespace {
std::string write(const TempDir& d, const std::string& name, const std::string& text) {
    const std::string p = (d / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
}
std::string error_of(const std::string& path) {
    return test::error_of<FormatError, IoError>([&] { read_positions(path); });
}
}  // namespace

TEST_CASE("position lists: a header, comments, any separator, extra columns ignored", "[formats][positions]") {
    TempDir d("positions");
    const auto p = read_positions(write(d, "a.csv", "x,y,z\n# probes\n\n0,0,0\n1.5;2\t3\n-4 5e-3 6 extra\n"));
    REQUIRE(p.size() == 3);
    CHECK(p[1].x == 1.5);
    CHECK(p[1].z == 3);
    CHECK(p[2].y == 5e-3);
}

TEST_CASE("position lists: every defect class is refused in one line naming the file", "[formats][positions]") {
    TempDir d("positions-bad");
    // a line without three numbers (the first line may be a header, no later one)
    CHECK_THAT(error_of(write(d, "short.csv", "1,2\n")), Catch::Contains("short.csv:1: expected x,y,z, got '1 2'"));
    CHECK_THAT(error_of(write(d, "twohead.csv", "a,b,c\nd,e,f\n")), Catch::Contains("twohead.csv:2: expected x,y,z"));
    // numbers out of the double range are not positions (the stream refuses them as it parses)
    CHECK_THAT(error_of(write(d, "huge.csv", "1,2,1e999\n")), Catch::Contains("huge.csv:1: expected x,y,z"));
    // nothing to probe
    CHECK_THAT(error_of(write(d, "empty.csv", "# only a comment\n\n")), Catch::Contains("empty.csv: no positions"));
    CHECK_THAT(error_of(write(d, "header.csv", "x,y,z\n")), Catch::Contains("header.csv: no positions"));
    // bytes quoted from the file are escaped
    const std::string e = error_of(write(d, "esc.csv", std::string("1,2,\x1b[31m\n")));
    CHECK(e.find('\x1b') == std::string::npos);
    // not a readable file
    CHECK_THAT(error_of((d / "missing.csv").string()), Catch::Contains("missing.csv"));
    CHECK_THAT(error_of(d.path.string()), Catch::Contains("is a directory"));
}
