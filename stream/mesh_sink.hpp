// The sink of the marching-cubes graph (stream/marching_cubes_stage.hpp): appends each mesh piece,
// welding the vertices it shares with earlier pieces by their grid-edge key (Batch::mesh_seam), and
// on finish() writes the mesh as a binary PLY (formats/ply_mesh.hpp) or VTK XML PolyData
// (formats/vtp_writer.hpp), temporary name + rename (no path: keeps it for mesh()). Memory: the welded mesh (a PLY mesh needs its counts up front) and
// the keys of seam vertices. Pieces without normals (the naive multiblock marching cubes) give
// PLY and VTP meshes with area-weighted ones (kernels/mesh_normals.hpp; finish() stores them in
// mesh(), so it holds them after a file is written; without a path it stays without); per-triangle block ids (Mesh::block) are carried into the mesh (a piece
// with them after one without, or the reverse, is a FormatError). Throws FormatError on non-mesh batches, std::length_error beyond 2^32-1
// vertices, and what write_ply_mesh / write_vtp_mesh throw. Not thread-safe (the runner calls it serially).
#pragma once
#include <string>
#include <unordered_map>

#include "formats/geometry_format.hpp"
#include "formats/vtp_writer.hpp"
#include "stream/stage.hpp"

namespace meshless {

class MeshWeldSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::mesh; }
    /// vtp: the VTP writer's settings (compression, compressing threads), unused for PLY.
    explicit MeshWeldSink(std::string path = {}, GeometryFormat format = GeometryFormat::ply, VtpOptions vtp = {})
        : path_(std::move(path)), format_(format), vtp_(vtp) {}
    void consume(Batch&& b) override;
    void finish() override;
    const Mesh& mesh() const { return mesh_; }
    /// Ends one surface of several (marching cubes at several isovalues): the next pieces' seam
    /// vertices are welded among themselves only, never to this surface's.
    void end_surface() { seam_.clear(); }

private:
    std::string path_;
    GeometryFormat format_;
    VtpOptions vtp_;
    Mesh mesh_;
    std::unordered_map<std::uint64_t, std::uint32_t> seam_;
    std::vector<std::uint32_t> remap_;
};

}  // namespace meshless
