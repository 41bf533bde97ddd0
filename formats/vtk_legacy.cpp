#include "formats/vtk_legacy.hpp"

#include <algorithm>
#include <cmath>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"
#include "kernels/flip_axes.hpp"

namespace meshless {

namespace {

std::optional<StoredType> vtk_type(const std::string& t) {
    const std::string l = to_lower(t);
    if (l == "unsigned_char") return StoredType::u8;
    if (l == "char" || l == "signed_char") return StoredType::i8;
    if (l == "unsigned_short") return StoredType::u16;
    if (l == "short") return StoredType::i16;
    if (l == "unsigned_int") return StoredType::u32;
    if (l == "int") return StoredType::i32;
    if (l == "unsigned_long" || l == "vtktypeuint64") return StoredType::u64;
    if (l == "long" || l == "vtktypeint64" || l == "vtkidtype") return StoredType::i64;
    if (l == "float") return StoredType::f32;
    if (l == "double") return StoredType::f64;
    return std::nullopt;
}

struct Cursor {
    const std::string& text;
    std::size_t pos = 0;
    // Next non-blank line (trimmed) and its start; false at the end of the text.
    bool next_line(std::string& line, std::size_t* start = nullptr) {
        while (pos < text.size()) {
            const std::size_t s = pos;
            std::size_t nl = text.find('\n', pos);
            if (nl == std::string::npos) return false;  // incomplete line: need more header
            pos = nl + 1;
            line = trim(std::string_view(text).substr(s, nl - s));
            if (!line.empty()) {
                if (start) *start = s;
                return true;
            }
        }
        return false;
    }
};

}  // namespace

PayloadPlan plan_vtk_legacy(const std::string& path) {
    const std::uint64_t fsize = regular_file_size(path);
    const std::string text = read_file_prefix(path, static_cast<std::size_t>(std::min<std::uint64_t>(fsize, 1 << 16)));
    if (text.rfind("# vtk DataFile", 0) != 0 && to_lower(text.substr(0, 14)) != "# vtk datafile")
        throw FormatError(path + ": not a VTK legacy file (wrong magic, expected '# vtk DataFile Version')");
    Cursor c{text};
    std::string line;
    const auto need = [&](const char* what) {
        if (!c.next_line(line)) throw FormatError(path + ": VTK header ends before " + std::string(what));
    };
    c.next_line(line);  // magic
    // the title may be empty: take the raw second line
    {
        const std::size_t nl = text.find('\n', c.pos);
        if (nl == std::string::npos) throw FormatError(path + ": VTK header ends before the title line");
        c.pos = nl + 1;
    }
    need("ASCII/BINARY");
    const std::string mode = to_lower(line);
    bool binary;
    if (mode == "binary")
        binary = true;
    else if (mode == "ascii")
        binary = false;
    else
        throw FormatError(path + ": bad VTK file type '" + escape_field(line) + "': expected ASCII or BINARY");

    need("DATASET");
    auto tk = split_ws(line);
    if (tk.size() < 2 || to_lower(tk[0]) != "dataset")
        throw FormatError(path + ": expected 'DATASET STRUCTURED_POINTS', got '" + escape_field(line) + "'");
    if (to_lower(tk[1]) != "structured_points")
        throw FormatError(path + ": unsupported VTK dataset '" + escape_field(tk[1]) + "' (STRUCTURED_POINTS supported)");

    PayloadPlan plan;
    plan.format = "vtk-legacy";
    plan.files = {path};
    plan.big_endian = true;
    plan.encoding = binary ? PayloadEncoding::raw : PayloadEncoding::ascii;
    bool have_dims = false;
    std::int64_t npoints = -1;
    std::array<double, 3> signed_spacing{1.0, 1.0, 1.0};
    for (;;) {
        need("the point scalars");
        tk = split_ws(line);
        const std::string key = to_lower(tk[0]);
        if (key == "dimensions") {
            const auto d = parse_ints(line.substr(tk[0].size()), 3, path, "DIMENSIONS");
            for (int a = 0; a < 3; ++a) {
                if (d[a] < 1) throw FormatError(path + ": bad DIMENSIONS: sizes must be >= 1");
                plan.grid.dims[a] = d[a];
            }
            have_dims = true;
        } else if (key == "spacing" || key == "aspect_ratio") {
            const auto s = parse_doubles(line.substr(tk[0].size()), 3, path, "SPACING");
            for (int a = 0; a < 3; ++a) {
                if (s[a] == 0 || !std::isfinite(s[a])) throw FormatError(path + ": bad SPACING: zero or non-finite spacing");
                signed_spacing[a] = s[a];  // negative: a flipped axis (below)
            }
        } else if (key == "origin") {
            const auto o = parse_doubles(line.substr(tk[0].size()), 3, path, "ORIGIN");
            for (int a = 0; a < 3; ++a) plan.grid.origin[a] = o[a];
        } else if (key == "point_data") {
            if (tk.size() != 2) throw FormatError(path + ": bad POINT_DATA line");
            npoints = static_cast<std::int64_t>(checked_count(parse_int(tk[1], path, "POINT_DATA"), path + ": POINT_DATA"));
        } else if (key == "cell_data") {
            throw FormatError(path + ": CELL_DATA before point scalars is not supported");
        } else if (key == "scalars" || key == "field") {
            if (npoints < 0) throw FormatError(path + ": " + tk[0] + " before POINT_DATA (cell data is not supported)");
            std::string type_name;
            if (key == "scalars") {
                if (tk.size() < 3) throw FormatError(path + ": bad SCALARS line '" + escape_field(line) + "'");
                type_name = tk[2];
                if (tk.size() >= 4 && parse_int(tk[3], path, "SCALARS components") != 1)
                    throw FormatError(path + ": unsupported SCALARS with " + escape_field(tk[3]) + " components");
                // optional LOOKUP_TABLE line
                const std::size_t save = c.pos;
                std::string l2;
                if (c.next_line(l2) && to_lower(split_ws(l2)[0]) == "lookup_table") {
                    // data starts after this line
                } else {
                    c.pos = save;
                }
            } else {
                need("the FIELD array");
                const auto a = split_ws(line);
                if (a.size() != 4) throw FormatError(path + ": bad FIELD array line '" + escape_field(line) + "'");
                if (parse_int(a[1], path, "FIELD components") != 1)
                    throw FormatError(path + ": unsupported FIELD array with " + escape_field(a[1]) + " components");
                if (parse_int(a[2], path, "FIELD tuples") != npoints)
                    throw FormatError(path + ": FIELD array has " + escape_field(a[2]) + " tuples, POINT_DATA is " + std::to_string(npoints));
                type_name = a[3];
            }
            if (to_lower(type_name) == "bit") throw FormatError(path + ": unsupported VTK scalar type 'bit'");
            const auto t = vtk_type(type_name);
            if (!t) throw FormatError(path + ": unknown VTK scalar type '" + escape_field(type_name) + "'");
            plan.type = *t;
            plan.file_offset = c.pos;
            break;
        }
        // other keywords (e.g. METADATA) are ignored
    }
    if (!have_dims) throw FormatError(path + ": missing DIMENSIONS");
    for (int a = 0; a < 3; ++a) honour_signed_spacing(plan.grid, plan.flip, a, signed_spacing[a]);
    validate_grid(plan.grid, path);
    if (npoints != plan.grid.voxel_count())
        throw FormatError(path + ": POINT_DATA " + std::to_string(npoints) + " does not match DIMENSIONS " +
                          dims_string(plan.grid));
    return plan;
}

VolumeInfo probe_vtk_legacy(const std::string& path) { return info_from_plan(plan_vtk_legacy(path)); }
Volume read_vtk_legacy(const std::string& path) { return read_payload(plan_vtk_legacy(path)); }

}  // namespace meshless
