// `meshless info` on VTK multiblock and AMR collections (cli/cmd_info.cpp): the levels, boxes,
// refinement, arrays and centring of the real AMR sets, and a missing piece reported on one line.
#include <catch2/catch.hpp>

#include "cli_harness.hpp"

using namespace meshless::test;

TEST_CASE("info describes AMR hierarchies: levels, boxes, refinement, arrays with centring, range", "[cli][multiblock]") {
    TempDir d("info-amr");
    if (have_shared_data()) {
        const std::string c = (shared_data() / "amr/chombo3d/chombo3d.vtm").string();
        auto r = sh("MESHLESS info " + c, d);
        REQUIRE(r.code == 0);
        CHECK_THAT(r.out, Catch::Contains("vtkHierarchicalBoxDataSet XML 0.1, 16 boxes in 3 levels"));
        CHECK_THAT(r.out, Catch::Contains("level 2: 14 boxes, spacing 0.25 0.25 0.25, refinement 2 from level 1"));
        CHECK_THAT(r.out, Catch::Contains("arrays: 'phi' (cell)"));
        CHECK_THAT(r.out, Catch::Contains("value: 'phi' (cell data: nodes at the cell centres), range -0.0391938073 .. -3.70335606e-05"));
        CHECK_THAT(r.out, Catch::Contains("level 2 box 0: 12 x 16 x 16 cell centres"));
        const std::string h = (shared_data() / "amr/HierarchicalBoxDataset.v1.1.vthb").string();
        r = sh("MESHLESS info " + h + " --value \"Fractal Volume Fraction\"", d);
        REQUIRE(r.code == 0);
        CHECK_THAT(r.out, Catch::Contains("81 boxes in 4 levels"));
        CHECK_THAT(r.out, Catch::Contains("level 3: 32 boxes"));
        CHECK_THAT(r.out, Catch::Contains("'VectorXYZ' (cell, 3 components)"));
        CHECK_THAT(r.out, Catch::Contains("range 0.0533417087 .. 5.26315789"));
    } else {
        WARN("shared data absent: the real AMR part of this test is skipped");
    }
    spit(d / "m.vtm", "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet><DataSet index=\"0\" file=\"p/gone.vts\"/>"
                      "</vtkMultiBlockDataSet></VTKFile>");
    const auto r = sh("MESHLESS info " + (d / "m.vtm").string(), d);
    CHECK(r.code == 2);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_THAT(r.err, Catch::Contains("m.vtm: piece 'p/gone.vts'"));
}
