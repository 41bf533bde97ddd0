// Oriented point sets as binary little-endian PLY (the product's point-set output).
//
// Vertex element with float properties x y z nx ny nz radius value: exactly the bytes of
// PointRecord, so writing is a memcpy. MeshLab, ParaView and VTK's vtkPLYReader open it (extra
// properties are ignored by readers that do not know them). The vertex count is patched into a
// fixed-width header at the end, so points can be streamed without holding them all.
// Output goes through AtomicFile (temporary name + rename; "-" = stdout, where the count must be
// known up front: use write_ply_points for that; PlyPointWriter on "-" throws InvalidArgument).
// Throws IoError naming the path.
// The reader accepts binary little/big endian and ASCII PLY with at least x y z; missing nx ny nz,
// radius or value read as 0; throws FormatError on a malformed header or truncated body.
#pragma once
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/records.hpp"

namespace meshless {

class AtomicFile;

class PlyPointWriter {
public:
    /// comments: extra "comment" lines (no newlines inside).
    PlyPointWriter(const std::string& path, const std::vector<std::string>& comments);
    ~PlyPointWriter();
    void append(std::span<const PointRecord> pts);
    /// Patches the vertex count and renames into place.
    void commit();
    std::uint64_t count() const { return count_; }

private:
    std::unique_ptr<AtomicFile> file_;
    std::size_t count_offset_ = 0;
    std::uint64_t count_ = 0;
};

/// Whole point set at once (works for "-" too).
void write_ply_points(const std::string& path, std::span<const PointRecord> pts,
                      const std::vector<std::string>& comments);

struct PlyPoints {
    std::vector<PointRecord> points;
    std::vector<std::string> comments;
};
PlyPoints read_ply_points(const std::string& path);

/// Streaming reader of the same files: the header is parsed on construction, the vertices are
/// read in pieces of at most `max` (memory = one piece). Binary little-endian files with exactly
/// the properties written above are read with one bulk read per piece. Throws as read_ply_points
/// (FormatError naming the file and the vertex; trailing bytes are reported by the read that
/// reaches the last vertex). Not thread-safe.
class PlyPointReader {
public:
    explicit PlyPointReader(const std::string& path);
    ~PlyPointReader();
    const std::vector<std::string>& comments() const;
    /// Vertices the header declares.
    std::uint64_t count() const;
    const std::string& path() const;
    /// Replaces out with the next up to max points; returns how many (0 at the end).
    std::size_t read(std::vector<PointRecord>& out, std::size_t max);

private:
    struct Impl;
    std::unique_ptr<Impl> d_;
};

}  // namespace meshless
