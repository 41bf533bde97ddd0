// formats/anatomical_frame.hpp through the readers: what NIfTI (sform, qform), NRRD (space, space
// directions, generic handed spaces) and MetaImage (TransformMatrix, AnatomicalOrientation, ITK's
// default) headers say about the patient's axes; formats that say nothing give no frame. Real files:
// VTK's headsq CT is x L, y P, z I; HeadMRVolume LPS; the MNI template RAS.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "formats/volume_reader.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
namespace fs = std::filesystem;

namespace {
void spit(const fs::path& p, const std::string& s) { std::ofstream(p, std::ios::binary) << s; }

std::string frame_of(const std::string& path) {
    const VolumeInfo vi = probe_volume(path);
    return vi.frame ? describe_frame(*vi.frame) : "none";
}

// NIfTI-1 n+1, 2x2x2 uint8, with the given sform rows or qform quaternion.
std::string nifti(int sform, int qform, const std::array<float, 12>& srow, const std::array<float, 3>& quat, float qfac) {
    std::string h(352, '\0');
    auto put16 = [&](std::size_t off, std::int16_t v) { std::memcpy(h.data() + off, &v, 2); };
    auto putf = [&](std::size_t off, float v) { std::memcpy(h.data() + off, &v, 4); };
    const std::int32_t sz = 348;
    std::memcpy(h.data(), &sz, 4);
    put16(40, 3);
    put16(42, 2), put16(44, 2), put16(46, 2);
    put16(70, 2), put16(72, 8);
    putf(76, qfac), putf(80, 1), putf(84, 1), putf(88, 1);
    putf(108, 352);
    put16(252, static_cast<std::int16_t>(qform));
    put16(254, static_cast<std::int16_t>(sform));
    for (int i = 0; i < 3; ++i) putf(256 + 4 * i, quat[i]);
    for (int i = 0; i < 12; ++i) putf(280 + 4 * i, srow[i]);
    std::memcpy(h.data() + 344, "n+1\0", 4);
    return h + std::string(8, '\0');
}
}  // namespace

TEST_CASE("a direction matrix along the axes but backwards gives world coordinates (NIfTI, NRRD, MetaImage)", "[formats]") {
    // FSL's "LAS" NIfTI (sform x = -2), an NRRD `space directions (-2,0,0)` and a MetaImage
    // TransformMatrix -1 0 0: the same 3x1x1 samples 10 20 30 at world x = 4, 2, 0. Read as world
    // coordinates: origin 0, spacing 2, samples 30 20 10 (they were written with origin + |s| index:
    // x 4..8, the object mirrored and moved)
    meshless::test::TempDir d("world_axes");
    const std::string samples("\x0a\x14\x1e", 3);
    std::string n = nifti(1, 0, {-2, 0, 0, 4, 0, 2, 0, 0, 0, 0, 2, 0}, {0, 0, 0}, 1);
    auto put16 = [&](std::size_t off, std::int16_t v) { std::memcpy(n.data() + off, &v, 2); };
    put16(42, 3), put16(44, 1), put16(46, 1);  // dims 3 x 1 x 1
    n.resize(352);
    spit(d.path / "las.nii", n + samples);
    spit(d.path / "neg.nrrd", "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 3 1 1\nspace: RAS\n"
                              "space directions: (-2,0,0) (0,2,0) (0,0,2)\nspace origin: (4,0,0)\nencoding: raw\n\n" + samples);
    spit(d.path / "neg.mha", "ObjectType = Image\nNDims = 3\nDimSize = 3 1 1\nElementSpacing = 2 2 2\nOffset = 4 0 0\n"
                             "TransformMatrix = -1 0 0 0 1 0 0 0 1\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n" + samples);
    // the slight obliquity scanners leave (here 5e-6 rad) is along the axes too (it was the index frame)
    std::string nob = nifti(1, 0, {-2, 1e-5f, 0, 4, 0, 2, 0, 0, 0, 0, 2, 0}, {0, 0, 0}, 1);
    std::memcpy(nob.data() + 42, n.data() + 42, 6);  // dims 3 x 1 x 1
    nob.resize(352);
    spit(d.path / "las_oblique.nii", nob + samples);
    for (const char* f : {"las.nii", "las_oblique.nii", "neg.nrrd", "neg.mha"}) {
        INFO(f);
        const Volume v = read_volume((d.path / f).string());
        CHECK(v.grid.origin[0] == 0);
        CHECK(v.grid.spacing[0] == 2);
        REQUIRE(v.bytes.size() == 3);
        CHECK(std::to_integer<int>(v.bytes[0]) == 30);
        CHECK(std::to_integer<int>(v.bytes[2]) == 10);
    }
}

TEST_CASE("anatomical frame: what the headers say, per format", "[formats]") {
    meshless::test::TempDir d("frames");
    // NIfTI sform: diag(-2, 2, 2) in RAS runs index x toward L; the reader reverses that axis (its
    // positions are then RAS world coordinates), so the volume's +x is R
    spit(d.path / "s.nii", nifti(1, 0, {-2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0}, {0, 0, 0}, 1));
    CHECK(frame_of((d.path / "s.nii").string()) == "x R, y A, z S");
    // qform: 180 degrees about z (quaternion 0,0,1) is diag(-1,-1,1), qfac -1 reverses z: all three
    // axes run backwards and are reversed
    spit(d.path / "q.nii", nifti(0, 1, {}, {0, 0, 1}, -1));
    CHECK(frame_of((d.path / "q.nii").string()) == "x R, y A, z S");
    // a rotating sform (index x along A, index y along R) cannot be a grid of world axes: the index
    // frame stays, the frame says where its axes point
    spit(d.path / "r.nii", nifti(1, 0, {0, 2, 0, 0, 2, 0, 0, 0, 0, 0, 2, 0}, {0, 0, 0}, 1));
    CHECK(frame_of((d.path / "r.nii").string()) == "x A, y R, z S");
    // both codes 0: nothing said
    spit(d.path / "n.nii", nifti(0, 0, {}, {0, 0, 0}, 1));
    CHECK(frame_of((d.path / "n.nii").string()) == "none");
    // NRRD
    const std::string bytes(8, '\0');
    auto nrrd = [&](const std::string& name, const std::string& fields) {
        spit(d.path / name, "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n" + fields + "\n" + bytes);
        return frame_of((d.path / name).string());
    };
    CHECK(nrrd("ras.nrrd", "space: right-anterior-superior\nspace directions: (1,0,0) (0,1,0) (0,0,1)\n") == "x R, y A, z S");
    CHECK(nrrd("lps.nrrd", "space: LPS\n") == "x L, y P, z S");
    CHECK(nrrd("cor.nrrd", "space: RAS\nspace directions: (-1,0,0) (0,0,-1) (0,-1,0)\n") == "x L, y I, z P");
    CHECK(nrrd("left.nrrd", "space: 3D-left-handed\n") == "x L, y P, z I");
    CHECK(nrrd("right.nrrd", "space: 3D-right-handed\n") == "x L, y P, z S");
    // a negative spacing: the samples are reversed into the world's axes, which this space names (the
    // frame was turned round as well, so such a volume was drawn upside down)
    CHECK(nrrd("flip.nrrd", "space: 3D-right-handed\nspacings: 1 1 -1\n") == "x L, y P, z S");
    CHECK(nrrd("flipdir.nrrd", "space: 3D-right-handed\nspace directions: (1,0,0) (0,1,0) (0,0,-1)\n") == "x L, y P, z S");
    CHECK(nrrd("lpsdir.nrrd", "space: LPS\nspace directions: (1,0,0) (0,1,0) (0,0,-1)\n") == "x L, y P, z S");
    CHECK(nrrd("none.nrrd", "") == "none");
    CHECK(nrrd("scanner.nrrd", "space: scanner-xyz\n") == "none");
    // MetaImage
    auto mhd = [&](const std::string& name, const std::string& fields) {
        spit(d.path / name, "ObjectType = Image\nNDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\n" + fields +
                                "ElementDataFile = LOCAL\n" + bytes);
        return frame_of((d.path / name).string());
    };
    CHECK(mhd("id.mha", "") == "x L, y P, z S");
    CHECK(mhd("rai.mha", "AnatomicalOrientation = RAI\n") == "x L, y P, z S");
    CHECK(mhd("lps.mha", "AnatomicalOrientation = LPS\n") == "x R, y A, z I");
    CHECK(mhd("tm.mha", "TransformMatrix = 1 0 0 0 0 1 0 -1 0\n") == "x L, y S, z A");
    // a backward matrix axis turns the frame round with the samples; a negative ElementSpacing
    // reverses the samples into the world's axes, whose directions the frame already says
    CHECK(mhd("tmneg.mha", "TransformMatrix = 1 0 0 0 1 0 0 0 -1\n") == "x L, y P, z S");
    CHECK(mhd("spneg.mha", "ElementSpacing = 1 1 -1\n") == "x L, y P, z S");
    // formats that say nothing
    spit(d.path / "v_2x2x2_uint8.raw", bytes);
    CHECK(frame_of((d.path / "v_2x2x2_uint8.raw").string()) == "none");
}

TEST_CASE("anatomical frame: the real heads", "[formats]") {
    if (!meshless::test::have_shared_data()) return;
    const auto R = [](const char* rel) { return (meshless::test::shared_data() / rel).string(); };
    CHECK(frame_of(R("vtk_headsq/quarter.nhdr")) == "x L, y P, z I");
    CHECK(frame_of(R("vtk_HeadMRVolume/HeadMRVolume.mhd")) == "x L, y P, z S");
    CHECK(frame_of(R("mni152_brain/avg152T1_RL_nifti.nii.gz")) == "x R, y A, z S");
    CHECK(frame_of(R("vtkjs_LIDC2/LIDC2.vti")) == "none");
    CHECK(frame_of(R("fuel/fuel_64x64x64_uint8.raw")) == "none");
    CHECK(frame_of(R("vtk_slc/neghip.slc")) == "none");
}
