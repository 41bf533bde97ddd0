#include "kernels/crack_edges.hpp"

#include <algorithm>
#include <bit>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

namespace meshless {

namespace {
struct Key {
    std::uint32_t x, y, z;
    bool operator==(const Key&) const = default;
};
struct KeyHash {
    std::size_t operator()(const Key& k) const {
        std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
        h ^= (h >> 29) + k.y * 0xBF58476D1CE4E5B9ull;
        h ^= (h >> 31) + k.z * 0x94D049BB133111EBull;
        return static_cast<std::size_t>(h ^ (h >> 32));
    }
};
std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f + 0.0f); }  // -0 -> +0
}  // namespace

WeldedMesh weld_by_position(const Mesh& m) {
    if (m.xyz.size() % 3 || m.tri.size() % 3) throw std::invalid_argument("weld_by_position: arrays are not multiples of 3");
    if (!m.block.empty() && m.block.size() != m.triangle_count())
        throw std::invalid_argument("weld_by_position: block ids of another count than the triangles");
    const std::size_t nv = m.vertex_count();
    std::unordered_map<Key, std::uint32_t, KeyHash> id;
    id.reserve(nv);
    std::vector<std::uint32_t> remap(nv);
    WeldedMesh w;
    for (std::size_t v = 0; v < nv; ++v) {
        const Key k{bits(m.xyz[3 * v]), bits(m.xyz[3 * v + 1]), bits(m.xyz[3 * v + 2])};
        const auto [it, fresh] = id.try_emplace(k, static_cast<std::uint32_t>(w.xyz.size() / 3));
        if (fresh) w.xyz.insert(w.xyz.end(), {double(m.xyz[3 * v]), double(m.xyz[3 * v + 1]), double(m.xyz[3 * v + 2])});
        remap[v] = it->second;
    }
    w.tri.resize(m.tri.size());
    for (std::size_t i = 0; i < m.tri.size(); ++i) {
        if (m.tri[i] >= nv) throw std::invalid_argument("weld_by_position: triangle index out of range");
        w.tri[i] = remap[m.tri[i]];
    }
    w.block = m.block;
    if (w.block.empty()) w.block.assign(m.triangle_count(), 0);
    return w;
}

CrackEdgeStats edge_census(const WeldedMesh& m, std::vector<BoundaryEdge>& boundary) {
    const std::size_t nt = m.tri.size() / 3;
    if (m.block.size() != nt) throw std::invalid_argument("edge_census: block ids of another count than the triangles");
    if (m.tri.size() % 3) throw std::invalid_argument("edge_census: triangle indices are not a multiple of 3");
    const std::size_t nv = m.xyz.size() / 3;
    CrackEdgeStats st;
    st.vertices = static_cast<std::int64_t>(nv);
    boundary.clear();
    struct Edge {
        std::uint32_t a, b, t;
    };
    std::vector<Edge> e;
    e.reserve(3 * nt);
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t* v = &m.tri[3 * t];
        if (v[0] >= nv || v[1] >= nv || v[2] >= nv) throw std::invalid_argument("edge_census: triangle index out of range");
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
            ++st.degenerate_triangles;
            continue;
        }
        for (int q = 0; q < 3; ++q) {
            const std::uint32_t a = v[q], b = v[(q + 1) % 3];
            e.push_back({std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(t)});
        }
    }
    std::sort(e.begin(), e.end(), [](const Edge& x, const Edge& y) { return std::tie(x.a, x.b, x.t) < std::tie(y.a, y.b, y.t); });
    for (std::size_t i = 0; i < e.size();) {
        std::size_t j = i + 1;
        while (j < e.size() && e[j].a == e[i].a && e[j].b == e[i].b) ++j;
        ++st.edges;
        if (j - i >= 3) ++st.nonmanifold_edges;
        if (j - i == 1) {
            ++st.boundary_edges;
            const double* p = &m.xyz[3 * e[i].a];
            const double* q = &m.xyz[3 * e[i].b];
            boundary.push_back({Vec3{0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])}, m.block[e[i].t]});
        }
        i = j;
    }
    return st;
}

CrackEdgeStats count_crack_edges(const WeldedMesh& m,
                                 const std::function<bool(const Vec3& midpoint, std::uint32_t own_block)>& inside_other) {
    std::vector<BoundaryEdge> boundary;
    CrackEdgeStats st = edge_census(m, boundary);
    for (const BoundaryEdge& b : boundary)
        if (inside_other(b.midpoint, b.block)) ++st.crack_edges;
    return st;
}

}  // namespace meshless
