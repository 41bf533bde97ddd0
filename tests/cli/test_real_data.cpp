// Smoke runs on the real volumes of ../shared/data (skipped with a warning when it is absent):
// every format family through `meshless isosurface`, pipes == in-process on a multi-file NRRD,
// and VTK's own PLY reader opening our output when python3-vtk9 is installed.
#include <catch2/catch.hpp>

#include <filesystem>

#include "cli/cli_harness.hpp"

using namespace meshless::test;
namespace fs = std::filesystem;

TEST_CASE("iso-splatting runs on every real volume format", "[cli][real]") {
    if (!have_shared_data()) {
        WARN("../shared/data not found: real-data smoke tests skipped");
        return;
    }
    TempDir d("real");
    const std::string D = d.path.string(), S = shared_data().string();
    struct Case { const char* path; const char* iso; };
    const Case cases[] = {
        {"neghip/neghip_64x64x64_uint8.raw", "100.5"},   {"fuel/fuel_64x64x64_uint8.raw", "20.5"},
        {"tooth/tooth_103x94x161_uint8.raw", "100.5"},   {"vtkjs_LIDC2/LIDC2.vti", "100.5"},
        {"vtk_headsq/quarter.nhdr", "1000.5"},           {"vtk_HeadMRVolume/HeadMRVolume.mhd", "60.5"},
        {"vtk_ironProt/ironProt.vtk", "100.5"},          {"vtk_hydrogen/hydrogen.vti", "0.1"},
        {"vtk_slc/nut.slc", "100.5"},                    {"mni152_brain/avg152T1_RL_nifti.nii.gz", "100.5"},
        {"bucky/Bucky_32x32x32_uint8.raw", "100.5"},     {"silicium/silicium_98x34x34_uint8.raw", "100.5"},
    };
    for (const auto& c : cases) {
        INFO(c.path);
        const auto r = sh("MESHLESS isosurface " + S + "/" + c.path + " --iso " + c.iso + " -o " + D + "/p.ply --stats", d);
        REQUIRE(r.code == 0);
        CHECK_THAT(r.err, Catch::Contains("points"));
        CHECK(fs::file_size(d / "p.ply") > 10000);
    }
}

TEST_CASE("pipes equal in-process on the multi-file headsq NRRD, exact projection, 2 threads", "[cli][real]") {
    if (!have_shared_data()) {
        WARN("../shared/data not found: skipped");
        return;
    }
    TempDir d("realpipe");
    const std::string D = d.path.string(), V = (shared_data() / "vtk_headsq/quarter.nhdr").string();
    REQUIRE(sh("MESHLESS isosurface " + V + " --iso 1000.5 --projection exact -o " + D + "/a.ply", d).code == 0);
    REQUIRE(sh("MESHLESS generate " + V + " --iso 1000.5 --threads 2 | MESHLESS project --projection exact --threads 2 | MESHLESS write -o " +
                   D + "/b.ply",
               d).code == 0);
    CHECK(slurp(d / "a.ply") == slurp(d / "b.ply"));
}

TEST_CASE("VTK's vtkPLYReader opens the point set and the MC mesh", "[cli][real][vtk]") {
    TempDir d("vtk");
    if (sh("/usr/bin/python3 -c \"import vtk\"", d).code != 0) {
        WARN("python3-vtk9 not installed: VTK interoperability check skipped");
        return;
    }
    const std::string D = d.path.string();
    REQUIRE(sh("MESHLESS demo -o " + D + " --n 40 --size 64x64", d).code == 0);
    REQUIRE(sh("MESHLESS info " + D + "/demo.ply | grep \"element vertex\" | awk \"{print \\$3}\" > " + D + "/n.txt", d).code == 0);
    const auto r = sh("/usr/bin/python3 -c \"import vtk; r = vtk.vtkPLYReader(); r.SetFileName(\\\"" + D +
                          "/demo.ply\\\"); r.Update(); o = r.GetOutput(); print(o.GetNumberOfPoints(), o.GetPointData().GetNormals() is not None)\"",
                      d);
    REQUIRE(r.code == 0);
    std::string n = slurp(d / "n.txt");
    n.erase(n.find_last_not_of(" \n") + 1);
    CHECK(r.out == n + " True\n");
}
