// VolumeInput::blocks() (cli/common.hpp): the one pass that gives the value range and the surface
// frame. Split into layers of blocks across threads (each thread with its own reader of a raw
// payload, or straight from memory), it gives exactly the blocks of the serial pass and of
// block_minmax on the whole volume, for any thread count; a gzip payload (no reopen) stays serial.
#include <catch2/catch.hpp>

#include <random>
#include <string>

#include "cli/cli_harness.hpp"
#include "cli/common.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/block_minmax.hpp"

using namespace meshless;
using namespace meshless::test;

TEST_CASE("VolumeInput::blocks: the same blocks for any thread count, streamed or in memory", "[cli][blocks]") {
    TempDir d("blocks");
    // 70 x 50 x 99: three full layers of 32-cell blocks and a partial one; random bytes with a
    // bright corner so that blocks differ
    std::string bytes(70 * 50 * 99, '\0');
    std::mt19937 rng(4);
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(rng() % 200);
    bytes[bytes.size() - 1] = static_cast<char>(255);
    const std::string path = (d / "v_70x50x99_uint8.raw").string();
    spit(path, bytes);
    const Volume whole = read_volume(path);
    const BlockMinMax want = block_minmax(whole.view(), 32);
    REQUIRE(want.blocks[2] == 4);
    for (int threads : {1, 2, 3, 8}) {
        INFO("threads " << threads);
        cli::VolumeInput streamed;
        streamed.slices = open_slice_source(path);
        streamed.reopen = [&] { return open_slice_source(path); };
        streamed.threads = threads;
        cli::VolumeInput serial;  // no reopen: read in order whatever the thread count
        serial.slices = open_slice_source(path);
        serial.threads = threads;
        cli::VolumeInput memory;
        memory.volume = read_volume(path);
        memory.threads = threads;
        for (const cli::VolumeInput* in : {&streamed, &serial, &memory}) {
            const BlockMinMax& got = in->blocks();
            CHECK(got.blocks == want.blocks);
            CHECK(got.vmin == want.vmin);
            CHECK(got.vmax == want.vmax);
            CHECK(in->value_range()[1] == 255);
        }
    }
}
