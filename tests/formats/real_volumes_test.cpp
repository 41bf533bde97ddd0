// Every regular volume listed in shared/data/SOURCES.md loads with the dims, type, spacing and
// value range given there; probe_volume agrees with read_volume without reading the payload.
#include <catch2/catch.hpp>

#include <filesystem>

#include "formats/volume_reader.hpp"
#include "tests/test_paths.hpp"

using namespace meshless;
namespace fs = std::filesystem;

namespace {

struct Expect {
    const char* rel;
    std::array<std::int64_t, 3> dims;
    SampleType type;
    std::array<double, 3> spacing;
    double lo, hi;
    RawOptions raw{};
};

void check(const Expect& e) {
    const std::string p = (meshless::test::shared_data() / e.rel).string();
    INFO(p);
    REQUIRE(looks_like_volume(p));
    const VolumeInfo info = probe_volume(p, e.raw);
    CHECK(info.grid.dims == e.dims);
    CHECK(info.type == e.type);
    const Volume v = read_volume(p, e.raw);
    CHECK(v.grid.dims == e.dims);
    CHECK(v.type == e.type);
    CHECK(v.grid == info.grid);
    CHECK(v.bytes.size() == static_cast<std::size_t>(v.grid.voxel_count()) * sample_size(v.type));
    for (int a = 0; a < 3; ++a) CHECK(v.grid.spacing[a] == Approx(e.spacing[a]));
    const auto r = v.value_range();
    CHECK(r[0] == Approx(e.lo));
    CHECK(r[1] == Approx(e.hi));
}

}  // namespace

TEST_CASE("real volumes from shared/data load with the documented dims, type and range", "[formats]") {
    if (!meshless::test::have_shared_data()) {
        WARN("shared data absent: skipping real-volume checks");
        return;
    }
    RawOptions bucky;
    bucky.dims = std::array<std::int64_t, 3>{32, 32, 32};
    bucky.type = SampleType::u8;
    const std::vector<Expect> all = {
        {"neghip/neghip_64x64x64_uint8.raw", {64, 64, 64}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"fuel/fuel_64x64x64_uint8.raw", {64, 64, 64}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"fuel/fuel_64x64x64_uint8.dat", {64, 64, 64}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"silicium/silicium_98x34x34_uint8.raw", {98, 34, 34}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"silicium/silicium_98_34_34_uint8.dat", {98, 34, 34}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"tooth/tooth_103x94x161_uint8.raw", {103, 94, 161}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"bucky/Bucky.raw", {32, 32, 32}, SampleType::u8, {1, 1, 1}, 1, 248, bucky},
        {"bucky/Bucky_32x32x32_uint8.raw", {32, 32, 32}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"bucky/Bucky_32x32x32_uint8.dat", {32, 32, 32}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"vtk_headsq/quarter.nhdr", {64, 64, 93}, SampleType::i16, {3.2, 3.2, 1.5}, 0, 3926},
        {"vtk_HeadMRVolume/HeadMRVolume.mhd", {48, 62, 42}, SampleType::u8, {4, 4, 4}, 0, 255},
        {"vtk_slc/neghip.slc", {66, 66, 66}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"vtk_slc/bolt.slc", {70, 123, 66}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"vtk_slc/nut.slc", {68, 41, 59}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"vtk_slc/sphere.slc", {50, 50, 50}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"vtk_slc/embryo.slc", {256, 256, 256}, SampleType::u8, {1, 1, 1}, 0, 197},
        {"vtk_hydrogen/hydrogen.vti", {64, 64, 64}, SampleType::f32, {1, 1, 1}, 0, 1},
        {"vtk_ironProt/ironProt.vtk", {68, 68, 68}, SampleType::u8, {1, 1, 1}, 0, 255},
        {"mni152_brain/avg152T1_RL_nifti.nii.gz", {91, 109, 91}, SampleType::u8, {2, 2, 2}, 0, 255},
        {"vtkjs_LIDC2/LIDC2.vti", {256, 256, 133}, SampleType::u8, {1.40625, 1.40625, 2.5}, 0, 255},
        {"vtkjs_LIDC2/LIDC2.vti/index.json", {256, 256, 133}, SampleType::u8, {1.40625, 1.40625, 2.5}, 0, 255},
    };
    for (const auto& e : all) check(e);
}

TEST_CASE("real volumes: the raw name convention, the .dat sidecar and the .dat itself agree byte for byte", "[formats]") {
    if (!meshless::test::have_shared_data()) {
        WARN("shared data absent: skipping");
        return;
    }
    const auto d = meshless::test::shared_data();
    const Volume a = read_volume((d / "silicium/silicium_98x34x34_uint8.raw").string());
    const Volume b = read_volume((d / "silicium/silicium_98_34_34_uint8.dat").string());
    CHECK(a.bytes == b.bytes);
    // Bucky.raw and the open-scivis Bucky differ (SOURCES.md): the reader must not mix them up
    RawOptions o;
    o.dims = std::array<std::int64_t, 3>{32, 32, 32};
    o.type = SampleType::u8;
    CHECK(read_volume((d / "bucky/Bucky.raw").string(), o).bytes !=
          read_volume((d / "bucky/Bucky_32x32x32_uint8.raw").string()).bytes);
    // headsq slices: slice k of the volume is the bytes of quarter.(k+1)
    const Volume h = read_volume((d / "vtk_headsq/quarter.nhdr").string());
    RawOptions s;
    s.dims = std::array<std::int64_t, 3>{64, 64, 1};
    s.type = SampleType::i16;
    const Volume q50 = read_volume((d / "vtk_headsq/quarter.50").string(), s);
    REQUIRE(q50.bytes.size() == 8192);
    CHECK(std::equal(q50.bytes.begin(), q50.bytes.end(), h.bytes.begin() + 49 * 8192));
    // embryo: every slice decodes one byte short; the pad is zero
    const Volume em = read_volume((d / "vtk_slc/embryo.slc").string());
    CHECK(em.view().at(255, 255, 0) == 0);
    CHECK(em.view().at(255, 255, 255) == 0);
    // hydrogen (vti, float32): the documented range is exactly [0, 1]
    const auto hr = read_volume((d / "vtk_hydrogen/hydrogen.vti").string()).value_range();
    CHECK(hr[0] == 0.0);
    CHECK(hr[1] == 1.0);
    // LIDC2: directory and index.json give the same bytes
    CHECK(read_volume((d / "vtkjs_LIDC2/LIDC2.vti").string()).bytes ==
          read_volume((d / "vtkjs_LIDC2/LIDC2.vti/index.json").string()).bytes);
}

TEST_CASE("looks_like_volume rejects metadata that is not a volume", "[formats]") {
    if (!meshless::test::have_shared_data()) {
        WARN("shared data absent: skipping");
        return;
    }
    const auto d = meshless::test::shared_data();
    CHECK_FALSE(looks_like_volume((d / "neghip/neghip.json").string()));
    CHECK_FALSE(looks_like_volume((d / "SOURCES.md").string()));
    CHECK_FALSE(looks_like_volume((d / "bucky").string()));
    CHECK(looks_like_volume((d / "vtkjs_LIDC2/LIDC2.vti").string()));
}
