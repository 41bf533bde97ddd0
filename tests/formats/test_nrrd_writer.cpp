// NRRD writer round trips through the NRRD reader.
#include <catch2/catch.hpp>

#include "formats/nrrd_writer.hpp"
#include "formats/volume_reader.hpp"
#include "test_paths.hpp"

using namespace meshless;

TEST_CASE("write_nrrd round trips grid and samples for every type", "[nrrd-writer]") {
    meshless::test::TempDir d("nrrdw");
    for (SampleType t : {SampleType::u8, SampleType::i16, SampleType::u16, SampleType::f32}) {
        GridSpec g;
        g.dims = {5, 4, 3};
        g.origin = {-1.5, 2.25, 1e6};
        g.spacing = {0.5, 1.25, 3};
        Volume v(g, t);
        for (std::size_t i = 0; i < v.bytes.size(); ++i) v.bytes[i] = static_cast<std::byte>(i * 7 + 3);
        const std::string p = (d / "v.nrrd").string();
        write_nrrd(v, p, "test");
        const Volume back = read_volume(p);
        CHECK(back.type == t);
        CHECK(back.grid.dims == g.dims);
        for (int a = 0; a < 3; ++a) {
            CHECK(back.grid.spacing[a] == Approx(g.spacing[a]));
            CHECK(back.grid.origin[a] == Approx(g.origin[a]));
        }
        CHECK(back.bytes == v.bytes);
    }
}
