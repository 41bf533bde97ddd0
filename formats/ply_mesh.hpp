// Triangle meshes (marching cubes output, dissertation §3.6 baseline) as PLY: a thin wrapper of
// the PLY codec (formats/ply.hpp) for Mesh.
//
// write_ply_mesh: binary little endian; element vertex with float x y z and, when the mesh has
// normals (normals.size() == xyz.size()), float nx ny nz; element face with
// "property list uchar int vertex_indices" (3 per face, in the mesh's winding: marching cubes winds
// counter-clockwise seen from the normal side, VTK's convention) and, when the mesh has block ids
// (Mesh::block, one per triangle), "property uint block". Goes through AtomicFile ("-" = stdout).
// Throws IoError (BrokenPipe on a closed stdout) naming the path, std::invalid_argument when the
// mesh arrays are inconsistent (xyz not a multiple of 3, normals of another size, an index out of
// range, block ids of another count than the triangles) and std::length_error when there are more than 2^31-1 vertices (int indices).
// read_ply_mesh (mainly for tests): any encoding the codec reads; any scalar property types, extra
// properties and elements are skipped; x y z required, nx ny nz optional (all three or none); a
// face property "block" (any integer type, not a list) fills Mesh::block (one per triangle);
// faces with more than 3 vertices are fan-triangulated. Throws IoError when the file cannot be read
// and FormatError ("PATH: ...") on the codec's defects, NaN/Inf coordinates, an index out of range,
// a face of fewer than 3 vertices, or a face element before the vertices.
// Thread-safety: reentrant (no shared state).
#pragma once
#include <string>

#include "kernels/marching_cubes.hpp"

namespace meshless {

void write_ply_mesh(const Mesh& mesh, const std::string& path);
Mesh read_ply_mesh(const std::string& path);

}  // namespace meshless
