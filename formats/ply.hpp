// The one PLY codec of meshless (Stanford polygon file format, version 1.0): the header model, its
// parser and formatter (ply_header.cpp), a streaming body reader (ply_reader.cpp) and a streaming
// writer (ply_writer.cpp). Every PLY the product reads or writes goes through here; the
// purpose-named wrappers are formats/ply_points.hpp (oriented points x y z nx ny nz radius value,
// dissertation §3.5-3.6 output), formats/points_ply.hpp (scattered points with a scalar, chapters
// 4-5 input) and formats/ply_mesh.hpp (marching-cubes triangle meshes, the §3.6 baseline).
//
// Header grammar accepted: "ply" (LF or CRLF line ends), exactly one "format ascii|binary_little_endian|
// binary_big_endian 1.0", "comment ...", "obj_info ...", "element NAME COUNT" (COUNT a decimal
// unsigned 64-bit integer), "property TYPE NAME", "property list CTYPE TYPE NAME" (CTYPE an integer
// type), blank lines, "end_header". Types: char uchar short ushort int uint float double and
// int8 uint8 int16 uint16 int32 uint32 float32 float64. Element and property names are unique.
// The header may be at most kPlyMaxHeaderBytes long.
//
// Bad input: FormatError, one line, "NAME: line N: what" (header, ASCII body) or "NAME: byte B: what"
// (binary body); bytes quoted from the file are escaped (ply_escape). Size arithmetic is checked:
// the smallest body the header implies (element counts x record sizes, overflow included) must fit
// in the bytes that follow the header when their number is known (regular files, memory); nothing
// is allocated from a count before the data proves it (reads are bounded by the caller's `max`).
// IoError when a file cannot be opened or read. Thread-safety: one reader/writer per thread;
// the free functions are reentrant.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "formats/stored_type.hpp"

namespace meshless {

class AtomicFile;

inline constexpr std::size_t kPlyMaxHeaderBytes = std::size_t(1) << 20;

enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

struct PlyProperty {
    std::string name;
    StoredType type = StoredType::f32;  ///< value type (list items for a list)
    bool is_list = false;
    StoredType count_type = StoredType::u8;  ///< list length type (lists only)
};

struct PlyElement {
    std::string name;
    std::uint64_t count = 0;
    std::vector<PlyProperty> props;
    std::size_t line = 0;  ///< header line of the element (parser output, for messages)
    bool has_lists() const;
    /// Bytes of one binary record (lists count only their length field).
    std::size_t min_record_bytes() const;
    /// Index of the property named `name`, or -1.
    int find(std::string_view name) const;
};

struct PlyHeader {
    PlyEncoding encoding = PlyEncoding::binary_little_endian;
    std::vector<std::string> comments;  ///< text after "comment ", trimmed; blank comments are dropped
    std::vector<std::string> obj_info;
    std::vector<PlyElement> elements;
    std::size_t header_bytes = 0;  ///< bytes up to and including the end_header line (parser output)
    std::size_t header_lines = 0;  ///< lines up to and including end_header (parser output)
    /// Index of the element named `name`, or -1.
    int find(std::string_view name) const;
};

/// "char", "uchar", ..., "double" (the classic names the writers emit); u64/i64 have none.
const char* ply_type_name(StoredType t);
/// The stored type of a PLY type name (both spellings), or nullopt.
std::optional<StoredType> ply_type(std::string_view name);
/// Bytes quoted in messages: printable ASCII kept, others as \xNN, at most `max` bytes then "...".
std::string ply_escape(std::string_view bytes, std::size_t max = 64);

/// Parses the header at the start of `bytes` (which must reach past end_header); `name` prefixes
/// messages. FormatError on any defect listed above.
PlyHeader parse_ply_header(std::string_view bytes, const std::string& name);

/// The header text of `h` (format, comments, obj_info, elements); a line feed inside a comment or
/// obj_info (a file name a producer quotes) is written as \x0a, every other byte as it is.
/// pad_counts: each element line is
/// followed by "comment" and spaces so that its count can later be rewritten in place with any
/// value up to 20 digits (ply_count_lines) without moving the body.
std::string format_ply_header(const PlyHeader& h, bool pad_counts);
/// "element NAME N\ncomment<pad>\n": the fixed-width element lines of a padded header.
std::string ply_count_lines(const std::string& element, std::uint64_t n);

/// One record of an element with lists (read_record): values[p] for scalar properties, lists[p]
/// for list properties (the other vector of each pair is empty).
struct PlyRecord {
    std::vector<double> values;
    std::vector<std::vector<double>> lists;
};

/// Streaming reader of a PLY file or of bytes in memory: header on construction, then the elements
/// in order. Memory: a 1 MiB buffer plus what the caller asks for.
class PlyReader {
public:
    /// A file ("-" is not accepted: a PLY needs a name); IoError when it cannot be opened.
    explicit PlyReader(const std::string& path);
    /// Bytes in memory (not copied; they must outlive the reader); `name` prefixes messages.
    PlyReader(std::string name, std::span<const std::byte> bytes);
    ~PlyReader();
    PlyReader(const PlyReader&) = delete;
    PlyReader& operator=(const PlyReader&) = delete;

    const PlyHeader& header() const;
    const std::string& name() const;
    /// Index of the element being read (header().elements.size() when all are read).
    std::size_t element() const;
    /// Records of the current element already read.
    std::uint64_t record() const;

    /// Moves to the first record of element e (>= element()), reading past what lies between.
    void skip_to(std::size_t e);
    /// Up to `max` records of the current element (no list properties) as doubles: the properties
    /// whose indices `columns` lists, in that order (empty: all, in header order); out is resized to
    /// n * columns (at most 32 MiB of values per call: n may be less than both `max` and the records
    /// left). Returns n (0 at the element's end). Every value of an ASCII record is parsed and checked
    /// (integer properties range-checked); NaN/Inf pass through (callers decide).
    std::size_t read_values(std::vector<double>& out, std::size_t max, std::span<const int> columns = {});
    /// Binary files, elements without lists: up to `max` records copied as they are stored (file
    /// byte order) into dst, which holds max * min_record_bytes(). Returns n.
    std::size_t read_raw(std::byte* dst, std::size_t max);
    /// The next record of the current element, lists included; false at its end. List lengths
    /// are checked against the bytes left before anything is allocated.
    bool read_record(PlyRecord& r);
    /// After the last element: FormatError when bytes follow (binary) or anything but whitespace
    /// (ASCII), unless allow_trailing; returns the number of trailing bytes.
    std::uint64_t finish(bool allow_trailing = false);
    /// True when the input's size is known (regular files, memory): the header's counts were then
    /// checked against it on construction, so allocating for them is safe.
    bool size_known() const;
    /// "NAME: byte B: " or "NAME: line N: " at the current position, for callers' messages.
    std::string where() const;

private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

/// Streaming writer: header on construction, records appended in element order, commit() renames
/// into place (AtomicFile: temporary + rename; "-" = stdout; destroyed without commit(): nothing is
/// left). PlyCounts::patched needs a seekable output (IoError otherwise). std::logic_error when the
/// declared counts are exceeded or not met at commit(). Throws IoError/BrokenPipe on write.
enum class PlyCounts {
    declared,         ///< the header's counts, written up front; commit() checks they were met
    declared_padded,  ///< the same, in a padded header (format_ply_header(h, true))
    patched,          ///< padded header; commit() writes the counts of the records appended
};

class PlyWriter {
public:
    PlyWriter(const std::string& path, PlyHeader header, PlyCounts counts);
    ~PlyWriter();
    PlyWriter(const PlyWriter&) = delete;
    PlyWriter& operator=(const PlyWriter&) = delete;
    /// Appends whole records of the current element (moving on to the next element when the current
    /// one's declared count is reached, unless counts are patched) given as packed host-order values in
    /// property order (a list: its length in the count type, then the items). Binary little endian
    /// on a little-endian host is written with one copy; other encodings are converted. `bytes`
    /// must end on a record boundary (std::invalid_argument otherwise).
    void append(const void* data, std::size_t bytes);
    /// PlyCounts::patched: ends the current element and starts the next one.
    void next_element();
    void commit();
    const std::string& path() const;
    /// Records appended to element e.
    std::uint64_t count(std::size_t e) const;

private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace meshless
