// The Zarr slab source (ooc/slice_source.hpp over formats/zarr.hpp ZarrChunkRows): any range of slices,
// within a chunk row, across rows, whole rows, backwards, served as the whole read has them.
#include <catch2/catch.hpp>

#include <cstring>
#include <utility>
#include <vector>

#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "ooc/slice_source.hpp"
#include "test_paths.hpp"
#include "zarr_test_data.hpp"

using namespace meshless;
using meshless::test::TempDir;
using meshless::test::write_zarr;
using meshless::test::ZarrWriteOptions;

namespace {
constexpr std::int64_t NX = test::kZarrNx, NY = test::kZarrNy, NZ = test::kZarrNz;
std::vector<double> oracle_values() { return test::zarr_oracle_values(); }
}  // namespace

TEST_CASE("zarr: the chunk-row streamer serves any slice range as the whole read", "[ooc][zarr]") {
    TempDir d("zarr-stream");
    ZarrWriteOptions o;
    o.dtype = ">i2";
    o.compressor = "zlib";
    o.chunks = {2, 4, 5};
    write_zarr(d.path / "v.zarr", oracle_values(), NX, NY, NZ, o);
    const Volume whole = read_volume((d.path / "v.zarr").string());
    auto src = open_slice_source((d.path / "v.zarr").string());
    REQUIRE(src->type() == SampleType::i16);
    const std::size_t slice = static_cast<std::size_t>(NX * NY) * 2;
    for (const auto& [k, count] : std::vector<std::pair<int, int>>{{0, 9}, {1, 1}, {3, 4}, {8, 1}, {0, 2}, {2, 2}, {7, 2}, {4, 1}}) {
        std::vector<std::byte> got(static_cast<std::size_t>(count) * slice);
        src->read_slices(k, count, got.data());
        INFO(k << " " << count);
        CHECK(std::memcmp(got.data(), whole.bytes.data() + static_cast<std::size_t>(k) * slice, got.size()) == 0);
    }
    CHECK_THROWS_AS(src->read_slices(8, 2, nullptr), InvalidArgument);
}

