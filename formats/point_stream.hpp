// The on-pipe binary stream between stages (docs/architecture.md "On-pipe stream"), version 1.
//
// Layout, all integers little endian:
//   stream header, 32 bytes: magic "\x89MLS\r\n\x1a\n" (8) | u32 version (=1) | u32 record kind
//     (1 point, 2 sample, 5 seed) | u32 record size | u32 flags | u64 reserved (0)
//   record sizes: point 32 (PointRecord), or 36 with flags bit 0 (kStreamFlagBlocks: each point
//     record is followed by a u32 block id, the multiblock path's PLY `block`); sample 88
//     (SampleRecord); seed 40 (SeedRecord, the multiblock seeds of section 4.4). Flags other than
//     bit 0, and bit 0 on anything but points, are refused. A point stream without blocks is
//     byte-for-byte what this format was before seeds and blocks existed.
//   frames, each a 32-byte header: u32 type (1 META, 2 DATA, 3 END) | u32 flags (bit 0: payload is
//     one zstd frame; bit 1: payload is cell-indexed samples, formats/sample_cell_frame.hpp) |
//     u64 seq | u64 count (records; END: total records in the stream) |
//     u32 stored payload bytes | u32 CRC-32 of the stored payload
//     followed by the payload: META = "key=value\n" text; DATA = count records (raw, zstd, or, in a
//     sample stream, cell-indexed: each sample as its cell's indices and corner values, 14 bytes
//     instead of 88 for a uint8 volume; the reader rebuilds the same records). A DATA frame with
//     other flags, with both bits, or cell-indexed in a stream of points or seeds is refused.
//   exactly one END frame closes the stream.
// Segments (a stream of several isovalues, `generate VOLUME --iso V1,V2,...`): the first META lists
//   `isovalues=V1,V2,...` and holds no `iso` (so a reader that knows no segments refuses it for want
//   of an isovalue); each isovalue's records follow a META frame of their own whose keys are
//   `segment=K` (0, 1, ... in order) and `iso=VK`. A segment META's keys are not merged into the
//   stream's metadata; a reader made to stop at segments hands them over one at a time, any other
//   reads the records of all segments in order. A segment number out of order is refused.
// Readers skip frame types they do not know, reject a wrong magic ("not a meshless stream"), a
// version other than 1, a record size that does not match the kind, CRC mismatches, EOF before
// END ("truncated stream") and bytes after END, all as FormatError naming the stream ("-" = stdin).
// Thread-safety: one reader or writer per object.
#pragma once
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "formats/sample_cell_frame.hpp"
#include "kernels/records.hpp"

namespace meshless {

inline constexpr std::uint32_t kStreamVersion = 1;
/// Stream header flag: point records carry a u32 block id each (record size 36).
inline constexpr std::uint32_t kStreamFlagBlocks = 1;
/// Bytes of one record of a point-with-block stream.
inline constexpr std::size_t kPointBlockRecordSize = sizeof(PointRecord) + sizeof(std::uint32_t);

/// Stream metadata: iso value, grid, bounds, producer command line ... (sorted keys).
struct StreamMeta {
    std::map<std::string, std::string> kv;
    /// The stream the values were read from (for messages; empty for metadata made in memory).
    std::string source;
    /// "SOURCE: " to begin a message about these values ("" without a source).
    std::string where() const { return source.empty() ? std::string() : source + ": "; }
    /// Stores v with its line feeds (a file name's) written as \x0a, so that every value is one
    /// line here, in a stream's META frame and in an output's header alike.
    void set(const std::string& k, const std::string& v);
    void set(const std::string& k, double v);
    std::optional<std::string> get(const std::string& k) const;
    /// The value parsed as a double; nullopt when absent; FormatError ("SOURCE: stream metadata:
    /// 'k' is not a number: ...") when present but not a number.
    std::optional<double> get_double(const std::string& k) const;
    /// The same, also refusing NaN and infinities.
    std::optional<double> get_finite(const std::string& k) const;
    std::string serialize() const;
    static StreamMeta parse(const std::string& text, const std::string& name);
};

/// Bytes per record of kind k under the header flags (see above).
std::size_t record_size(RecordKind k, std::uint32_t flags = 0);

/// Packs points and their block ids (same size) as 36-byte records into out (replaced).
void interleave_point_blocks(const PointRecord* points, const std::uint32_t* blocks, std::size_t n, std::vector<char>& out);
/// Unpacks n 36-byte records into points and blocks (resized to n).
void deinterleave_point_blocks(const char* records, std::size_t n, std::vector<PointRecord>& points,
                               std::vector<std::uint32_t>& blocks);

class StreamWriter {
public:
    /// Writes the stream header to f (not owned). `name` is used in error messages.
    /// flags: kStreamFlagBlocks for points with block ids (records of kPointBlockRecordSize bytes).
    StreamWriter(std::FILE* f, std::string name, RecordKind kind, bool compress = false, std::uint32_t flags = 0);
    void write_meta(const StreamMeta& m);
    /// Sample streams without compression: DATA frames are written cell-indexed when that halves
    /// them or better (samples generated on this grid), raw otherwise; the records read back are
    /// the same either way.
    void index_cells(const CellGrid& grid, SampleCellEncoder::Verify verify = SampleCellEncoder::Verify::all);
    /// Begins segment `index` (0, 1, ... in order; see "Segments" above): a META frame of `keys`
    /// (its isovalue: iso=V) with segment=index.
    void write_segment(std::uint64_t index, const StreamMeta& keys);
    /// Writes one DATA frame (skipped when count == 0).
    void write_data(std::uint64_t seq, const void* records, std::uint64_t count);
    /// Writes the END frame and flushes.
    void finish();
    std::uint64_t total() const { return total_; }

private:
    void write_frame(std::uint32_t type, std::uint32_t flags, std::uint64_t seq, std::uint64_t count,
                     const void* payload, std::uint32_t bytes);
    void put(const void* p, std::size_t n);
    std::FILE* f_;
    std::string name_;
    std::size_t rsize_;
    bool compress_;
    std::uint64_t total_ = 0;
    std::vector<char> scratch_;
    std::optional<SampleCellEncoder> cells_;
};

class StreamReader {
public:
    /// Reads and validates the stream header from f (not owned); throws FormatError.
    StreamReader(std::FILE* f, std::string name);
    RecordKind kind() const { return kind_; }
    /// Header flags (kStreamFlagBlocks) and the resulting record size.
    std::uint32_t flags() const { return flags_; }
    bool has_blocks() const { return (flags_ & kStreamFlagBlocks) != 0; }
    std::size_t record_bytes() const { return rsize_; }
    /// Metadata of all META frames seen so far (the first frames of a stream in practice), but for
    /// segment frames.
    const StreamMeta& meta() const { return meta_; }
    /// Reads frames up to the first DATA frame (the META frames before it), or up to the first
    /// segment frame when stopping at segments.
    void read_meta();
    /// Makes next_records() end at each segment frame (nullopt) until next_segment() is called; call
    /// before read_meta(). Otherwise segments are read through as one.
    void stop_at_segments() { stop_at_segments_ = true; }
    /// Stopping at segments: the keys of the segment that begins here (segment=K, iso=V), after which
    /// next_records() delivers its records; nullopt at the END of the stream. Throws FormatError for
    /// records before the first segment of a stream that has segments.
    std::optional<StreamMeta> next_segment();
    /// Segment frames read so far.
    std::uint64_t segments() const { return segments_; }
    /// Next DATA frame's records appended to `out` as raw bytes; returns the record count, or
    /// nullopt at END (after checking the END total). Throws FormatError on corruption/truncation.
    std::optional<std::uint64_t> next_data(std::vector<char>& out);
    /// The same into memory the caller provides: room(count) must return space for count records
    /// (called once per DATA frame: raw payloads are then read straight into it, with no
    /// intermediate copy; zstd and cell-indexed payloads are read and checked first, then decoded
    /// into it). On a FormatError the room may hold part of a frame.
    std::optional<std::uint64_t> next_records(const std::function<void*(std::uint64_t count)>& room);
    std::uint64_t total() const { return total_; }
    /// DATA frames read so far that were cell-indexed, and the payload bytes of all DATA frames.
    std::uint64_t cell_frames() const { return cell_frames_; }
    std::uint64_t data_bytes() const { return data_bytes_; }
    const std::string& name() const { return name_; }

private:
    bool read_exact(void* p, std::size_t n);  // false on clean EOF at start
    /// Reads a frame's `bytes` payload bytes into buf, which grows only as they arrive (doubling
    /// from kProvenBytes): a header's claim takes no memory before the data proves it.
    void read_proven(std::vector<char>& buf, std::size_t bytes);
    /// Decompresses a zstd payload that claims `raw` bytes into buf, which grows only as the
    /// decompressed bytes arrive; FormatError unless it gives exactly `raw`.
    void decompress_proven(const std::vector<char>& in, std::size_t raw, std::vector<char>& buf);
    std::FILE* f_;
    std::string name_;
    RecordKind kind_;
    std::uint32_t flags_ = 0;
    std::size_t rsize_ = 0;
    StreamMeta meta_;
    std::uint64_t total_ = 0;
    std::uint64_t cell_frames_ = 0, data_bytes_ = 0;
    bool ended_ = false;
    bool stop_at_segments_ = false, at_segment_ = false;
    std::uint64_t segments_ = 0;
    StreamMeta segment_;  // the keys of the segment frame read last
    // a DATA frame read ahead by read_meta
    bool pending_ = false;
    std::uint64_t pending_count_ = 0;
    std::vector<char> pending_buf_;
    std::vector<char> stored_;
    std::vector<char> staged_;  // a large frame's records, proven before the caller's room takes them
    SampleCellDecoder cells_;
};

}  // namespace meshless
