// Triangle rasterizer: draws a triangle mesh (marching cubes output, the dissertation's §3.6
// baseline) with the splat renderer's camera, shading and colours, so a mesh PLY and a point set of
// the same surface give comparable pictures (meshless splat MESH.ply).
//
// Camera: make_view(cam, bounds[0], bounds[1]) (kernels/camera.hpp), exactly as the splat renderer.
// Rasterisation: vertex screen positions are snapped to 1/256 pixel (integers) and the edge
//   functions evaluated exactly in 64-bit integers at pixel centres (i + 0.5, j + 0.5); a centre on
//   an edge belongs to the triangle only when that edge is a top or left edge (top-left fill rule),
//   so triangles sharing an edge cover each pixel of their union exactly once (no cracks, no double
//   draws). Triangles are drawn whatever their screen winding (no back-face culling). A triangle with
//   a vertex behind the near plane (ViewTransform::near_depth), a non-finite or out-of-range index,
//   a non-finite coordinate, or a vertex more than 2^21 pixels from the image centre is skipped (never the
//   case for a mesh inside the framed bounds).
// Interpolation: perspective-correct barycentrics (weights l_i / depth_i, renormalised; orthographic:
//   the screen-linear ones) of the depth, the camera-space position and the vertex normals. Without
//   vertex normals (Mesh::normals empty) each triangle is flat-shaded with its geometric normal
//   (b - a) x (c - a) (VTK: counter-clockwise seen from the normal side).
// Depth: a float z-buffer of the interpolated depth (distance from the eye along -z); a fragment is
//   kept when strictly nearer, so with equal depths the earlier triangle wins: the picture depends
//   on the triangle order, which is fixed by the mesh (the same mesh gives the same bytes).
// Shading: the splat renderer's Lambert + Phong (kernels/shading.hpp, ShadingParams), two-sided
//   (the normal is flipped towards the viewer), per pixel with the interpolated normal; uncovered
//   pixels get ShadingParams::background.
// Colours (ShadingParams::color_by): none (ShadingParams::base), normal ((n + 1) / 2 of the
//   interpolated world-space normal), block (categorical_color of Mesh::block of the triangle; 0
//   without block ids). value is not available (a mesh carries no values): drawn as none.
// Cost: O(triangles + covered pixels of their bounding boxes); buffers: 4 bytes of depth per pixel
//   and the image. Single-threaded.
// Throws nothing but std::bad_alloc.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "kernels/camera.hpp"
#include "kernels/marching_cubes.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

struct TriangleStats {
    std::int64_t triangles_drawn = 0;  ///< triangles rasterised (not skipped, bounding box on the image)
    std::int64_t fragments = 0;        ///< pixel centres inside a triangle (before the depth test)
};

/// Axis-aligned bounds of the mesh's finite vertices; {0,0,0},{0,0,0} when there are none.
std::array<Vec3, 2> mesh_bounds(const Mesh& mesh);

/// Renders `mesh` as seen by `cam` framing `bounds` (see above). coverage: when not null, resized
/// to width * height and incremented once per fragment (pixel centre inside a triangle, before the
/// depth test): the fill rule's test.
Image render_triangles(const Mesh& mesh, const Camera& cam, const ShadingParams& shading,
                       const std::array<Vec3, 2>& bounds, TriangleStats* stats = nullptr,
                       std::vector<std::uint32_t>* coverage = nullptr);

}  // namespace meshless
