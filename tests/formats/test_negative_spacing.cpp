// A negative spacing is honoured as a reversed axis (nonsense geometry): the volume read
// from a file with spacing -s along an axis holds, at every world position, the value the file puts
// there. Oracle: the same samples written with positive spacing in reversed order.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
namespace fs = std::filesystem;

namespace {
void spit(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

// 3x2x2 uint8 samples 100k+10j+i, x fastest; reversed along x when `rev_x`, along z when `rev_z`.
std::string samples(bool rev_x, bool rev_z) {
    std::string s;
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 3; ++i) s += static_cast<char>(100 * (rev_z ? 1 - k : k) + 10 * j + (rev_x ? 2 - i : i));
    return s;
}
}  // namespace

TEST_CASE("negative spacing: NRRD, MetaImage, VTK legacy and VTI read as reversed axes", "[formats][hostile]") {
    test::TempDir d("negspacing");
    // the reference: positive spacing, samples reversed along x and z, origin at the last file sample
    spit(d / "ref.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 2 2\nspacings: 2 1 0.5\nspace origin: (6,20,29.5)\n"
                         "encoding: raw\n\n" + samples(true, true));
    spit(d / "neg.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 2 2\nspacings: -2 1 -0.5\nspace origin: (10,20,30)\n"
                         "encoding: raw\n\n" + samples(false, false));
    spit(d / "neg.mha", "ObjectType = Image\nNDims = 3\nDimSize = 3 2 2\nElementSpacing = -2 1 -0.5\nOffset = 10 20 30\n"
                        "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n" + samples(false, false));
    spit(d / "neg.vtk", "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 3 2 2\n"
                        "SPACING -2 1 -0.5\nORIGIN 10 20 30\nPOINT_DATA 12\nSCALARS s unsigned_char\nLOOKUP_TABLE default\n" +
                            samples(false, false));
    std::string ascii;
    for (unsigned char c : samples(false, false)) ascii += std::to_string(c) + " ";
    spit(d / "neg.vti", "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                        "<ImageData WholeExtent=\"0 2 0 1 0 1\" Origin=\"10 20 30\" Spacing=\"-2 1 -0.5\">\n"
                        "<Piece Extent=\"0 2 0 1 0 1\">\n<PointData Scalars=\"s\">\n<DataArray type=\"UInt8\" Name=\"s\" "
                        "format=\"ascii\">" + ascii + "</DataArray>\n</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n");
    const Volume ref = read_volume((d / "ref.nrrd").string());
    REQUIRE(ref.grid.origin == std::array<double, 3>{6, 20, 29.5});
    for (const char* name : {"neg.nrrd", "neg.mha", "neg.vtk", "neg.vti"}) {
        INFO(name);
        const std::string p = (d / name).string();
        const Volume v = read_volume(p);
        CHECK(v.grid == ref.grid);
        CHECK(v.bytes == ref.bytes);
        CHECK(map_volume(p).bytes == ref.bytes);  // the mapped path is not taken for a flipped axis
        CHECK(probe_volume(p).grid == ref.grid);
    }
}
