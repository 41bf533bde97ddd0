#include "stream/mesh_sink.hpp"

#include "kernels/mesh_normals.hpp"

#include <limits>
#include <stdexcept>

#include "formats/ply_mesh.hpp"
#include "formats/vtp_writer.hpp"
#include "kernels/errors.hpp"

namespace meshless {

void MeshWeldSink::consume(Batch&& b) {
    const Mesh& m = b.mesh;
    const std::size_t n = m.vertex_count();
    remap_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (mesh_.vertex_count() >= std::numeric_limits<std::uint32_t>::max())
            throw std::length_error("marching cubes: more than 2^32-1 vertices (uint32 indices)");
        const auto fresh = static_cast<std::uint32_t>(mesh_.vertex_count());
        if (i < b.mesh_seam.size() && b.mesh_seam[i] != Batch::kNoSeam) {
            const auto [it, inserted] = seam_.emplace(b.mesh_seam[i], fresh);
            if (!inserted) {
                remap_[i] = it->second;
                continue;
            }
        }
        remap_[i] = fresh;
        mesh_.xyz.insert(mesh_.xyz.end(), &m.xyz[3 * i], &m.xyz[3 * i] + 3);
        if (!m.normals.empty()) mesh_.normals.insert(mesh_.normals.end(), &m.normals[3 * i], &m.normals[3 * i] + 3);
    }
    for (std::uint32_t t : m.tri) mesh_.tri.push_back(remap_[t]);
    if (!m.block.empty() || !mesh_.block.empty()) {
        if (m.block.size() != m.triangle_count() || mesh_.block.size() + m.block.size() != mesh_.triangle_count())
            throw FormatError("mesh writer: mesh pieces with and without block ids mixed");
        mesh_.block.insert(mesh_.block.end(), m.block.begin(), m.block.end());
    }
}

void MeshWeldSink::finish() {
    if (path_.empty()) return;
    // a mesh file carries vertex normals (ParaView and MeshLab shade with them, else faceted):
    // pieces without (the naive multiblock marching cubes) get the area-weighted normals of their
    // welded triangles, the same in the PLY and the VTP
    if (mesh_.normals.empty() && !mesh_.tri.empty()) mesh_.normals = area_weighted_normals(mesh_);
    if (format_ == GeometryFormat::vtp) write_vtp_mesh(mesh_, path_, {"meshless marching cubes"}, vtp_);
    else write_ply_mesh(mesh_, path_);
}

}  // namespace meshless
