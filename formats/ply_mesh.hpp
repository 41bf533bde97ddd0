// Triangle meshes (marching cubes output, dissertation §3.6 baseline) as PLY.
//
// write_ply_mesh: binary little endian; element vertex with float x y z and, when the mesh has
// normals (normals.size() == xyz.size()), float nx ny nz; element face with
// "property list uchar int vertex_indices" (3 per face). Goes through AtomicFile ("-" = stdout).
// Throws IoError (BrokenPipe on a closed stdout) naming the path, std::invalid_argument when the
// mesh arrays are inconsistent (xyz not a multiple of 3, normals of another size, an index out of
// range) and std::length_error when there are more than 2^31-1 vertices (int indices).
// read_ply_mesh (mainly for tests): binary little endian or ASCII 1.0; any scalar property types,
// extra properties and elements are skipped; x y z required, nx ny nz optional (all three or none);
// faces with more than 3 vertices are fan-triangulated. Throws IoError when the file cannot be read
// and FormatError ("PATH: what") on a malformed header, a truncated body, garbage numbers, an index
// out of range, or binary big endian (unsupported).
// Thread-safety: reentrant (no shared state).
#pragma once
#include <string>

#include "kernels/marching_cubes.hpp"

namespace meshless {

void write_ply_mesh(const Mesh& mesh, const std::string& path);
Mesh read_ply_mesh(const std::string& path);

}  // namespace meshless
