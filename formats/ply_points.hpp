// Oriented point sets as binary little-endian PLY (the product's point-set output).
//
// Vertex element with float properties x y z nx ny nz radius value: exactly the bytes of
// PointRecord, so writing is a memcpy. MeshLab, ParaView and VTK's vtkPLYReader open it (extra
// properties are ignored by readers that do not know them). The vertex count is patched into a
// fixed-width header at the end, so points can be streamed without holding them all.
// Output goes through AtomicFile (temporary name + rename; "-" = stdout, where the count must be
// known up front: use write_ply_points for that). Throws IoError naming the path.
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

}  // namespace meshless
