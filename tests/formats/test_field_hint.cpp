// formats/field_hint: the Hardy c a level of detail carries, written as a provenance line and read
// back from PLY header comments and VTP prolog comments; anything else (CSV, a line in the data,
// after end_header or inside VTKFile, malformed or out-of-range numbers) is no hint.
#include <catch2/catch.hpp>

#include <fstream>
#include <string>

#include "formats/field_hint.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;

TEST_CASE("field hint: the line round-trips and malformed ones are no hint", "[formats]") {
    for (double c : {0.003, 0.025, 1e-9, 100.0, 0.1 + 0.2}) CHECK(parse_field_hint(field_hint_line(c)) == c);
    CHECK(field_hint_line(0.003) == "meshless field: hardy-c-rel 0.003");
    for (const char* bad : {"meshless field: hardy-c-rel", "meshless field: hardy-c-rel x", "meshless field: hardy-c-rel 0",
                            "meshless field: hardy-c-rel -1", "meshless field: hardy-c-rel 101", "meshless field: hardy-c-rel nan",
                            "meshless field: hardy-c-rel 1e999", "meshless field: hardy-c-rel 0.5.5", "hardy-c-rel 0.5", ""})
        CHECK_FALSE(parse_field_hint(bad).has_value());
}

TEST_CASE("field hint: read from a PLY header comment or a VTP prolog comment, nowhere else", "[formats]") {
    TempDir d("field_hint");
    const std::string line = field_hint_line(0.004);
    auto hint = [&](const std::string& name, const std::string& text) {
        std::ofstream(d / name, std::ios::binary) << text;
        return point_file_field_hint((d / name).string());
    };
    CHECK(hint("a.ply", "ply\nformat ascii 1.0\ncomment meshless lod count 5\ncomment " + line +
                            "\nelement vertex 0\nproperty double x\nend_header\n") == 0.004);
    CHECK_FALSE(hint("b.ply", "ply\nformat ascii 1.0\nelement vertex 0\nend_header\ncomment " + line + "\n").has_value());
    CHECK_FALSE(hint("c.ply", "ply\nformat ascii 1.0\nobj_info " + line + "\nend_header\n").has_value());
    CHECK(hint("a.vtp", "<?xml version=\"1.0\"?>\n<!-- " + line + " -->\n<VTKFile type=\"PolyData\"></VTKFile>\n") == 0.004);
    CHECK_FALSE(hint("b.vtp", "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\"><!-- " + line + " --></VTKFile>\n").has_value());
    CHECK_FALSE(hint("c.vtp", "<?xml version=\"1.0\"?>\n<!-- " + line + "\n").has_value());  // unclosed comment
    CHECK_FALSE(hint("a.csv", "# " + line + "\nx,y,z,value\n").has_value());
    CHECK_FALSE(point_file_field_hint((d / "missing.ply").string()).has_value());
    CHECK_FALSE(point_file_field_hint(d.path.string()).has_value());  // a folder
}
