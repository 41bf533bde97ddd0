// A DICOM series as a slice source (ooc/slice_source.hpp): slices served one file at a time, in any
// slab split, are the samples read_volume gives for the series and for the same volume as an NRRD.
// The series is written at test time with pydicom (tests/dicom_test_data.hpp).
#include <catch2/catch.hpp>
#include <cstring>
#include <vector>

#include "dicom_test_data.hpp"
#include "formats/volume_reader.hpp"
#include "ooc/slice_source.hpp"

using namespace meshless;
using namespace meshless::test;

#if MESHLESS_DICOM
TEST_CASE("dicom slice source: slabs of a series equal the NRRD's samples", "[ooc][dicom]") {
    TempDir dir("dicom-slices");
    const auto f = make_dicom_case("flipped", dir);  // y and z reversed into world order
    if (!f) return;
    const Volume n = read_volume(f->string() + ".nrrd");
    auto src = open_slice_source(f->string());
    REQUIRE(src->grid() == n.grid);
    REQUIRE(src->type() == n.type);
    const std::size_t slice = static_cast<std::size_t>(n.grid.dims[0] * n.grid.dims[1]) * sample_size(n.type);
    std::vector<std::byte> buf(slice * static_cast<std::size_t>(n.grid.dims[2]));
    src->read_slices(0, 3, buf.data());
    src->read_slices(3, n.grid.dims[2] - 3, buf.data() + 3 * slice);
    CHECK(std::memcmp(buf.data(), n.bytes.data(), buf.size()) == 0);
    CHECK_THROWS_AS(src->read_slices(n.grid.dims[2], 1, buf.data()), InvalidArgument);
}
#endif
