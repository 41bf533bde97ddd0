// Oriented point sets and triangle meshes as VTK XML PolyData (.vtp), the file ParaView and VTK open
// directly (vtkXMLPolyDataReader). The product's outputs of dissertation §3.5-3.6 (points) and the
// marching-cubes baseline (mesh), for VTK users; the PLY writers (formats/ply_points.hpp,
// formats/ply_mesh.hpp) write the same data for MeshLab.
//
// File layout: <VTKFile type="PolyData" version="1.0" byte_order="LittleEndian"
// header_type="UInt64" [compressor="vtkZLibDataCompressor"]>, one <Piece>, every DataArray
// format="appended" in one raw <AppendedData> section. Compressed arrays use VTK's block format:
// UInt64 header [nblocks, block_size, last_block_size (0: the last block is full),
// compressed_size_0 .. compressed_size_{nblocks-1}], then the zlib streams, one per block of
// `block_size` raw bytes; uncompressed arrays are [UInt64 byte count][bytes]. Positions and
// normals are Huffman-coded only (Z_HUFFMAN_ONLY, 3x faster) where zlib's string matching gains
// less than 3%, decided by every 8th block (compressed both ways); the bytes depend on the data
// only, never on batching or threads.
//   Points:  Points (Float32 x3); Verts (one vertex cell per point: connectivity 0..n-1, offsets
//            1..n, Int32 below 2^31 points, else Int64); PointData Normals (Float32 x3, the
//            Normals attribute), radius (Float32, splat radius, world units), both left out when
//            VtpOptions::oriented is false, value (Float32, the Scalars attribute) and, when the
//            points carry block ids, block (UInt32).
//   Meshes:  Points (Float32 x3); Polys (triangles: connectivity = Mesh::tri, offsets 3, 6, ...,
//            in the mesh's winding: counter-clockwise seen from the normal side, VTK's convention);
//            PointData Normals when the mesh has normals; CellData block (UInt32) when it has
//            per-triangle block ids.
// Comments (the stream's provenance: command line, isovalue, bounds) go into XML comments before
// <VTKFile>, with bytes outside printable ASCII escaped (\xNN) and "--" broken up as XML requires.
//
// Memory: the writers never hold the whole output. Each array goes, block by block as it arrives,
// compressed into its own unlinked temporary file in $TMPDIR (else /tmp); commit() writes the XML
// header (which needs the counts and offsets) and then copies the arrays behind it. Memory = the
// raw and compressed blocks of one appended batch (or of hardware_concurrency blocks, 2..16, of a mesh or cell array) + 8 bytes per
// block of compressed-size table (1/32768 of the raw data with the default block size). Full
// blocks are compressed in parallel on up to VtpOptions::threads threads (each block alone, so
// the bytes do not depend on the thread count). The output goes through AtomicFile (temporary name + rename; "-" = stdout,
// written in full at commit()); nothing is left behind by an exception or a signal (the spool
// files are unlinked at creation).
// Throws IoError naming the path (output) or the spool file (temporary) when a write fails,
// FormatError when points with and without block ids are mixed, std::invalid_argument on an
// inconsistent Mesh (like write_ply_mesh) and std::length_error beyond 2^63 bytes.
// Thread-safety: one writer per object, not thread-safe; distinct writers are independent. Output
// bytes depend only on the data appended (identical for any thread count upstream).
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/marching_cubes.hpp"
#include "kernels/records.hpp"

namespace meshless {

enum class VtpCompression { none, zlib };

struct VtpOptions {
    VtpCompression compression = VtpCompression::zlib;
    int zlib_level = 1;                     ///< 1 (fastest) .. 9 (level 6 was 2x slower, 0.6% smaller on points)
    std::size_t block_size = 1u << 18;      ///< raw bytes per compressed block (VTK reads any size)
    int threads = 0;                        ///< compressing threads (0: hardware_concurrency); bytes do not depend on it
    /// Points only: true writes the Normals and radius arrays; false leaves them out (samples that
    /// are not oriented splats, e.g. a cluster tree's level of detail: PointData value only).
    bool oriented = true;
    /// Points: the name of the value array (the PointData's active scalars): the array the values
    /// are, e.g. "temperature" for an isosurface coloured by it. Empty gives "value"; a name the other
    /// arrays take (Normals, radius, block, ...) gets "_value" appended ("radius_value").
    std::string value_name = "value";
};

class VtpPointWriter {
public:
    /// comments: provenance lines (see above). Creates the output's temporary and the spools.
    VtpPointWriter(const std::string& path, const std::vector<std::string>& comments, VtpOptions options = {});
    ~VtpPointWriter();
    VtpPointWriter(const VtpPointWriter&) = delete;
    VtpPointWriter& operator=(const VtpPointWriter&) = delete;

    /// Appends points; blocks: empty or one id per point, the same choice for every non-empty call
    /// (FormatError otherwise).
    void append(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks = {});
    /// Writes header + arrays and renames into place. No appends after.
    void commit();
    std::uint64_t count() const { return count_; }
    bool has_blocks() const;

private:
    struct Impl;
    std::unique_ptr<Impl> d_;
    std::uint64_t count_ = 0;
};

/// Whole mesh at once (Mesh::normals optional, Mesh::block optional).
void write_vtp_mesh(const Mesh& mesh, const std::string& path, const std::vector<std::string>& comments = {},
                    VtpOptions options = {});

}  // namespace meshless
