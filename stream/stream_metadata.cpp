#include "stream/stream_metadata.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "formats/length_unit.hpp"
#include "formats/text_header.hpp"
#include "kernels/block_minmax.hpp"
#include "kernels/errors.hpp"

namespace meshless {

std::string triple(double a, double b, double c) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g", a, b, c);
    return buf;
}

std::string triple(const Vec3& v) { return triple(v.x, v.y, v.z); }

namespace {
std::optional<Vec3> parse_triple_meta(const StreamMeta& m, const std::string& key) {
    auto s = m.get(key);
    if (!s) return std::nullopt;
    double v[3];
    if (std::sscanf(s->c_str(), "%lf,%lf,%lf", &v[0], &v[1], &v[2]) != 3)
        throw FormatError(m.where() + "stream metadata: '" + key + "' is not three numbers: " +
                          escape_field(*s));
    return Vec3{v[0], v[1], v[2]};
}
}  // namespace

StreamMeta volume_meta(const std::string& source, const GridSpec& g, SampleType type,
                       const std::optional<std::array<double, 2>>& r, double iso, const std::string& producer) {
    StreamMeta m;
    m.set("source", std::filesystem::path(source).filename().string());
    m.set("iso", iso);
    m.set("grid_dims", std::to_string(g.dims[0]) + "," + std::to_string(g.dims[1]) + "," + std::to_string(g.dims[2]));
    m.set("grid_origin", triple(g.origin[0], g.origin[1], g.origin[2]));
    m.set("grid_spacing", triple(g.spacing[0], g.spacing[1], g.spacing[2]));
    m.set("bounds_lo", triple(g.origin[0], g.origin[1], g.origin[2]));
    m.set("bounds_hi", triple(g.origin[0] + (g.dims[0] - 1) * g.spacing[0], g.origin[1] + (g.dims[1] - 1) * g.spacing[1],
                              g.origin[2] + (g.dims[2] - 1) * g.spacing[2]));
    if (r) {
        m.set("value_min", (*r)[0]);
        m.set("value_max", (*r)[1]);
    }
    m.set("sample_type", to_string(type));
    m.set("producer", producer);
    return m;
}

StreamMeta sample_store_meta(const SampleStore& store, double iso, const std::string& producer) {
    const BrickStore& mlb = store.brick_store();
    const BrickStoreInfo& bi = mlb.info();
    StreamMeta m = volume_meta(mlb.path(), bi.grid, bi.type, {bi.value_min, bi.value_max}, iso, producer);
    m.set("paradigm", "A");
    set_surface_bounds(m, store_surface_bounds(mlb, BrickIndex(mlb), iso));  // frames as the .mlb's graph does
    set_patient_axes(m, store_frame(bi));  // and faces alike
    set_length_unit(m, bi.length_unit);
    if (!bi.value_unit.empty()) m.set("value_unit", bi.value_unit);
    return m;
}

std::optional<std::array<Vec3, 2>> store_surface_bounds(const BrickStore& store, const BrickIndex& index, double iso) {
    std::optional<VoxelBox> box;
    for (std::size_t i : index.active(iso)) {
        const BrickBox b = store.box(i);
        VoxelBox one;
        for (int a = 0; a < 3; ++a) {
            one.lo[a] = b.first[a];
            one.hi[a] = b.first[a] + b.dims[a] - 1;
        }
        if (!box) {
            box = one;
            continue;
        }
        for (int a = 0; a < 3; ++a) {
            box->lo[a] = std::min(box->lo[a], one.lo[a]);
            box->hi[a] = std::max(box->hi[a], one.hi[a]);
        }
    }
    if (!box) return std::nullopt;
    return world_bounds(store.info().grid, *box);
}

void set_surface_bounds(StreamMeta& m, const std::optional<std::array<Vec3, 2>>& surface) {
    m.set("volume_bounds_lo", *m.get("bounds_lo"));
    m.set("volume_bounds_hi", *m.get("bounds_hi"));
    if (!surface) return;  // nothing active: frame the volume
    m.set("bounds_lo", triple((*surface)[0].x, (*surface)[0].y, (*surface)[0].z));
    m.set("bounds_hi", triple((*surface)[1].x, (*surface)[1].y, (*surface)[1].z));
}

std::optional<AnatomicalFrame> store_frame(const BrickStoreInfo& info) {
    if (!info.patient_axes) return std::nullopt;
    return frame_of_axes(*info.patient_axes, "brick store header");
}

void set_patient_axes(StreamMeta& m, const std::optional<AnatomicalFrame>& f) {
    if (!f) return;
    const auto ax = frame_axes(*f);
    m.set("patient_axes", triple(ax[0][0], ax[0][1], ax[0][2]) + "," + triple(ax[1][0], ax[1][1], ax[1][2]) + "," +
                              triple(ax[2][0], ax[2][1], ax[2][2]));
}

void set_length_unit(StreamMeta& m, const std::string& unit) {
    if (!unit.empty()) m.set("length_unit", unit);
}

std::string meta_length_unit(const StreamMeta& m) {
    const auto u = m.get("length_unit");
    return u ? length_unit_from_name(*u) : std::string();
}

std::vector<std::string> ply_comments(const StreamMeta& m) {
    std::vector<std::string> c{"meshless oriented point set: x y z, unit normal, splat radius, value"};
    for (const char* k : {"source", "iso", "isovalues", "projection", "field", "samples", "tolerance", "blocks", "grid_dims", "grid_spacing",
                          "bounds_lo", "bounds_hi", "frame", "volume_bounds_lo", "volume_bounds_hi", "value_min", "value_max",
                          "value_name", "value_unit", "patient_axes", "length_unit"})
        if (auto v = m.get(k)) c.push_back(std::string(k) + " " + *v);
    return c;
}

namespace {
StreamMeta comments_meta(const std::vector<std::string>& comments) {
    StreamMeta m;
    for (const auto& c : comments)
        if (auto sp = c.find(' '); sp != std::string::npos) m.set(c.substr(0, sp), c.substr(sp + 1));
    return m;
}
}  // namespace

StreamMeta ply_comments_meta(const std::vector<std::string>& comments) { return comments_meta(comments); }

std::optional<std::array<Vec3, 2>> ply_bounds(const std::vector<std::string>& comments) {
    return meta_bounds(comments_meta(comments));
}

std::optional<std::array<Vec3, 2>> meta_bounds(const StreamMeta& m) {
    auto lo = parse_triple_meta(m, "bounds_lo"), hi = parse_triple_meta(m, "bounds_hi");
    if (!lo || !hi) return std::nullopt;
    return std::array<Vec3, 2>{*lo, *hi};
}

std::optional<std::array<Vec3, 2>> picture_bounds(const StreamMeta& m) {
    if (m.get("frame") == std::optional<std::string>("points")) return std::nullopt;
    return meta_bounds(m);
}

std::optional<std::array<Vec3, 2>> ply_picture_bounds(const std::vector<std::string>& comments) {
    return picture_bounds(comments_meta(comments));
}

std::optional<AnatomicalFrame> meta_patient_axes(const StreamMeta& m) {
    const auto v = m.get("patient_axes");
    if (!v) return std::nullopt;
    std::array<std::array<double, 3>, 3> ax{};
    char tail = 0;
    if (std::sscanf(v->c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf%c", &ax[0][0], &ax[0][1], &ax[0][2], &ax[1][0], &ax[1][1],
                    &ax[1][2], &ax[2][0], &ax[2][1], &ax[2][2], &tail) != 9)
        return std::nullopt;
    for (const auto& r : ax)
        for (double x : r)
            if (!std::isfinite(x)) return std::nullopt;
    return frame_of_axes(ax, "patient_axes");
}

/// Records the isovalues of a job of several in `meta` (instead of `iso`: the points do not lie on
/// one surface) and frames the union of their surfaces. `bounds(iso)` gives one surface's.
void set_isovalues(StreamMeta& meta, const std::vector<double>& isos,
                   const std::function<std::optional<std::array<Vec3, 2>>(double)>& bounds) {
    if (isos.size() < 2) return;
    std::string list;
    std::optional<std::array<Vec3, 2>> all;
    for (double v : isos) {
        StreamMeta one;
        one.set("iso", v);  // (the number as the metadata writes it)
        list += (list.empty() ? "" : ",") + *one.get("iso");
        if (const auto b = bounds(v)) {
            if (!all) all = *b;
            const Vec3 &lo = (*all)[0], &hi = (*all)[1];
            all = std::array<Vec3, 2>{Vec3{std::min(lo.x, (*b)[0].x), std::min(lo.y, (*b)[0].y), std::min(lo.z, (*b)[0].z)},
                                      Vec3{std::max(hi.x, (*b)[1].x), std::max(hi.y, (*b)[1].y), std::max(hi.z, (*b)[1].z)}};
        }
    }
    meta.kv.erase("iso");
    meta.set("isovalues", list);
    if (all) {
        meta.set("bounds_lo", triple((*all)[0].x, (*all)[0].y, (*all)[0].z));
        meta.set("bounds_hi", triple((*all)[1].x, (*all)[1].y, (*all)[1].z));
    }
}

std::optional<std::vector<double>> meta_isovalues(const StreamMeta& m) {
    const auto list = m.get("isovalues");
    if (!list) return std::nullopt;
    std::vector<double> v;
    std::size_t at = 0;
    for (;;) {
        const std::size_t comma = list->find(',', at);
        StreamMeta one;
        one.source = m.source;
        one.kv["isovalues"] = list->substr(at, comma == std::string::npos ? std::string::npos : comma - at);
        v.push_back(*one.get_finite("isovalues"));
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    if (v.size() < 2) throw FormatError(m.where() + "stream metadata: 'isovalues' lists fewer than two values");
    return v;
}

}  // namespace meshless
