#include "kernels/marching_cubes_table.hpp"

#include <stdexcept>

namespace meshless {
namespace {

struct I3 {
    int x, y, z;
};
constexpr I3 sub(I3 a, I3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr I3 cross3(I3 a, I3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr int dot3(I3 a, I3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Corner positions doubled so that edge midpoints are integers.
constexpr I3 corner2(int c) { return {2 * (c & 1), 2 * ((c >> 1) & 1), 2 * ((c >> 2) & 1)}; }
constexpr I3 edge_mid2(int e) {
    const I3 a = corner2(kMcEdgeCorners[e][0]), b = corner2(kMcEdgeCorners[e][1]);
    return {(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
}

// Direction factor of a segment p->q on face f whose endpoint p lies on the face edge (u,v):
// the boundary of a surface whose normal points to the above side runs along a x n_f, where a points
// from the below corner to the above corner of that edge and n_f is the outward face normal.
constexpr int orientation(int cs, const McFace& f, int u, int v, I3 t) {
    const bool u_above = (cs >> u) & 1;
    const I3 a = u_above ? sub(corner2(u), corner2(v)) : sub(corner2(v), corner2(u));
    I3 n{0, 0, 0};
    if (f.axis == 0) n.x = f.sign;
    if (f.axis == 1) n.y = f.sign;
    if (f.axis == 2) n.z = f.sign;
    return dot3(t, cross3(a, n));
}

constexpr McTable build_table() {
    McTable table{};
    for (int cs = 0; cs < 256; ++cs) {
        McCase mc{};
        int next[12];
        int incoming[12];
        for (int e = 0; e < 12; ++e) next[e] = -1, incoming[e] = 0;

        for (const McFace& f : kMcFaces) {
            int above[4];
            int edge[4];
            bool cross[4];
            int ncross = 0;
            for (int k = 0; k < 4; ++k) above[k] = (cs >> f.corners[k]) & 1;
            for (int k = 0; k < 4; ++k) {
                edge[k] = mc_edge_of(f.corners[k], f.corners[(k + 1) % 4]);
                cross[k] = above[k] != above[(k + 1) % 4];
                ncross += cross[k] ? 1 : 0;
            }
            int pairs[2][2]{};
            int npairs = 0;
            if (ncross == 2) {
                int found = 0;
                for (int k = 0; k < 4; ++k)
                    if (cross[k]) pairs[0][found++] = k;
                npairs = 1;
            } else if (ncross == 4) {
                // Ambiguous face: separate the above corners (cut each one off by its own segment).
                ++mc.ambiguous_faces;
                npairs = 2;
                if (above[0]) {
                    pairs[0][0] = 3, pairs[0][1] = 0;  // cuts corner 0
                    pairs[1][0] = 1, pairs[1][1] = 2;  // cuts corner 2
                } else {
                    pairs[0][0] = 0, pairs[0][1] = 1;  // cuts corner 1
                    pairs[1][0] = 2, pairs[1][1] = 3;  // cuts corner 3
                }
            } else if (ncross != 0) {
                throw std::logic_error("marching cubes table: odd number of face crossings");
            }
            for (int s = 0; s < npairs; ++s) {
                const int k1 = pairs[s][0], k2 = pairs[s][1];
                int from = edge[k1], to = edge[k2];
                const I3 t = sub(edge_mid2(to), edge_mid2(from));
                const int o1 =
                    orientation(cs, f, f.corners[k1], f.corners[(k1 + 1) % 4], t);
                const int o2 =
                    orientation(cs, f, f.corners[k2], f.corners[(k2 + 1) % 4], t);
                if (o1 == 0 || o2 == 0 || (o1 > 0) != (o2 > 0))
                    throw std::logic_error("marching cubes table: inconsistent segment orientation");
                if (o1 < 0) {
                    const int tmp = from;
                    from = to;
                    to = tmp;
                }
                if (next[from] != -1)
                    throw std::logic_error("marching cubes table: edge with two outgoing segments");
                next[from] = to;
                ++incoming[to];
            }
        }

        // Chain segments into closed polygons and triangulate each.
        bool used[12]{};
        int ntri = 0;
        for (int e = 0; e < 12; ++e) {
            if (next[e] != -1) mc.edge_mask = static_cast<std::uint16_t>(mc.edge_mask | (1u << e));
            if ((next[e] == -1) != (incoming[e] == 0) || incoming[e] > 1)
                throw std::logic_error("marching cubes table: open polygon");
        }
        for (int e = 0; e < 12; ++e) {
            if (next[e] == -1 || used[e]) continue;
            int poly[12]{};
            int n = 0;
            for (int x = e; !used[x]; x = next[x]) {
                used[x] = true;
                poly[n++] = x;
            }
            if (n < 3) throw std::logic_error("marching cubes table: degenerate polygon");
            ++mc.polygon_count;
            // Triangulate with diagonals that never lie in a cell face (two polygon vertices on
            // edges of one face): such a diagonal would lie in the face shared with the neighbour
            // cell, which may cut the same face the same way (overlapping, non-manifold triangles).
            // A fan from the first admissible apex when there is one, else ear clipping.
            int apex = -1;
            for (int s = 0; s < n && apex < 0; ++s) {
                bool ok = true;
                for (int k = 2; k + 1 < n; ++k)
                    if (mc_edges_share_face(poly[s], poly[(s + k) % n])) ok = false;
                if (ok) apex = s;
            }
            // The polygons run counter-clockwise seen from the above side; a triangle is stored
            // reversed, (a, c, b), so that it faces the below side (VTK's convention: normals
            // towards decreasing value, out of the region >= iso).
            auto emit = [&](int a, int b, int c) {
                if (ntri >= kMcMaxTriangles) throw std::logic_error("marching cubes table: too many triangles");
                mc.edges[3 * ntri + 0] = static_cast<std::uint8_t>(a);
                mc.edges[3 * ntri + 1] = static_cast<std::uint8_t>(c);
                mc.edges[3 * ntri + 2] = static_cast<std::uint8_t>(b);
                ++ntri;
            };
            if (apex >= 0) {
                for (int k = 1; k + 1 < n; ++k)
                    emit(poly[apex], poly[(apex + k) % n], poly[(apex + k + 1) % n]);
            } else {
                int m = n;
                while (m > 3) {
                    int ear = -1;
                    for (int s = 0; s < m && ear < 0; ++s)
                        if (!mc_edges_share_face(poly[(s + m - 1) % m], poly[(s + 1) % m])) ear = s;
                    if (ear < 0) throw std::logic_error("marching cubes table: no admissible triangulation");
                    emit(poly[(ear + m - 1) % m], poly[ear], poly[(ear + 1) % m]);
                    for (int q = ear; q + 1 < m; ++q) poly[q] = poly[q + 1];
                    --m;
                }
                emit(poly[0], poly[1], poly[2]);
            }
        }
        mc.triangle_count = static_cast<std::uint8_t>(ntri);
        if (ntri > table.max_triangles) table.max_triangles = ntri;
        table.cases[cs] = mc;
    }
    return table;
}

constexpr McTable kTable = build_table();

// Compile-time sanity: the empty and full cases have no surface, a lone corner gives one triangle,
// complementary single-corner cases have the same triangle count.
static_assert(kTable.cases[0].triangle_count == 0 && kTable.cases[255].triangle_count == 0);
static_assert(kTable.cases[1].triangle_count == 1 && kTable.cases[254].triangle_count == 1);
static_assert(kTable.cases[3].triangle_count == 2);  // two adjacent corners: a quad

}  // namespace

const McTable& marching_cubes_table() { return kTable; }

}  // namespace meshless
