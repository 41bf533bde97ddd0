#include "formats/points_ply.hpp"

#include <algorithm>
#include <cmath>

#include "formats/ply.hpp"

namespace meshless {

namespace {

/// The vertex element and the columns read from it: x y z, then the scalar (-1: none).
struct PlyPointColumns {
    int vi = -1;
    int cols[4] = {-1, -1, -1, -1};
    int iv = -1;
    std::size_t count() const { return iv >= 0 ? 4 : 3; }
};

PlyPointColumns ply_point_columns(const PlyHeader& h, const std::string& path, const PointSetOptions& o) {
    PlyPointColumns c;
    const int vi = h.find("vertex");
    if (vi < 0) throw FormatError(path + ": PLY file has no vertex element");
    const PlyElement& V = h.elements[static_cast<std::size_t>(vi)];
    for (const auto& p : V.props)
        if (p.is_list)
            throw FormatError(path + ": line " + std::to_string(V.line) + ": list property '" + ply_escape(p.name) +
                              "' on PLY vertices is not supported");
    const int ix[3] = {V.find("x"), V.find("y"), V.find("z")};
    if (ix[0] < 0 || ix[1] < 0 || ix[2] < 0) throw FormatError(path + ": line " + std::to_string(V.line) + ": PLY vertices have no x y z properties");
    auto names = [&] {
        std::string s;
        for (const auto& p : V.props) s += (s.empty() ? "" : ", ") + ply_escape(p.name);
        return s;
    };
    int iv = -1;
    if (!o.value_name.empty()) {
        iv = V.find(o.value_name);
        if (iv < 0) throw FormatError(path + ": no vertex property '" + o.value_name + "' (properties: " + names() + ")");
    } else {
        iv = V.find("value");
        if (iv < 0) iv = V.find("scalar");
        static const char* skip[] = {"x", "y", "z", "nx", "ny", "nz", "radius"};
        for (std::size_t p = 0; p < V.props.size() && iv < 0; ++p) {
            const auto& pr = V.props[p];
            if ((pr.type == StoredType::f32 || pr.type == StoredType::f64) &&
                std::none_of(std::begin(skip), std::end(skip), [&](const char* s) { return pr.name == s; }))
                iv = static_cast<int>(p);
        }
    }
    c.vi = vi;
    c.cols[0] = ix[0];
    c.cols[1] = ix[1];
    c.cols[2] = ix[2];
    c.cols[3] = iv;
    c.iv = iv;
    return c;
}

}  // namespace

PointSet read_points_ply(const std::string& path, const PointSetOptions& o, std::vector<std::string>* notes) {
    PlyReader r(path);
    const PlyHeader& h = r.header();
    const PlyPointColumns c = ply_point_columns(h, path, o);
    const int vi = c.vi, iv = c.iv;
    const PlyElement& V = h.elements[static_cast<std::size_t>(vi)];
    PointSetBuilder b(path, o);
    r.skip_to(static_cast<std::size_t>(vi));
    // the count was checked against the file size when it is known; otherwise grow with the data
    b.reserve(static_cast<std::size_t>(r.size_known() ? V.count : std::min<std::uint64_t>(V.count, 1u << 20)));
    const int* cols = c.cols;
    const std::size_t nc = c.count();
    std::vector<double> vals;
    std::uint64_t v = 0;
    while (r.element() == static_cast<std::size_t>(vi)) {
        const std::size_t n = r.read_values(vals, 65536, std::span<const int>(cols, nc));
        for (std::size_t i = 0; i < n; ++i, ++v) {
            const double* q = &vals[i * nc];
            b.add(q[0], q[1], q[2], iv >= 0 ? q[3] : 0.0, "vertex", v);
        }
    }
    const std::uint64_t trailing = r.finish(o.allow_trailing);
    if (notes && trailing) notes->push_back(std::to_string(trailing) + " trailing bytes ignored");
    if (notes && iv >= 0 && o.value_name.empty()) notes->push_back("scalar: vertex property '" + ply_escape(V.props[iv].name) + "'");
    return b.finish(iv >= 0 ? V.props[iv].name : "", iv >= 0);
}

void stream_points_ply(const std::string& path, const PointSetOptions& o, const PlyPointsBegin& begin,
                       const PlyPointsChunk& chunk, std::uint64_t& dropped_nonfinite, std::vector<std::string>* notes) {
    PlyReader r(path);
    const PlyHeader& h = r.header();
    const PlyPointColumns c = ply_point_columns(h, path, o);
    const PlyElement& V = h.elements[static_cast<std::size_t>(c.vi)];
    begin(c.iv >= 0 ? V.props[static_cast<std::size_t>(c.iv)].name : "", c.iv >= 0);
    r.skip_to(static_cast<std::size_t>(c.vi));
    const std::size_t nc = c.count();
    std::vector<double> vals, xyzv;
    std::uint64_t v = 0;
    while (r.element() == static_cast<std::size_t>(c.vi)) {
        const std::size_t n = r.read_values(vals, 65536, std::span<const int>(c.cols, nc));
        xyzv.clear();
        for (std::size_t i = 0; i < n; ++i, ++v) {
            const double* q = &vals[i * nc];
            const double x = q[0], y = q[1], z = q[2], val = c.iv >= 0 ? q[3] : 0.0;
            if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(val)) {
                if (o.strict)
                    throw FormatError(path + ": vertex " + std::to_string(v) + ": non-finite " +
                                      (std::isfinite(x) && std::isfinite(y) && std::isfinite(z) ? "value" : "coordinate") +
                                      " (NaN/Inf are refused in strict mode)");
                ++dropped_nonfinite;
                continue;
            }
            xyzv.insert(xyzv.end(), {x, y, z, val});
        }
        if (!xyzv.empty()) chunk(xyzv);
    }
    const std::uint64_t trailing = r.finish(o.allow_trailing);
    if (notes && trailing) notes->push_back(std::to_string(trailing) + " trailing bytes ignored");
}

}  // namespace meshless
