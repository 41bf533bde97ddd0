// Oriented point sets as PLY (the product's point-set output, dissertation §3.5-3.6): a thin
// wrapper of the PLY codec (formats/ply.hpp) for PointRecord.
//
// Written as binary little endian, vertex element with float properties x y z nx ny nz radius
// value: exactly the bytes of PointRecord, so writing is one copy. MeshLab, ParaView and VTK's
// vtkPLYReader open it. The vertex count sits in a fixed-width (padded) header and is patched at the
// end, so points can be streamed without holding them all. Output goes through AtomicFile
// (temporary name + rename; "-" = stdout, where the count must be known up front: use
// write_ply_points for that). Throws IoError naming the path.
// Multiblock/AMR point sets (dissertation chapter 4) add a ninth property, `uint block`: the id of
// the block each point was seeded in (ParaView and MeshLab colour by it); such files are written
// with_blocks, and read back with their block ids (PlyPoints::block, PlyPointReader::read).
// `--ply-color` adds `uchar red green blue` last (readers that drop unknown properties, such as
// vtkPLYReader, keep these); the point reader ignores them.
// The reader accepts binary little/big endian and ASCII PLY (formats/ply.hpp) whose vertex
// element has at least x y z (any numeric types, no lists); missing nx ny nz, radius or value read
// as 0; elements before the vertices are skipped, elements after them are not read. A binary
// little-endian file with exactly the properties written above is read with bulk copies.
// NaN/Inf values pass through. Throws FormatError as the codec does (the file and the byte or line).
#pragma once
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "kernels/records.hpp"

namespace meshless {

class PlyWriter;
class PlyReader;

class PlyPointWriter {
public:
    /// comments: extra "comment" lines (no newlines inside). with_blocks: a `uint block` property.
    /// with_colors: `uchar red green blue` after it (the colours vtkPLYReader and MeshLab show).
    /// count: the number of points that will be appended, when known up front: the header then
    /// declares it (as write_ply_points: the same bytes) and the output need not seek (stdout,
    /// FIFOs); without it the count is patched on commit().
    PlyPointWriter(const std::string& path, const std::vector<std::string>& comments, bool with_blocks = false,
                   bool with_colors = false, std::optional<std::uint64_t> count = std::nullopt);
    /// Any layout: blocks (pts.size(), or empty without blocks) and rgb (3 bytes a point, or empty
    /// without colours) as the writer was made; std::invalid_argument on a size mismatch.
    void append(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks, std::span<const std::uint8_t> rgb);
    ~PlyPointWriter();
    /// Without blocks; std::invalid_argument when the writer was made with_blocks.
    void append(std::span<const PointRecord> pts);
    /// With blocks (blocks.size() == pts.size()); std::invalid_argument when made without.
    void append(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks);
    /// Patches the vertex count and renames into place.
    void commit();
    std::uint64_t count() const { return count_; }

private:
    std::unique_ptr<PlyWriter> w_;
    bool blocks_ = false, colors_ = false;
    std::vector<char> packed_;
    std::uint64_t count_ = 0;
};

/// Whole point set at once (works for "-" too). `blocks` given (size pts.size(); empty when there
/// are no points) adds the `block` property; `rgb` given (3 bytes a point) the colours.
void write_ply_points(const std::string& path, std::span<const PointRecord> pts,
                      const std::vector<std::string>& comments,
                      std::optional<std::span<const std::uint32_t>> blocks = std::nullopt,
                      std::optional<std::span<const std::uint8_t>> rgb = std::nullopt);

struct PlyPoints {
    std::vector<PointRecord> points;
    std::vector<std::uint32_t> block;  ///< empty unless the vertices have a `block` property
    std::vector<std::string> comments;
};
PlyPoints read_ply_points(const std::string& path);

/// Streaming reader of the same files: the header is parsed (and its counts checked against the
/// file size) on construction, the vertices are read in pieces of at most `max` (memory = one
/// piece). Binary little-endian files with exactly the properties written above are read with one
/// bulk read per piece. When the vertices are the last element, the read that reaches the last
/// vertex reports trailing bytes (FormatError). Not thread-safe.
class PlyPointReader {
public:
    explicit PlyPointReader(const std::string& path);
    ~PlyPointReader();
    const std::vector<std::string>& comments() const;
    /// Vertices the header declares.
    std::uint64_t count() const;
    const std::string& path() const;
    /// The file's size is known (a regular file): count() was checked against it.
    bool size_known() const;
    /// The vertices have a `block` property (an integer type; values must be 0..2^32-1).
    bool has_blocks() const;
    /// Byte offset of the first vertex when the file is a regular file whose first element is the
    /// vertices stored exactly as PointRecords (binary little endian, x y z nx ny nz radius value as
    /// float, no block): vertex i is then the 32 bytes at offset + 32 i. Else nullopt.
    std::optional<std::uint64_t> records_offset() const;
    /// Replaces out with the next up to max points; returns how many (0 at the end). With
    /// `blocks`, it is replaced by their block ids when has_blocks() (else cleared); a block value
    /// that is not an integer in 0..2^32-1 is a FormatError.
    std::size_t read(std::vector<PointRecord>& out, std::size_t max, std::vector<std::uint32_t>* blocks = nullptr);

private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace meshless
