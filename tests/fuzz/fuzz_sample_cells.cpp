// libFuzzer target for cell-indexed sample frames (formats/sample_cell_frame.hpp), the compact DATA
// payload of sample streams: the decoder alone, since a stream's CRC would stop the fuzzer's
// mutations before they reach it (fuzz_point_stream covers the framing around it).
// Input: u32 little-endian record count, then the payload. The count is held to what the payload
// could describe (7 records' bytes per payload byte, as StreamReader holds it), so no allocation
// exceeds what the data justifies. The only acceptable failure is FormatError. Oracle: records
// that decode are re-encoded on the payload's grid (every field verified) and decode to the same
// bytes. Built and run like every target: scripts/fuzz.sh SECONDS BUILD fuzz_sample_cells.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "formats/sample_cell_frame.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 4) return 0;
    std::uint32_t count;
    std::memcpy(&count, data, 4);
    const std::uint8_t* payload = data + 4;
    const std::size_t bytes = size - 4;
    if (std::uint64_t{count} * sizeof(SampleRecord) > std::uint64_t{bytes} * 7) return 0;
    std::vector<SampleRecord> out(count);
    SampleCellDecoder dec;
    try {
        dec.decode(payload, bytes, count, out.data());
    } catch (const FormatError&) {
        return 0;
    }
    CellGrid g;
    std::memcpy(g.origin, payload + 16, 24);
    std::memcpy(g.spacing, payload + 40, 24);
    SampleCellEncoder enc(g, SampleCellEncoder::Verify::all);
    std::vector<char> again;
    if (!enc.encode(out.data(), out.size(), again)) return 0;
    std::vector<SampleRecord> back(count);
    dec.decode(again.data(), again.size(), count, back.data());  // must not throw
    if (count && std::memcmp(back.data(), out.data(), count * sizeof(SampleRecord)) != 0) __builtin_trap();
    return 0;
}
