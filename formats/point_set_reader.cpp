#include "formats/point_set_reader.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "formats/binary_file.hpp"
#include "formats/cluster_tree_file.hpp"
#include "formats/npy_header.hpp"
#include "formats/plot3d.hpp"
#include "formats/points_ply.hpp"
#include "formats/points_raw.hpp"
#include "formats/points_text.hpp"
#include "formats/points_vtp.hpp"
#include "formats/points_vts.hpp"
#include "formats/points_vtu.hpp"
#include "formats/raw_volume.hpp"
#include "formats/point_store.hpp"
#include "formats/text_header.hpp"
#include "formats/volume_reader.hpp"

namespace meshless {

namespace {

std::string ext_of(const std::string& path) {
    std::string e = to_lower(std::filesystem::path(path).extension().string());
    return e;
}

// A .raw is a volume when its name says a volume's shape (name_XxYxZ_type.raw: the volume's reader
// then names what is wrong with it) or its layout comes from elsewhere (a Voreen .dat sidecar).
bool volume_claims(const std::string& path) {
    if (parse_raw_name(path)) return true;
    try {
        (void)probe_volume(path);
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

enum class Fmt { text, ply, vtp, vts, vtu, raw, npy, plot3d, p3d, volume, mlh, mlc };

Fmt choose(const std::string& path) {
    const std::string e = ext_of(path);
    if (e == ".csv" || e == ".tsv" || e == ".txt" || e == ".pts" || e == ".asc" || e == ".xyzv") return Fmt::text;
    if (e == ".ply") return Fmt::ply;
    if (e == ".mlh" || is_cluster_tree_file(path)) return Fmt::mlh;
    if (e == ".mlc" || is_point_store(path)) return Fmt::mlc;
    if (e == ".vtp") return Fmt::vtp;
    if (e == ".vts") return Fmt::vts;
    if (e == ".vtu") return Fmt::vtu;
    if (e == ".npy") return npy_ndim(path) == 3 ? Fmt::volume : Fmt::npy;  // a 3-D array is a volume
    if (e == ".p3d") return Fmt::p3d;
    if (e == ".xyz" || e == ".x" || e == ".g") return Fmt::plot3d;
    if (e == ".raw") return volume_claims(path) ? Fmt::volume : Fmt::raw;
    if (e == ".bin") return looks_like_plot3d_xyz(path) ? Fmt::plot3d : Fmt::raw;
    if (looks_like_volume(path)) return Fmt::volume;
    // by content
    const std::string head = read_file_prefix(path, 64);
    if (head.rfind("ply", 0) == 0) return Fmt::ply;
    if (head.rfind("\x93NUMPY", 0) == 0) return npy_ndim(path) == 3 ? Fmt::volume : Fmt::npy;
    if (head.find("<VTKFile") != std::string::npos || head.rfind("<?xml", 0) == 0) {
        const std::string more = read_file_prefix(path, 4096);
        if (more.find("UnstructuredGrid") != std::string::npos) return Fmt::vtu;
        return more.find("StructuredGrid") != std::string::npos ? Fmt::vts : Fmt::vtp;
    }
    if (looks_like_plot3d_xyz(path)) return Fmt::plot3d;
    if (head.find('\0') != std::string::npos)  // binary, and no format above claimed it
        throw FormatError(path + ": " + (head.rfind("\x89PNG", 0) == 0 ? "a PNG image" : "binary data of no known format") +
                          ", not a volume or point set (raw float32 records need a .raw or .bin name; `meshless info` "
                          "describes what it reads)");
    return Fmt::text;
}

const char* fmt_name(Fmt f) {
    switch (f) {
        case Fmt::text: return "text";
        case Fmt::ply: return "ply";
        case Fmt::vtp: return "vtp";
        case Fmt::vts: return "vts";
        case Fmt::vtu: return "vtu";
        case Fmt::raw: return "raw-float32";
        case Fmt::npy: return "npy";
        case Fmt::plot3d: return "plot3d";
        case Fmt::p3d: return "plot3d-meta";
        case Fmt::volume: return "volume";
        case Fmt::mlh: return "cluster-tree-lod";
        case Fmt::mlc: return "point-store";
    }
    return "?";
}

void merge_blocks(PointSet& ps, const std::string& path) {
    if (ps.blocks.size() <= 1) return;
    ps.blocks = {PointSetBlock{std::filesystem::path(path).filename().string(),
                               {static_cast<std::int64_t>(ps.pos.size()), 1, 1}, 0, ps.pos.size()}};
}

void check_count(const PointSet& ps, const std::string& path) {
    if (ps.size() < kMinPointSetPoints)
        throw FormatError(path + ": " + std::to_string(ps.size()) + " valid point" + (ps.size() == 1 ? "" : "s") +
                          (ps.dropped_nonfinite || ps.dropped_blanked
                               ? " (" + std::to_string(ps.dropped_nonfinite) + " NaN/Inf and " +
                                     std::to_string(ps.dropped_blanked) + " blanked dropped)"
                               : std::string()) +
                          ", at least " + std::to_string(kMinPointSetPoints) + " needed");
}

/// Coordinates spread over more than kMaxExtent units are refused: squared distances (every field
/// and search sums them) would overflow a double beyond about 1e154.
constexpr double kMaxExtent = 1e150;

void check_extent(const PointSet& ps, const std::string& path) {
    if (ps.pos.empty()) return;
    double lo[3] = {ps.pos.front().x, ps.pos.front().y, ps.pos.front().z}, hi[3] = {lo[0], lo[1], lo[2]};
    for (const Vec3& p : ps.pos)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
    for (int a = 0; a < 3; ++a)
        if (!(hi[a] - lo[a] <= kMaxExtent))
            throw FormatError(path + ": the points' " + "xyz"[a] + " coordinates span " + number_text(lo[a]) + " .. " +
                              number_text(hi[a]) + ", more than " + number_text(kMaxExtent) +
                              " units (squared distances would overflow); an outlier or a unit mix-up?");
}

PointSet read_one(const std::string& path, const PointSetOptions& o, Fmt f, std::vector<std::string>* notes) {
    if (std::filesystem::is_directory(path) && f != Fmt::volume) throw IoError(path + ": is a directory, expected a file");
    PointSet ps;
    switch (f) {
        case Fmt::text: ps = read_points_text(path, o, notes); break;
        case Fmt::ply: ps = read_points_ply(path, o, notes); break;
        case Fmt::vtp: ps = read_points_vtp(path, o, notes); break;
        case Fmt::vts: ps = read_points_vts(path, o, notes); break;
        case Fmt::vtu: ps = read_points_vtu(path, o, notes); break;
        case Fmt::raw: ps = read_points_raw(path, o, notes); break;
        case Fmt::npy: ps = read_points_npy(path, o, notes); break;
        case Fmt::plot3d: ps = read_plot3d(path, o, notes); break;
        case Fmt::p3d: ps = read_plot3d_meta(path, o, notes); break;
        case Fmt::volume: ps = point_set_from_volume(path, o); break;
        case Fmt::mlh: ps = point_set_from_cluster_tree(path, o, notes); break;
        case Fmt::mlc: ps = point_set_from_point_store(path, notes); break;
    }
    if (ps.blocks.size() == 1 && ps.blocks[0].name == "points")
        ps.blocks[0].name = std::filesystem::path(path).filename().string();
    if (o.merge_blocks) merge_blocks(ps, path);
    check_count(ps, path);
    check_extent(ps, path);
    return ps;
}

}  // namespace

PointSet point_set_from_volume(const std::string& path, const PointSetOptions& o, const RawOptions& raw) {
    const Volume v = read_volume(path, raw);
    const GridSpec& g = v.grid;
    const VolumeView view = v.view();
    PointSetBuilder b(path, o);
    b.begin_block(std::filesystem::path(path).filename().string(), g.dims);
    b.reserve(static_cast<std::size_t>(g.voxel_count()));
    std::uint64_t idx = 0;
    for (std::int64_t k = 0; k < g.dims[2]; ++k)
        for (std::int64_t j = 0; j < g.dims[1]; ++j)
            for (std::int64_t i = 0; i < g.dims[0]; ++i, ++idx)
                b.add(g.origin[0] + i * g.spacing[0], g.origin[1] + j * g.spacing[1], g.origin[2] + k * g.spacing[2],
                      view.at(static_cast<std::int64_t>(idx)), "voxel", idx);
    return b.finish("value", true);
}

PointSet read_point_set(const std::string& path, const PointSetOptions& o) {
    return read_one(path, o, choose(path), nullptr);
}

PointSet read_point_set(const std::vector<std::string>& paths, const PointSetOptions& o) {
    if (paths.empty()) throw InvalidArgument("no point-set files given");
    if (paths.size() == 1) return read_point_set(paths.front(), o);
    PointSetOptions each = o;
    each.merge_blocks = false;
    PointSet out;
    for (std::size_t i = 0; i < paths.size(); ++i) {
        PointSet ps = read_point_set(paths[i], each);
        if (i == 0) {
            out.value_name = ps.value_name;
            out.has_values = ps.has_values;
        } else if (ps.value_name != out.value_name || ps.has_values != out.has_values) {
            throw FormatError(paths[i] + ": scalar '" + ps.value_name + "' differs from '" + out.value_name + "' in " + paths[0]);
        }
        const std::uint64_t first = out.pos.size();
        for (auto blk : ps.blocks) {
            blk.first += first;
            out.blocks.push_back(std::move(blk));
        }
        out.pos.insert(out.pos.end(), ps.pos.begin(), ps.pos.end());
        out.value.insert(out.value.end(), ps.value.begin(), ps.value.end());
        out.dropped_nonfinite += ps.dropped_nonfinite;
        out.dropped_blanked += ps.dropped_blanked;
    }
    if (o.merge_blocks) merge_blocks(out, paths.front());
    return out;
}

std::string point_set_format(const std::string& path) { return fmt_name(choose(path)); }

PointSetInfo probe_point_set(const std::string& path, const PointSetOptions& o) {
    PointSetInfo info;
    const Fmt f = choose(path);
    info.format = fmt_name(f);
    info.set = read_one(path, o, f, &info.notes);
    return info;
}

PointSet point_set_from_cluster_tree(const std::string& path, const PointSetOptions& o, std::vector<std::string>* notes) {
    const ClusterTree t = read_cluster_tree_file(path);
    const ClusterTreeLodRequest r = cluster_tree_lod_request(t, o);
    if (notes && !r.note.empty()) notes->push_back(r.note);
    PointSet ps = lod_point_set(t.nodes, r.mode, r.threshold, t.value_name);
    ps.blocks[0].name = std::filesystem::path(path).filename().string();
    return ps;
}

ClusterTreeLodRequest cluster_tree_lod_request(const ClusterTree& t, const PointSetOptions& o) {
    if (int(o.lod_level.has_value()) + int(o.lod_error.has_value()) + int(o.lod_count.has_value()) +
            int(o.lod_fraction.has_value()) > 1)
        throw InvalidArgument("a level of detail is chosen by one of level, error, count or fraction");
    ClusterTreeLodRequest r;
    if (o.lod_count || o.lod_fraction) {
        double n = 0;
        if (o.lod_fraction) {
            if (!(*o.lod_fraction > 0 && *o.lod_fraction <= 1)) throw InvalidArgument("LOD fraction: expected a number in (0, 1]");
            n = std::max(1.0, std::round(*o.lod_fraction * static_cast<double>(t.stats.samples)));
        } else {
            if (*o.lod_count < 1) throw InvalidArgument("LOD count: expected a count >= 1");
            n = static_cast<double>(*o.lod_count);
        }
        const std::uint64_t leaves = t.stats.splits + 1;
        r.mode = LodMode::count;
        r.threshold = n;
        r.clamped = n > static_cast<double>(leaves);
        char buf[96];
        if (o.lod_fraction) std::snprintf(buf, sizeof buf, "fraction %g (%.0f points)", *o.lod_fraction, n);
        else std::snprintf(buf, sizeof buf, "count %.0f", n);
        r.description = buf;
        if (r.clamped)
            r.note = std::string(buf) + " is more than the tree's " + std::to_string(leaves) + " leaves: the finest level of detail";
    } else if (o.lod_error) {
        if (!std::isfinite(*o.lod_error) || *o.lod_error < 0) throw InvalidArgument("LOD error: expected a finite number >= 0");
        r.mode = LodMode::error;
        r.threshold = *o.lod_error;
        r.clamped = *o.lod_error < t.stats.error_reached;
        char buf[64];
        std::snprintf(buf, sizeof buf, "error %g", *o.lod_error);
        r.description = buf;
        if (r.clamped)
            r.note = "error " + std::to_string(*o.lod_error) + " is below the error the hierarchy reached (" +
                     std::to_string(t.stats.error_reached) + "): the finest level of detail";
    } else {
        r.mode = LodMode::level;
        r.threshold = o.lod_level ? *o.lod_level : t.stats.depth;
        r.clamped = o.lod_level && *o.lod_level > t.stats.depth;
        r.description = o.lod_level ? "level " + std::to_string(*o.lod_level) : "finest";
        if (r.clamped)
            r.note = "level " + std::to_string(*o.lod_level) + " is beyond the depth " + std::to_string(t.stats.depth) +
                     ": the finest level of detail";
    }
    return r;
}

bool looks_like_point_set(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;
    const std::string e = ext_of(path);
    if (e == ".csv" || e == ".tsv" || e == ".txt" || e == ".pts" || e == ".asc" || e == ".xyzv" || e == ".vtp" ||
        e == ".vts" || e == ".vtu" || e == ".p3d" || e == ".xyz" || e == ".x" || e == ".g")
        return true;
    if (e == ".mlh" || e == ".mlc") return true;
    if (e == ".npy") return npy_ndim(path) != 3;  // a 3-D array is a volume (formats/npy_volume.hpp)
    if (e == ".raw") return !volume_claims(path);
    if (e == ".bin") return looks_like_plot3d_xyz(path);
    return false;
}

}  // namespace meshless
