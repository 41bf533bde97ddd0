// Pipe endpoints of the stage graph: a Source that reads the binary point stream
// (formats/point_stream.hpp) and a Sink that writes it. One DATA frame = one batch, so a stage run
// as its own process sees the same batches, in the same order, as in-process: results are
// byte-identical across pipes. Frames are read straight into the batches' record arrays, which are
// recycled from consumed batches. Not thread-safe (called serially by the runner).
// Kinds: samples, seeds (multiblock seeds, section 4.4) and points; a point stream flagged with block
// ids (kStreamFlagBlocks) fills Batch::point_block, and a StreamSink made with_blocks writes it
// (a point batch without block ids is then a FormatError). A point or sample record with a NaN or
// infinite number is refused (FormatError naming the stream and the record): meshless writes none.
#pragma once
#include <memory>
#include <mutex>
#include <vector>

#include "formats/point_stream.hpp"
#include "stream/stage.hpp"

namespace meshless {

class StreamSource final : public Source {
public:
    Payload gives() const override { return payload_of(r_.kind()); }
    /// The reader must outlive the source; its META must already be read (read_meta()).
    explicit StreamSource(StreamReader& r) : r_(r) {}
    std::optional<Batch> next() override;
    /// Keeps the record arrays of consumed batches (a few) and reads later frames into them.
    bool recycle(Batch& consumed) override;

private:
    StreamReader& r_;
    std::uint64_t seq_ = 0;
    std::uint64_t records_ = 0;  ///< records handed out so far (for the messages)
    std::mutex m_;  // recycle() may run on the sink's thread while next() runs
    std::vector<std::vector<PointRecord>> spare_points_;
    std::vector<std::vector<SampleRecord>> spare_samples_;
    std::vector<char> packed_;  // point-with-block records before they are split
};

class StreamSink final : public Sink {
public:
    PayloadSet takes() const override { return payload_of(kind_); }
    /// Writes the stream header and META immediately; one DATA frame per non-empty batch.
    /// with_blocks (points only): records carry Batch::point_block (kStreamFlagBlocks).
    StreamSink(std::FILE* f, std::string name, RecordKind kind, const StreamMeta& meta, bool compress = false,
               bool with_blocks = false);
    void consume(Batch&& b) override;
    void finish() override { w_.finish(); }
    /// Begins segment `index` of a stream of several isovalues (formats/point_stream.hpp "Segments"):
    /// call between graph runs, when the previous run's batches are all consumed.
    void begin_segment(std::uint64_t index, double iso) {
        StreamMeta keys;
        keys.set("iso", iso);
        w_.write_segment(index, keys);
    }
    /// Samples generated on this grid travel cell-indexed (StreamWriter::index_cells).
    void index_cells(const CellGrid& grid, SampleCellEncoder::Verify verify = SampleCellEncoder::Verify::all) {
        w_.index_cells(grid, verify);
    }
    std::uint64_t total() const { return w_.total(); }

private:
    StreamWriter w_;
    RecordKind kind_;
    bool blocks_;
    std::vector<char> packed_;
};

}  // namespace meshless
