// Cell-indexed sample frames: the compact payload of a sample stream's DATA frame
// (formats/point_stream.hpp, frame flag 2). A paradigm (C) sample (dissertation sections 3.4-3.5)
// is a function of its cell: the 88-byte SampleRecord's position, gradient, value, cell corner and
// cell size all follow from the cell's indices and its eight corner values on the volume's grid
// (kernels/cell_sampling.hpp complete_centre_samples). A frame may therefore carry, per record,
// only the cell's indices and corners: 14 bytes for a uint8 volume under 65,536 cells a side, 22
// for 16-bit samples, 38 for float32, instead of 88 (a frame is written so only when that at least
// halves it: float32 corners with 4-byte indices never do). The reader rebuilds the records.
//
// Payload layout (little endian), 64-byte header:
//   u8 corner coding (1 uint8, 2 int16, 3 uint16, 4 float32 bits) | u8 index bytes (2 or 4) |
//   u16 zero | u32 exception count E | f32 radius (every record's) | u32 zero |
//   f64 origin[3] | f64 spacing[3]
// then, per record, in order: i, j, k (index bytes each, unsigned) and the 8 corners (index
//   dx + 2 dy + 4 dz, in the corner coding);
// then E exceptions, by increasing record number: u32 record number | the whole 88-byte record,
//   which replaces that record (its slot above is zero).
// The encoder checks every record it compacts (Verify::all: rebuilds it and compares all 88 bytes;
// Verify::position: the fields that follow from the indices, for a producer that vouches for the
// rest): a record that does not rebuild exactly (another producer's, an index off the grid, another
// radius) becomes an exception, so the decoded records equal the encoded ones (under
// Verify::position, given the producer's promise, which tests/formats/test_sample_cell_frame.cpp
// checks for the generator).
// Errors: SampleCellDecoder throws FormatError("...") describing the defect (the caller adds the
// stream's name and position). Memory: the encoder keeps 256 rebuilt records (Verify::all) and 4
// bytes per exception; the decoder a 24 KB gradient table, and writes into the caller's records.
// Not thread-safe per object.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/cell_sampling.hpp"
#include "kernels/grid.hpp"
#include "kernels/records.hpp"

namespace meshless {

/// The grid the samples were generated on: world position of voxel (0,0,0) and the voxel spacing.
struct CellGrid {
    double origin[3] = {0, 0, 0};
    double spacing[3] = {1, 1, 1};
};

inline CellGrid cell_grid(const GridSpec& g) {
    CellGrid c;
    for (int a = 0; a < 3; ++a) {
        c.origin[a] = g.origin[a];
        c.spacing[a] = g.spacing[a];
    }
    return c;
}

inline constexpr std::size_t kSampleCellHeaderBytes = 64;

class SampleCellEncoder {
public:
    /// How a record is checked before it travels as its cell:
    ///   all: every field is rebuilt from the cell and compared (any producer's records);
    ///   position: the fields that follow from the cell's indices (pos, cell_lo, cell_size) and the
    ///     radius are; value and gradient are taken to be those of the corners, which the producer
    ///     vouches for: kernels/cell_sampling.hpp sample_active_cells on a volume whose values a
    ///     float holds exactly (tests/formats/test_sample_cell_frame.cpp checks that promise).
    enum class Verify { all, position };
    explicit SampleCellEncoder(const CellGrid& grid, Verify verify = Verify::all);
    /// Encodes rec[0..n) into out (replaced) and returns true when the payload is at most half the
    /// records' bytes; false (out unspecified) otherwise: the frame is then written raw.
    bool encode(const SampleRecord* rec, std::size_t n, std::vector<char>& out);

private:
    bool same_position(const SampleRecord& s, const std::uint32_t* ijk) const;
    CellGrid grid_;
    Verify verify_;
    double inverse_[3];
    std::uint8_t coding_ = 1;        // corner coding of the last frame (starts at uint8)
    std::size_t index_bytes_ = 2;    // index width of the last frame
    std::vector<SampleRecord> rebuilt_;
    std::vector<std::uint32_t> exceptions_;
};

class SampleCellDecoder {
public:
    /// Checks the header and that the payload's size is exactly what it implies for `count`
    /// records (FormatError otherwise), so the caller may size the records' memory from count.
    static void check(const void* payload, std::size_t bytes, std::uint64_t count);
    /// Decodes a payload of `bytes` bytes holding `count` records into out[0..count). Throws
    /// FormatError as check() does, and on an exception out of order or out of range; out[] may
    /// then hold part.
    void decode(const void* payload, std::size_t bytes, std::uint64_t count, SampleRecord* out);

private:
    struct Header {
        std::uint8_t coding = 0, index_bytes = 0;
        std::uint32_t exceptions = 0;
        float radius = 0;
        CellGrid grid;
    };
    static Header header(const void* payload, std::size_t bytes, std::uint64_t count);
    CentreGradientTable table_;  // uint8 corners: kept while the spacing stays the same (24 KB)
};

}  // namespace meshless
