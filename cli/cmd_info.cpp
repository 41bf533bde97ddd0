// meshless info: describes any file meshless reads or writes (volumes, point/sample streams,
// PLY point sets and meshes, PNG pictures).
#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "formats/reference_policy.hpp"
#include "cli/cluster_tree_cli.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "cli/point_set_cli.hpp"
#include "formats/multiblock_reader.hpp"
#include "formats/cluster_tree_file.hpp"
#include "formats/field_file.hpp"
#include "formats/ply.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/point_stream.hpp"
#include "formats/volume_reader.hpp"
#include "ooc/sample_store.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_store.hpp"

namespace meshless::cli {

namespace {

void info_stream(const std::string& path) {
    InputFile in(path);
    StreamReader r(in.f, in.name);
    r.read_meta();
    std::vector<char> buf;
    std::uint64_t frames = 0;
    for (;;) {
        buf.clear();
        if (!r.next_data(buf)) break;
        ++frames;
    }
    std::printf("%s: meshless %s stream%s, version %u, %zu-byte records\n", terminal_safe(path).c_str(),
                r.kind() == RecordKind::point ? "point" : (r.kind() == RecordKind::seed ? "seed" : "sample"),
                r.has_blocks() ? " with block ids" : "", kStreamVersion, r.record_bytes());
    std::printf("  records: %llu in %llu DATA frames, END frame present\n", static_cast<unsigned long long>(r.total()),
                static_cast<unsigned long long>(frames));
    if (r.total() > 0) {
        std::printf("  payload: %llu bytes, %.1f per record", static_cast<unsigned long long>(r.data_bytes()),
                    static_cast<double>(r.data_bytes()) / static_cast<double>(r.total()));
        if (r.kind() == RecordKind::sample)  // only sample frames can be cell-indexed
            std::printf(" (%llu cell-indexed frames)", static_cast<unsigned long long>(r.cell_frames()));
        std::printf("\n");
    }
    for (const auto& [k, v] : r.meta().kv) std::printf("  %s: %s\n", terminal_safe(k).c_str(), terminal_safe(v).c_str());
}

// Per-property minimum, maximum and non-finite count of an element without lists, read in chunks.
struct PropertyRange {
    double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
    std::uint64_t non_finite = 0;
};

std::vector<PropertyRange> scan_ranges(PlyReader& r, std::size_t nprops, std::uint64_t count) {
    std::vector<PropertyRange> ranges(nprops);
    std::vector<double> chunk;
    // stop at the element's last record: one more read would step into the next element
    for (std::uint64_t left = count; left > 0;) {
        const std::size_t n = r.read_values(chunk, static_cast<std::size_t>(std::min<std::uint64_t>(left, 1u << 16)));
        if (n == 0) break;
        left -= n;
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t p = 0; p < nprops; ++p) {
                const double v = chunk[i * nprops + p];
                PropertyRange& g = ranges[p];
                if (!std::isfinite(v)) {
                    ++g.non_finite;
                    continue;
                }
                g.lo = std::min(g.lo, v);
                g.hi = std::max(g.hi, v);
            }
    }
    return ranges;
}

void info_ply(const std::string& path) {
    // the header through the PLY codec, then the whole body read through (a truncated or corrupt
    // body is reported, not just the header); the vertex element is summarised: count, bounds,
    // the range of every other property, non-finite values
    PlyReader r(path);
    const PlyHeader h = r.header();
    bool faces = false;
    for (const auto& e : h.elements) faces = faces || e.name != "vertex";
    std::string summary;
    const int vi = h.find("vertex");
    if (vi >= 0 && !h.elements[vi].has_lists()) {
        const PlyElement& ve = h.elements[vi];
        r.skip_to(static_cast<std::size_t>(vi));
        const std::vector<PropertyRange> ranges = scan_ranges(r, ve.props.size(), ve.count);
        char line[512];
        std::snprintf(line, sizeof line, "  %llu vertices\n", static_cast<unsigned long long>(ve.count));
        summary += line;
        const int ix = ve.find("x"), iy = ve.find("y"), iz = ve.find("z");
        if (ve.count > 0 && ix >= 0 && iy >= 0 && iz >= 0) {
            std::snprintf(line, sizeof line, "  bounds: x %.9g .. %.9g, y %.9g .. %.9g, z %.9g .. %.9g\n", ranges[ix].lo,
                          ranges[ix].hi, ranges[iy].lo, ranges[iy].hi, ranges[iz].lo, ranges[iz].hi);
            summary += line;
        }
        for (std::size_t p = 0; p < ve.props.size(); ++p) {
            const int ip = static_cast<int>(p);
            if (ip == ix || ip == iy || ip == iz) continue;
            if (ranges[p].lo <= ranges[p].hi) {
                std::snprintf(line, sizeof line, "  %s: %.9g .. %.9g\n", ply_escape(ve.props[p].name).c_str(), ranges[p].lo,
                              ranges[p].hi);
                summary += line;
            } else if (ve.count > 0) {
                summary += "  " + ply_escape(ve.props[p].name) + ": no finite value\n";
            }
        }
        std::uint64_t non_finite = 0;
        for (const auto& g : ranges) non_finite += g.non_finite;
        if (non_finite > 0) {
            std::snprintf(line, sizeof line, "  non-finite values: %llu\n", static_cast<unsigned long long>(non_finite));
            summary += line;
        }
    }
    for (const auto& e : h.elements) {  // a mesh's faces (and any other element) counted too
        if (e.name == "vertex") continue;
        summary += "  " + std::to_string(e.count) + " " + (e.name == "face" ? std::string("faces") : ply_escape(e.name) + " elements") + "\n";
    }
    r.finish();
    // a mesh with faces: read as splat reads it (vertices finite, face indices integral and within
    // the vertices), so that info passes what splat draws; point sets stream through as above
    if (const int fi = h.find("face"); fi >= 0 && h.elements[static_cast<std::size_t>(fi)].count > 0) (void)read_ply_mesh(path);
    std::string text = format_ply_header(h, false);
    text = text.substr(4, text.size() - 4 - std::string("end_header\n").size());  // between "ply" and end_header
    std::string indented;
    for (std::size_t i = 0; i < text.size();) {
        const std::size_t nl = text.find('\n', i);
        indented += "  " + ply_escape(text.substr(i, nl - i), 4096) + "\n";
        i = nl + 1;
    }
    std::printf("%s: PLY%s (body checked)\n%s%s  end_header\n", terminal_safe(path).c_str(), faces ? "" : " point set", summary.c_str(),
                indented.c_str());
}

void info_png(const std::string& path, const unsigned char* h, std::size_t n) {
    if (n < 24) throw FormatError(path + ": truncated PNG header");
    auto be32 = [&](int o) { return (unsigned(h[o]) << 24) | (unsigned(h[o + 1]) << 16) | (unsigned(h[o + 2]) << 8) | h[o + 3]; };
    std::printf("%s: PNG image, %u x %u\n", terminal_safe(path).c_str(), be32(16), be32(20));
}

void info_brick_store(const std::string& path) {
    const auto store = BrickStore::open(path);
    const BrickStoreInfo& i = store->info();
    const GridSpec& g = i.grid;
    std::uint64_t stored = 0, raw = 0, constant = 0;
    for (const auto& e : store->bricks()) {
        stored += e.stored_bytes;
        raw += e.raw_bytes;
        if (e.vmin == e.vmax) ++constant;
    }
    const std::uint64_t volume_bytes = static_cast<std::uint64_t>(g.voxel_count()) * sample_size(i.type);
    const std::uint64_t file_bytes = stored + kBrickStoreHeaderBytes + kBrickStoreFooterBytes +
                                     store->bricks().size() * kBrickIndexEntryBytes;
    std::printf("%s: meshless brick store, version %u\n", terminal_safe(path).c_str(), kBrickStoreVersion);
    std::printf("  dims: %lld x %lld x %lld (%lld voxels, %lld cells)\n", static_cast<long long>(g.dims[0]),
                static_cast<long long>(g.dims[1]), static_cast<long long>(g.dims[2]), static_cast<long long>(g.voxel_count()),
                static_cast<long long>(g.cell_count()));
    std::printf("  type: %s\n  spacing: %g %g %g\n  origin: %g %g %g\n  value range: %g .. %g\n", to_string(i.type),
                g.spacing[0], g.spacing[1], g.spacing[2], g.origin[0], g.origin[1], g.origin[2], i.value_min, i.value_max);
    if (i.patient_axes)  // recorded by convert from the volume's header
        std::printf("  patient axes: %s (from the converted volume's header)\n",
                    describe_frame(frame_of_axes(*i.patient_axes, "brick store header")).c_str());
    std::printf("  bricks: %llu (%lld x %lld x %lld) of %u cells + %u ghost, Morton order, zstd level %d; %llu constant\n",
                static_cast<unsigned long long>(i.brick_count), static_cast<long long>(i.bricks_per_axis[0]),
                static_cast<long long>(i.bricks_per_axis[1]), static_cast<long long>(i.bricks_per_axis[2]), i.brick_edge,
                i.ghost, i.zstd_level, static_cast<unsigned long long>(constant));
    std::printf("  largest brick: %llu bytes decompressed (minimum --memory)\n",
                static_cast<unsigned long long>(store->max_brick_bytes()));
    std::printf("  size: %llu bytes; volume %llu bytes (bricks with ghost layers %llu): compression ratio %.2f\n",
                static_cast<unsigned long long>(file_bytes), static_cast<unsigned long long>(volume_bytes),
                static_cast<unsigned long long>(raw), file_bytes ? static_cast<double>(volume_bytes) / file_bytes : 0.0);
}

void info_volume(const std::string& path, const Args& a) {
    // the payload proven as the readers would before allocating it, and decoded through a small
    // buffer: a bomb, a truncated or a corrupt payload fails here as it fails every reading command
    const VolumeInfo vi = prove_volume(path, raw_options(a));
    const GridSpec& g = vi.grid;
    std::printf("%s: %s volume\n", terminal_safe(path).c_str(), vi.format.c_str());
    std::printf("  dims: %lld x %lld x %lld (%lld voxels, %lld cells)\n", static_cast<long long>(g.dims[0]),
                static_cast<long long>(g.dims[1]), static_cast<long long>(g.dims[2]), static_cast<long long>(g.voxel_count()),
                static_cast<long long>(g.cell_count()));
    std::printf("  type: %s\n  spacing: %g %g %g\n  origin: %g %g %g\n", to_string(vi.type), g.spacing[0], g.spacing[1],
                g.spacing[2], g.origin[0], g.origin[1], g.origin[2]);
    if (!vi.encoding.empty()) std::printf("  encoding: %s\n", vi.encoding.c_str());
    // every file the header makes the readers open, as named and resolved (`..`, symbolic links)
    if (!vi.data_files.empty()) {
        std::printf("  data files: %zu\n", vi.data_files.size());
        for (const auto& f : vi.data_files)
            std::printf("    %s -> %s\n", terminal_safe(f).c_str(), terminal_safe(resolved_path(f)).c_str());
    }
    if (vi.frame)
        std::printf("  patient axes: %s (%s)\n", describe_frame(*vi.frame).c_str(), terminal_safe(vi.frame->source).c_str());
    std::printf("  payload: checked, %llu bytes decoded%s\n", static_cast<unsigned long long>(decoded_bytes(vi, path)),
                vi.maps ? " (mapped from the file when read)" : "");
}

void info_sample_store(const std::string& path) {
    const auto store = SampleStore::open(path);
    const SampleStoreInfo& i = store->info();
    const GridSpec& g = i.grid;
    std::printf("%s: meshless paradigm (A) sample store, version %u (span-space index of cell rows)\n", terminal_safe(path).c_str(),
                kSampleStoreVersion);
    std::printf("  brick store: %s -> %s (recomputed from; identity checked), %lld x %lld x %lld %s, spacing %g %g %g\n",
                terminal_safe(store->brick_store().path()).c_str(), terminal_safe(resolved_path(store->brick_store().path())).c_str(), static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]),
                static_cast<long long>(g.dims[2]), to_string(i.type), g.spacing[0], g.spacing[1], g.spacing[2]);
    std::printf("  cells: %llu indexed (non-constant; %llu constant, %llu NaN/Inf cells skipped) as %llu cell-row keys, "
                "%llu key bytes\n",
                static_cast<unsigned long long>(i.cells), static_cast<unsigned long long>(i.constant_cells),
                static_cast<unsigned long long>(i.nonfinite_cells), static_cast<unsigned long long>(i.key_count),
                static_cast<unsigned long long>(i.key_bytes));
    std::printf("  index: %llu buckets over %u %s levels of [%g, %g]\n", static_cast<unsigned long long>(i.bucket_count),
                i.levels, i.exact_levels ? "exact" : "quantised", i.value_lo, i.value_hi);
}

// Fitted fields (.mlf): read and validated whole (every checksum and index), then described.
void info_field_file(const std::string& path) {
    const FieldFile ff = read_field_file(path);
    const FieldFileInfo& i = ff.info;
    const FieldParams& p = i.params;
    const FieldBuildStats& s = i.stats;
    const PointSetIdentity& id = i.data.identity;
    auto u = [](std::uint64_t v) { return static_cast<unsigned long long>(v); };
    std::printf("%s: meshless fitted field (.mlf), format version %u, %llu bytes (checked)\n", terminal_safe(path).c_str(), i.version,
                u(i.file_bytes));
    std::printf("  field: %s\n", std::string(field_kind_name(p.kind)).c_str());
    std::string c = p.hardy_c_world > 0 ? std::to_string(p.hardy_c_world) + " (world units)"
                                        : std::to_string(p.hardy_c_rel) + " x bounding-box diagonal";
    switch (p.kind) {
        case FieldKind::rbf_grid:
            std::printf("  parameters: binning m = %g, support %s, local points %u..%u, nearest K = %s, Hardy c = %s\n",
                        p.binning_m, p.rbf_grid_support == RbfGridSupport::paper_radius ? "paper radius" : "27 neighbours",
                        p.rbf_grid_min_local, p.rbf_grid_max_local,
                        p.rbf_grid_local_points == 0 ? "all" : std::to_string(p.rbf_grid_local_points).c_str(), c.c_str());
            break;
        case FieldKind::mpu:
            std::printf("  parameters: N = %u, min points %u, alpha = %g, max depth %u, Hardy c = %s\n", p.mpu_max_points,
                        p.mpu_min_points, p.mpu_alpha, p.mpu_max_depth, c.c_str());
            break;
        case FieldKind::global_rbf:
            std::printf("  parameters: at most %u points, Hardy c = %s\n", p.global_max_points, c.c_str());
            break;
    }
    std::printf("  merge: points closer than %g x mean spacing%s\n", p.merge_rel, p.normalise_axes ? ", axes normalised" : "");
    std::printf("  fitted to: %llu points, identity hash %016llx\n", u(id.count), u(id.hash));
    std::printf("  bounds: %.12g %.12g %.12g .. %.12g %.12g %.12g\n", id.bounds[0].x, id.bounds[0].y, id.bounds[0].z,
                id.bounds[1].x, id.bounds[1].y, id.bounds[1].z);
    if (i.data.has_values)
        std::printf("  value: %s, range %.9g .. %.9g\n",
                    i.data.value_name.empty() ? "(unnamed)" : ply_escape(i.data.value_name, 128).c_str(), id.value_range[0],
                    id.value_range[1]);
    else
        std::printf("  value: none (positions only)\n");
    std::printf("  dropped by the reader: %llu NaN/Inf, %llu blanked\n", u(i.data.dropped_nonfinite), u(i.data.dropped_blanked));
    std::printf("  build: %llu points used (%llu merged, tolerance %g), c = %g, %llu local interpolants (%llu exact, "
                "%llu rank-deficient, %llu regularised, %llu linear fallback, %llu polynomial only, %llu grown, %llu capped), "
                "%.1f points per local (max %llu)\n",
                u(s.used_points), u(s.merged_points), s.merge_tolerance, s.hardy_c_world, u(s.locals), u(s.interpolated),
                u(s.rank_deficient), u(s.regularised), u(s.linear_fallback), u(s.polynomial_only), u(s.grown), u(s.capped),
                s.mean_local_points, u(s.max_local_points));
    if (p.kind == FieldKind::rbf_grid)
        std::printf("  RBF grid: %lld x %lld x %lld cells\n", static_cast<long long>(s.grid_dims[0]),
                    static_cast<long long>(s.grid_dims[1]), static_cast<long long>(s.grid_dims[2]));
    if (p.kind == FieldKind::mpu) std::printf("  octree: %llu nodes, depth %u\n", u(s.octree_nodes), s.octree_depth);
    std::printf("  memory when loaded: %.1f MiB\n", s.memory_bytes / 1048576.0);
    std::printf("  sections: %zu\n", i.sections.size());
    for (const auto& sec : i.sections) {
        static const char* const kType[] = {"bytes", "f64", "i64", "u32", "i32"};
        std::printf("    %-14s %-5s %12llu elements, %12llu bytes%s\n", terminal_safe(sec.name).c_str(), kType[sec.type < 5 ? sec.type : 0],
                    u(sec.count), u(sec.stored_bytes),
                    sec.compressed ? (" (zstd" + std::string(sec.shuffled ? ", shuffled" : "") + ", from " +
                                      std::to_string(sec.raw_bytes) + ")").c_str()
                                   : "");
    }
}

// Scattered and multiblock point sets (text, .vtp, .vts, PLOT3D, raw records, .npy): read through.
void info_point_set(const std::string& path, const Args& a) {
    const PointSetInfo info = probe_point_set(path, point_set_options(a));
    const PointSet& ps = info.set;
    std::printf("%s: %s point set\n", terminal_safe(path).c_str(), info.format.c_str());
    for (const auto& n : info.notes) std::printf("  %s\n", terminal_safe(n).c_str());
    std::printf("  points: %zu\n", ps.size());
    std::printf("  blocks: %zu\n", ps.blocks.size());
    const std::size_t listed = std::min<std::size_t>(ps.blocks.size(), 16);
    for (std::size_t b = 0; b < listed; ++b) {
        const auto& blk = ps.blocks[b];
        std::printf("    %s: %lld x %lld x %lld, %llu points\n", terminal_safe(blk.name).c_str(), static_cast<long long>(blk.dims[0]),
                    static_cast<long long>(blk.dims[1]), static_cast<long long>(blk.dims[2]),
                    static_cast<unsigned long long>(blk.count));
    }
    if (listed < ps.blocks.size()) std::printf("    ... (%zu more)\n", ps.blocks.size() - listed);
    if (ps.has_values) {
        const auto r = ps.value_range();
        std::printf("  value: %s, range %.9g .. %.9g\n", ps.value_name.empty() ? "(unnamed)" : terminal_safe(ps.value_name).c_str(), r[0], r[1]);
    } else {
        std::printf("  value: none (positions only)\n");
    }
    const auto bb = ps.bounds();
    std::printf("  bounds: %.12g %.12g %.12g .. %.12g %.12g %.12g\n", bb[0].x, bb[0].y, bb[0].z, bb[1].x, bb[1].y, bb[1].z);
    std::printf("  dropped: %llu NaN/Inf, %llu blanked (IBLANK 0)\n", static_cast<unsigned long long>(ps.dropped_nonfinite),
                static_cast<unsigned long long>(ps.dropped_blanked));
}

// VTK multiblock (.vtm) and AMR (.vthb, vtkHierarchicalBoxDataSet .vtm) collections: read through
// (every piece is opened and checked against the hierarchy), then described.
void info_multiblock(const std::string& path, const Args& a) {
    MultiblockDetails det;
    const Multiblock mb = read_multiblock({path}, point_set_options(a), det);
    std::printf("%s: %s\n", terminal_safe(path).c_str(), terminal_safe(det.description).c_str());
    for (const auto& n : mb.notes) std::printf("  note: %s\n", ply_escape(n, 400).c_str());
    if (det.origin) std::printf("  origin: %g %g %g\n", (*det.origin)[0], (*det.origin)[1], (*det.origin)[2]);
    for (const auto& l : det.levels) {
        std::printf("  level %d: %zu box%s, spacing %g %g %g", l.level, l.boxes, l.boxes == 1 ? "" : "es", l.spacing[0],
                    l.spacing[1], l.spacing[2]);
        if (l.refinement) std::printf(", refinement %d from level %d", l.refinement, l.level - 1);
        std::printf("\n");
    }
    std::printf("  arrays: %s\n", describe_arrays(det.arrays).c_str());
    double lo = 0, hi = 0;
    bool any = false;
    std::uint64_t nodes = 0, valid = 0;
    Vec3 bmin{0, 0, 0}, bmax{0, 0, 0};
    for (const auto& b : mb.blocks)
        for (std::int64_t n = 0; n < b.node_count(); ++n) {
            ++nodes;
            if (!b.is_valid(n)) continue;
            ++valid;
            const double v = b.value[static_cast<std::size_t>(n)];
            const Vec3& p = b.node[static_cast<std::size_t>(n)];
            if (!any) lo = hi = v, bmin = bmax = p, any = true;
            lo = std::min(lo, v), hi = std::max(hi, v);
            bmin = Vec3{std::min(bmin.x, p.x), std::min(bmin.y, p.y), std::min(bmin.z, p.z)};
            bmax = Vec3{std::max(bmax.x, p.x), std::max(bmax.y, p.y), std::max(bmax.z, p.z)};
        }
    std::printf("  value: '%s' (%s), range %.9g .. %.9g\n", ply_escape(mb.value_name).c_str(),
                det.cell ? "cell data: nodes at the cell centres" : "point data", lo, hi);
    std::printf("  nodes: %llu, %llu valid (%llu blanked, %llu NaN/Inf)\n", static_cast<unsigned long long>(nodes),
                static_cast<unsigned long long>(valid), static_cast<unsigned long long>(mb.blanked),
                static_cast<unsigned long long>(mb.nonfinite));
    std::printf("  bounds: %.9g %.9g %.9g .. %.9g %.9g %.9g\n", bmin.x, bmin.y, bmin.z, bmax.x, bmax.y, bmax.z);
    if (!det.files.empty()) std::printf("  pieces read: %zu\n", det.files.size());
    for (const auto& f : det.files)
        std::printf("    %s -> %s\n", terminal_safe(f).c_str(), terminal_safe(resolved_path(f)).c_str());
    std::printf("  blocks: %zu\n", mb.blocks.size());
    const std::size_t shown = std::min<std::size_t>(mb.blocks.size(), 16);
    for (std::size_t i = 0; i < shown; ++i) {
        const auto& b = mb.blocks[i];
        std::printf("    %s: %lld x %lld x %lld %s\n", ply_escape(b.name, 200).c_str(), static_cast<long long>(b.dims[0]),
                    static_cast<long long>(b.dims[1]), static_cast<long long>(b.dims[2]),
                    b.cell_centred ? "cell centres" : "points");
    }
    if (shown < mb.blocks.size()) std::printf("    ... (%zu more)\n", mb.blocks.size() - shown);
}

bool is_collection(const std::string& path) {
    const std::string e = lower_extension(path);
    return e == ".vtm" || e == ".vthb";
}

// A .raw that --dims describes is a volume, whatever the point-set sniffing would say (as for the
// volume commands, cli/scattered_isosurface.cpp scattered_invocation).
bool raw_volume_given(const std::string& path, const Args& a) { return lower_extension(path) == ".raw" && a.has("dims"); }

void describe(const std::string& path, const Args& a) {
    unsigned char h[32] = {};
    std::size_t n = 0;
    std::error_code ec;
    const bool dir = std::filesystem::is_directory(path, ec);  // a vtk-js image is a directory
    if (path != "-" && !dir) {
        InputFile in(path);
        n = std::fread(h, 1, sizeof h, in.f);
    }
    if (path == "-" || (n >= 8 && std::memcmp(h, "\x89MLS", 4) == 0)) {
        info_stream(path);
    } else if (n >= 4 && std::memcmp(h, "ply", 3) == 0 && (h[3] == '\n' || h[3] == '\r')) {
        info_ply(path);
    } else if (n >= 8 && std::memcmp(h, kBrickStoreMagic, 8) == 0) {
        info_brick_store(path);
    } else if (n >= 8 && is_sample_store(path)) {
        info_sample_store(path);
    } else if (n >= 8 && std::memcmp(h, kFieldFileMagic, 8) == 0) {
        info_field_file(path);
    } else if (n >= 8 && std::memcmp(h, kClusterTreeMagic, 8) == 0) {
        info_cluster_tree(path);
    } else if (n >= 8 && std::memcmp(h, "\x89PNG", 4) == 0) {
        info_png(path, h, n);
    } else if (is_collection(path)) {
        info_multiblock(path, a);
    } else if (!raw_volume_given(path, a) && looks_like_point_set(path)) {
        info_point_set(path, a);
    } else {
        info_volume(path, a);
        if (a.has("value-range")) {
            check_volume_fits(a, path, probe_volume(path, raw_options(a)), /*map=*/false);  // read whole
            const Volume v = read_volume(path, raw_options(a));
            const auto r = v.value_range();
            std::printf("  value range: %g .. %g\n", r[0], r[1]);
        }
    }
}

}  // namespace

int cmd_info(int argc, char** argv) {
    Args a("info", "FILE...",
           "Describes files meshless reads or writes: volumes (format, dims, type, spacing, value range; the payload\n"
           "is checked and decoded through a small buffer, so bombs, truncated or corrupt data are reported),\n"
           "point/sample streams (records, frames, metadata; checks the END frame), brick stores (.mlb),\n"
           "sample stores (.mls), fitted fields (.mlf: kind, parameters, the data it was fitted to), PLY (point sets are read through, so truncation is reported), PNG, and\n"
           "scattered/multiblock point sets (CSV/TSV/text, .vtp, .vts, PLOT3D .bin/.xyz/.p3d, raw float32\n"
           "records, .npy): points, blocks and dims, value name and range, bounds, dropped samples;\n"
           "VTK multiblock .vtm and AMR .vthb/.vtm hierarchies: levels, boxes per level, refinement,\n"
           "spacing, arrays with their centring, the chosen array's range (--value), blocks and dims.\n"
           "Files that cannot be described are reported on stderr; the others are still described.");
    a.flag("value-range", "volumes: also read the samples and print the value range").deprecated_alias("range");
    a.positionals(1, 100000);
    add_volume_options(a);
    add_point_set_options(a, false);
    if (!a.parse(argc, argv, 2)) return 0;
    if (a.positional().empty()) throw UsageError("missing FILE argument");
    int status = 0;
    for (const std::string& path : a.positional()) {
        try {
            describe(path, a);
        } catch (const std::exception& e) {  // report, go on with the other files, exit 2 at the end
            if (exit_code(e) == kExitUsage) throw;  // a bad option (UsageError, InvalidArgument) fails them all
            std::fflush(stdout);
            std::fprintf(stderr, "meshless info: %s\n", error_message(e).c_str());
            status = 2;
        }
    }
    return status;
}

}  // namespace meshless::cli
