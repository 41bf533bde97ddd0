#include "formats/ply_mesh.hpp"
#include "formats/text_header.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "formats/ply.hpp"
#include "kernels/errors.hpp"

namespace meshless {

void write_ply_mesh(const Mesh& mesh, const std::string& path) {
    if (mesh.xyz.size() % 3 != 0 || mesh.tri.size() % 3 != 0)
        throw std::invalid_argument(path + ": mesh arrays are not multiples of 3");
    const bool normals = !mesh.normals.empty();
    if (normals && mesh.normals.size() != mesh.xyz.size())
        throw std::invalid_argument(path + ": mesh has " + std::to_string(mesh.normals.size()) +
                                    " normal floats for " + std::to_string(mesh.xyz.size()) + " position floats");
    const std::size_t nv = mesh.vertex_count(), nf = mesh.triangle_count();
    if (nv > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
        throw std::length_error(path + ": more than 2^31-1 vertices do not fit PLY int indices");
    for (std::uint32_t i : mesh.tri)
        if (i >= nv)
            throw std::invalid_argument(path + ": triangle index " + std::to_string(i) +
                                        " out of range (" + std::to_string(nv) + " vertices)");

    PlyHeader h;
    h.encoding = PlyEncoding::binary_little_endian;
    h.comments = {"meshless marching cubes"};
    PlyElement v{"vertex", nv, {}, 0};
    for (const char* n : {"x", "y", "z"}) v.props.push_back({n, StoredType::f32, false, StoredType::u8});
    if (normals)
        for (const char* n : {"nx", "ny", "nz"}) v.props.push_back({n, StoredType::f32, false, StoredType::u8});
    const bool blocks = !mesh.block.empty();
    if (blocks && mesh.block.size() != nf)
        throw std::invalid_argument(path + ": mesh has " + std::to_string(mesh.block.size()) + " block ids for " +
                                    std::to_string(nf) + " triangles");
    PlyElement f{"face", nf, {{"vertex_indices", StoredType::i32, true, StoredType::u8}}, 0};
    if (blocks) f.props.push_back({"block", StoredType::u32, false, StoredType::u8});
    h.elements = {v, f};
    PlyWriter out(path, std::move(h), PlyCounts::declared);

    // packed host-order records, in pieces of 64 Ki
    constexpr std::size_t kChunk = std::size_t(1) << 16;
    std::vector<unsigned char> buf;
    buf.reserve(kChunk * 24);
    for (std::size_t b = 0; b < nv; b += kChunk) {
        const std::size_t e = std::min(nv, b + kChunk);
        buf.clear();
        for (std::size_t i = b; i < e; ++i) {
            const auto* p = reinterpret_cast<const unsigned char*>(&mesh.xyz[3 * i]);
            buf.insert(buf.end(), p, p + 12);
            if (normals) {
                const auto* q = reinterpret_cast<const unsigned char*>(&mesh.normals[3 * i]);
                buf.insert(buf.end(), q, q + 12);
            }
        }
        out.append(buf.data(), buf.size());
    }
    for (std::size_t b = 0; b < nf; b += kChunk) {
        const std::size_t e = std::min(nf, b + kChunk);
        buf.clear();
        for (std::size_t t = b; t < e; ++t) {
            buf.push_back(3);
            const std::int32_t idx[3] = {static_cast<std::int32_t>(mesh.tri[3 * t]), static_cast<std::int32_t>(mesh.tri[3 * t + 1]),
                                         static_cast<std::int32_t>(mesh.tri[3 * t + 2])};
            const auto* p = reinterpret_cast<const unsigned char*>(idx);
            buf.insert(buf.end(), p, p + 12);
            if (blocks) {
                const auto* q = reinterpret_cast<const unsigned char*>(&mesh.block[t]);
                buf.insert(buf.end(), q, q + 4);
            }
        }
        out.append(buf.data(), buf.size());
    }
    out.commit();
}

Mesh read_ply_mesh(const std::string& path) {
    PlyReader r(path);
    const PlyHeader& h = r.header();
    const int vi = h.find("vertex");
    if (vi < 0) throw FormatError(path + ": PLY file has no vertex element");
    const PlyElement& V = h.elements[static_cast<std::size_t>(vi)];
    int slot[6];
    const char* names[6] = {"x", "y", "z", "nx", "ny", "nz"};
    for (int s = 0; s < 6; ++s) {
        slot[s] = V.find(names[s]);
        if (slot[s] >= 0 && V.props[slot[s]].is_list)
            throw FormatError(path + ": line " + std::to_string(V.line) + ": PLY vertex property '" + names[s] + "' is a list");
    }
    if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0) throw FormatError(path + ": line " + std::to_string(V.line) + ": PLY vertex element lacks x, y or z");
    const int nn = (slot[3] >= 0) + (slot[4] >= 0) + (slot[5] >= 0);
    if (nn != 0 && nn != 3) throw FormatError(path + ": line " + std::to_string(V.line) + ": PLY vertex has some but not all of nx ny nz");
    const int fi = h.find("face");
    int list_prop = -1, block_prop = -1;
    if (fi >= 0) {
        const PlyElement& F = h.elements[static_cast<std::size_t>(fi)];
        for (const char* n : {"vertex_indices", "vertex_index"})
            if (list_prop < 0 && F.find(n) >= 0 && F.props[F.find(n)].is_list) list_prop = F.find(n);
        block_prop = F.find("block");
        if (block_prop >= 0 && F.props[static_cast<std::size_t>(block_prop)].is_list)
            throw FormatError(path + ": line " + std::to_string(F.line) + ": PLY face property 'block' is a list");
        if (F.count > 0 && list_prop < 0) throw FormatError(path + ": line " + std::to_string(F.line) + ": PLY face element lacks vertex_indices");
        if (fi < vi && F.count > 0) throw FormatError(path + ": line " + std::to_string(h.elements[fi].line) + ": PLY face element before the vertex element");
    }

    Mesh mesh;
    const std::uint64_t nv = V.count;
    r.skip_to(static_cast<std::size_t>(vi));
    PlyRecord rec;
    std::vector<double> vals;
    const std::size_t np = V.props.size();
    auto add_vertex = [&](const double* q) {
        float f[6];
        for (int s = 0; s < 6; ++s) {
            const double x = slot[s] >= 0 ? q[slot[s]] : 0.0;
            if (!std::isfinite(x)) throw FormatError(r.where() + "non-finite PLY vertex " + names[s]);
            f[s] = static_cast<float>(x);
        }
        mesh.xyz.insert(mesh.xyz.end(), f, f + 3);
        if (nn) mesh.normals.insert(mesh.normals.end(), f + 3, f + 6);
    };
    if (!V.has_lists()) {
        while (r.element() == static_cast<std::size_t>(vi)) {
            const std::size_t n = r.read_values(vals, 65536);
            for (std::size_t i = 0; i < n; ++i) add_vertex(&vals[i * np]);
        }
    } else {
        while (r.element() == static_cast<std::size_t>(vi) && r.read_record(rec)) add_vertex(rec.values.data());
    }
    if (fi > vi) {
        r.skip_to(static_cast<std::size_t>(fi));
        std::uint64_t face = 0;
        while (r.element() == static_cast<std::size_t>(fi) && r.read_record(rec)) {
            const std::vector<double>& l = rec.lists[list_prop];
            if (l.size() < 3)
                throw FormatError(r.where() + "PLY face " + std::to_string(face) + " has fewer than 3 vertices");
            std::uint32_t block = 0;
            if (block_prop >= 0) {
                const double bv = rec.values[static_cast<std::size_t>(block_prop)];
                if (!(bv >= 0 && bv <= 4294967295.0) || bv != std::floor(bv))
                    throw FormatError(r.where() + "PLY face " + std::to_string(face) + " block id is not a 32-bit unsigned integer");
                block = static_cast<std::uint32_t>(bv);
            }
            std::uint32_t first = 0, prev = 0;
            for (std::size_t q = 0; q < l.size(); ++q) {
                if (!(l[q] >= 0 && l[q] < static_cast<double>(nv)) || l[q] != std::floor(l[q]))
                    throw FormatError(r.where() + "PLY face " + std::to_string(face) + " vertex index " +
                                      number_text(l[q]) + " out of range (" + std::to_string(nv) +
                                      " vertices)");
                const auto idx = static_cast<std::uint32_t>(l[q]);
                if (q == 0) first = idx;
                else if (q >= 2) {
                    mesh.tri.insert(mesh.tri.end(), {first, prev, idx});
                    if (block_prop >= 0) mesh.block.push_back(block);
                }
                prev = idx;
            }
            ++face;
        }
    }
    r.finish();
    return mesh;
}

}  // namespace meshless
