// The length unit of a volume's world coordinates: the names files spell, the brick store's codes,
// NIfTI's xyzt_units, NRRD's space units (all equal and known, else none), and a store's header
// round trip (stores made before the unit was recorded read as none).
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include "formats/length_unit.hpp"
#include "formats/volume_reader.hpp"

using namespace meshless;

TEST_CASE("length units: the names files spell, codes and NIfTI's xyzt_units", "[formats][units]") {
    CHECK(length_unit_from_name("mm") == "mm");
    CHECK(length_unit_from_name(" \"Millimeter\" ") == "mm");
    CHECK(length_unit_from_name("micrometer") == "um");
    CHECK(length_unit_from_name("\xc2\xb5m") == "um");
    CHECK(length_unit_from_name("micron") == "um");
    CHECK(length_unit_from_name("metre") == "m");
    CHECK(length_unit_from_name("nanometer") == "nm");
    CHECK(length_unit_from_name("centimeter") == "cm");
    CHECK(length_unit_from_name("furlong").empty());
    CHECK(length_unit_from_name("").empty());
    for (const char* u : {"m", "mm", "um", "nm", "cm"}) CHECK(length_unit_of_code(length_unit_code(u)) == u);
    CHECK(length_unit_code("") == 0);
    CHECK(length_unit_of_code(0).empty());
    CHECK(length_unit_of_code(99).empty());
    CHECK(nifti_length_unit(10) == "mm");  // NIFTI_UNITS_MM | NIFTI_UNITS_SEC
    CHECK(nifti_length_unit(1) == "m");
    CHECK(nifti_length_unit(3) == "um");
    CHECK(nifti_length_unit(0).empty());
    CHECK(nifti_length_unit(8).empty());  // seconds alone
}

TEST_CASE("length units: NRRD space units all equal and known, else none", "[formats][units]") {
    const auto dir = std::filesystem::temp_directory_path() / "meshless-units-nrrd";
    std::filesystem::create_directories(dir);
    const auto probe = [&](const std::string& lines) {  // a 2x2x2 NRRD with these header lines
        const std::string path = (dir / "v.nrrd").string();
        std::ofstream f(path, std::ios::binary);
        f << "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n" << lines << "\n";
        f.write("\1\2\3\4\5\6\7\10", 8);
        f.close();
        return probe_volume(path);
    };
    const auto nrrd = [&](const std::string&, const std::string& lines) { return probe(lines).length_unit; };
    CHECK(nrrd("a.nrrd", "space units: \"mm\" \"mm\" \"mm\"\n") == "mm");
    CHECK(nrrd("b.nrrd", "space units: \"micron\" \"um\" \"micrometer\"\n") == "um");
    CHECK(nrrd("c.nrrd", "space units: \"mm\" \"mm\" \"cm\"\n").empty());
    CHECK(nrrd("d.nrrd", "space units: \"mm\" \"mm\" \"parsec\"\n").empty());
    CHECK(nrrd("e.nrrd", "space units: \"mm\n").empty());
    CHECK(nrrd("f.nrrd", "").empty());
    CHECK(nrrd("g.nrrd", "space units: mm mm mm\n") == "mm");  // bare words, as some writers spell them
    CHECK(nrrd("h.nrrd", "space units: \"mm\" \"mm\"\n").empty());  // one per axis: three
    CHECK(nrrd("i.nrrd", "space units: \"mm\" \"mm\" \"mm\" \"mm\"\n").empty());
    const auto value_unit = [&](const std::string& lines) { return probe(lines).value_unit; };
    CHECK(value_unit("sample units: \"kg/m^3\"\n") == "kg/m^3");
    CHECK(value_unit("sample units: HU\n") == "HU");
    CHECK(value_unit("sample units: \"Hounsfield units\"\n") == "Hounsfield units");  // 16 bytes: a store keeps them
    CHECK(value_unit("sample units: \"a unit name far too long\"\n").empty());
    CHECK(value_unit("sample units: \"\x1b[2J\"\n") == "\\x1b[2J");            // escaped, never raw
    CHECK(value_unit("").empty());
    std::filesystem::remove_all(dir);
}
