#include "stream/point_set_info.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "formats/multiblock_reader.hpp"
#include "formats/ply.hpp"
#include "formats/ply_mesh.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/reference_policy.hpp"
#include "formats/terminal_safe.hpp"
#include "formats/vtk_structured.hpp"

namespace meshless {

namespace {

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

// The vertex element summarised: count, bounds, the range of every other property, non-finite values.
std::string vertex_summary(PlyReader& r, const PlyHeader& h, int vi) {
    std::string summary;
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
    return summary;
}

}  // namespace

void describe_ply(const std::string& path, std::FILE* out) {
    // the header through the PLY codec, then the whole body read through (a truncated or corrupt
    // body is reported, not just the header)
    PlyReader r(path);
    const PlyHeader h = r.header();
    bool faces = false;
    for (const auto& e : h.elements) faces = faces || e.name != "vertex";
    std::string summary;
    const int vi = h.find("vertex");
    if (vi >= 0 && !h.elements[vi].has_lists()) summary = vertex_summary(r, h, vi);
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
    std::fprintf(out, "%s: PLY%s (body checked)\n%s%s  end_header\n", terminal_safe(path).c_str(), faces ? "" : " point set",
                 summary.c_str(), indented.c_str());
}

// Scattered and multiblock point sets (text, .vtp, .vts, PLOT3D, raw records, .npy): read through.
void describe_point_set(const std::string& path, const PointSetOptions& options, std::FILE* out) {
    const PointSetInfo info = probe_point_set(path, options);
    const PointSet& ps = info.set;
    std::fprintf(out, "%s: %s point set\n", terminal_safe(path).c_str(), info.format.c_str());
    for (const auto& n : info.notes) std::fprintf(out, "  %s\n", terminal_safe(n).c_str());
    std::fprintf(out, "  points: %zu\n", ps.size());
    std::fprintf(out, "  blocks: %zu\n", ps.blocks.size());
    const std::size_t listed = std::min<std::size_t>(ps.blocks.size(), 16);
    for (std::size_t b = 0; b < listed; ++b) {
        const auto& blk = ps.blocks[b];
        std::fprintf(out, "    %s: %lld x %lld x %lld, %llu points\n", terminal_safe(blk.name).c_str(),
                     static_cast<long long>(blk.dims[0]), static_cast<long long>(blk.dims[1]),
                     static_cast<long long>(blk.dims[2]), static_cast<unsigned long long>(blk.count));
    }
    if (listed < ps.blocks.size()) std::fprintf(out, "    ... (%zu more)\n", ps.blocks.size() - listed);
    if (ps.has_values) {
        const auto r = ps.value_range();
        std::fprintf(out, "  value: %s, range %.9g .. %.9g\n", ps.value_name.empty() ? "(unnamed)" : terminal_safe(ps.value_name).c_str(),
                     r[0], r[1]);
    } else {
        std::fprintf(out, "  value: none (positions only)\n");
    }
    const auto bb = ps.bounds();
    std::fprintf(out, "  bounds: %.12g %.12g %.12g .. %.12g %.12g %.12g\n", bb[0].x, bb[0].y, bb[0].z, bb[1].x, bb[1].y, bb[1].z);
    std::fprintf(out, "  dropped: %llu NaN/Inf, %llu blanked (IBLANK 0)\n", static_cast<unsigned long long>(ps.dropped_nonfinite),
                 static_cast<unsigned long long>(ps.dropped_blanked));
}

// VTK multiblock (.vtm) and AMR (.vthb, vtkHierarchicalBoxDataSet .vtm) collections.
void describe_multiblock(const std::string& path, const PointSetOptions& options, std::FILE* out) {
    MultiblockDetails det;
    const Multiblock mb = read_multiblock({path}, options, det);
    std::fprintf(out, "%s: %s\n", terminal_safe(path).c_str(), terminal_safe(det.description).c_str());
    for (const auto& n : mb.notes) std::fprintf(out, "  note: %s\n", ply_escape(n, 400).c_str());
    if (det.origin) std::fprintf(out, "  origin: %g %g %g\n", (*det.origin)[0], (*det.origin)[1], (*det.origin)[2]);
    for (const auto& l : det.levels) {
        std::fprintf(out, "  level %d: %zu box%s, spacing %g %g %g", l.level, l.boxes, l.boxes == 1 ? "" : "es", l.spacing[0],
                     l.spacing[1], l.spacing[2]);
        if (l.refinement) std::fprintf(out, ", refinement %d from level %d", l.refinement, l.level - 1);
        std::fprintf(out, "\n");
    }
    std::fprintf(out, "  arrays: %s\n", describe_arrays(det.arrays).c_str());
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
    std::fprintf(out, "  value: '%s' (%s), range %.9g .. %.9g\n", ply_escape(mb.value_name).c_str(),
                 det.cell ? "cell data: nodes at the cell centres" : "point data", lo, hi);
    std::fprintf(out, "  nodes: %llu, %llu valid (%llu blanked, %llu NaN/Inf)\n", static_cast<unsigned long long>(nodes),
                 static_cast<unsigned long long>(valid), static_cast<unsigned long long>(mb.blanked),
                 static_cast<unsigned long long>(mb.nonfinite));
    std::fprintf(out, "  bounds: %.9g %.9g %.9g .. %.9g %.9g %.9g\n", bmin.x, bmin.y, bmin.z, bmax.x, bmax.y, bmax.z);
    if (!det.files.empty()) std::fprintf(out, "  pieces read: %zu\n", det.files.size());
    for (const auto& f : det.files)
        std::fprintf(out, "    %s -> %s\n", terminal_safe(f).c_str(), terminal_safe(resolved_path(f)).c_str());
    std::fprintf(out, "  blocks: %zu\n", mb.blocks.size());
    const std::size_t shown = std::min<std::size_t>(mb.blocks.size(), 16);
    for (std::size_t i = 0; i < shown; ++i) {
        const auto& b = mb.blocks[i];
        std::fprintf(out, "    %s: %lld x %lld x %lld %s\n", ply_escape(b.name, 200).c_str(), static_cast<long long>(b.dims[0]),
                     static_cast<long long>(b.dims[1]), static_cast<long long>(b.dims[2]),
                     b.cell_centred ? "cell centres" : "points");
    }
    if (shown < mb.blocks.size()) std::fprintf(out, "    ... (%zu more)\n", mb.blocks.size() - shown);
}

}  // namespace meshless
