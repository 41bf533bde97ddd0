#include "formats/vtk_legacy.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>

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

constexpr std::uint64_t kHeaderBytes = 1 << 16;  // the keywords before the first point array lie here
constexpr std::uint64_t kWindow = 1 << 16;       // past it, the file is read a window at a time

// The lines of a legacy file. Until `whole_file` is set, only its first 64 KiB (the header and the
// first point array's keywords must lie there); then windows of the whole file, read as needed
// (the arrays after the first, reached by skipping the values before them).
class Lines {
public:
    Lines(const std::string& path, std::uint64_t size)
        : path_(path), size_(size), buf_(read_file_prefix(path, static_cast<std::size_t>(std::min(size, kHeaderBytes)))) {}
    const std::string& prefix() const { return buf_; }  // before whole_file is set
    std::uint64_t pos = 0;
    bool whole_file = false;

    // The offset of the next '\n' at or after `at`; npos when there is none in reach (a line
    // longer than a window ends the lines too).
    std::uint64_t newline_at(std::uint64_t at) {
        for (bool loaded = false;; loaded = true) {
            if (at >= base_ && at <= base_ + buf_.size()) {
                const std::size_t nl = buf_.find('\n', static_cast<std::size_t>(at - base_));
                if (nl != std::string::npos) return base_ + nl;
                if (!whole_file || base_ + buf_.size() >= size_ || loaded) return npos;
            } else if (!whole_file) {
                return npos;
            }
            load(at);
        }
    }
    // Next non-blank line (trimmed); false at the end of the text.
    bool next_line(std::string& line) {
        while (pos < size_) {
            const std::uint64_t nl = newline_at(pos);
            if (nl == npos) return false;  // incomplete line: need more header
            const std::uint64_t s = pos;
            pos = nl + 1;
            line = trim(std::string_view(buf_).substr(static_cast<std::size_t>(s - base_), static_cast<std::size_t>(nl - s)));
            if (!line.empty()) return true;
        }
        return false;
    }
    // Past `n` bytes of binary values.
    void skip_bytes(std::uint64_t n, const std::string& what) {
        if (n > size_ - std::min(pos, size_)) throw FormatError(path_ + ": the file ends within the values of " + what);
        pos += n;
    }
    // Past `n` whitespace-separated ascii values.
    void skip_values(std::uint64_t n, const std::string& what) {
        std::uint64_t seen = 0;
        bool in_token = false;
        while (seen < n) {
            if (pos >= size_) {
                if (in_token && ++seen == n) return;
                throw FormatError(path_ + ": the file ends within the values of " + what + " (" + std::to_string(seen) +
                                  " of " + std::to_string(n) + ")");
            }
            if (pos < base_ || pos >= base_ + buf_.size()) load(pos);
            const std::size_t end = buf_.size();
            for (std::size_t i = static_cast<std::size_t>(pos - base_); i < end; ++i) {
                const bool space = std::isspace(static_cast<unsigned char>(buf_[i])) != 0;
                if (space && in_token && ++seen == n) {
                    pos = base_ + i;
                    return;
                }
                in_token = !space;
            }
            pos = base_ + end;
        }
    }
    static constexpr std::uint64_t npos = ~std::uint64_t{0};

private:
    void load(std::uint64_t at) {
        const auto b = read_file_range(path_, at, std::min(kWindow, size_ - at));
        buf_.assign(reinterpret_cast<const char*>(b.data()), b.size());
        base_ = at;
    }
    const std::string& path_;
    std::uint64_t size_;
    std::string buf_;
    std::uint64_t base_ = 0;
};

// One point array's header as read: what is listed, and what reading or skipping it needs.
struct ArrayHead {
    std::string kind;       // SCALARS, FIELD, VECTORS, NORMALS, TENSORS, TEXTURE_COORDINATES, COLOR_SCALARS
    std::string name, type_name, components_text;
    std::int64_t components = 1, tuples = 0;
    bool scalars = false;   // SCALARS or a FIELD array: the default is the first of these
};

// Bytes (binary) or values (ascii) of an array's data; nullopt for a type whose size is unknown.
std::optional<std::uint64_t> data_size(const ArrayHead& a, bool binary, const std::string& path) {
    const std::uint64_t n = checked_mul(checked_count(a.components, path + ": " + a.kind + " components"),
                                        checked_count(a.tuples, path + ": " + a.kind + " tuples"), path + ": array size");
    if (!binary) return n;
    if (a.kind == "COLOR_SCALARS") return n;  // unsigned char in binary files
    if (to_lower(a.type_name) == "bit") return n / 8 + (n % 8 != 0);
    const auto t = vtk_type(a.type_name);
    if (!t) return std::nullopt;
    return checked_mul(n, stored_size(*t), path + ": array size");
}

}  // namespace

PayloadPlan plan_vtk_legacy(const std::string& path, const std::string& array, bool list_all) {
    const std::uint64_t fsize = regular_file_size(path);
    Lines c(path, fsize);
    const std::string& text = c.prefix();
    if (text.rfind("# vtk DataFile", 0) != 0 && to_lower(text.substr(0, 14)) != "# vtk datafile")
        throw FormatError(path + ": not a VTK legacy file (wrong magic, expected '# vtk DataFile Version')");
    std::string line;
    const auto need = [&](const char* what) {
        if (!c.next_line(line)) throw FormatError(path + ": VTK header ends before " + std::string(what));
    };
    c.next_line(line);  // magic
    // the title may be empty: take the raw second line
    {
        const std::uint64_t nl = c.newline_at(c.pos);
        if (nl == Lines::npos) throw FormatError(path + ": VTK header ends before the title line");
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
    // Without a name to find and a list to make, the first SCALARS or FIELD array is read and the
    // keywords before it that are not the grid's are passed over as they always were; otherwise
    // every point array is parsed, listed and its values skipped until the one to read is found
    // (and, listing, until the point data ends: after the array read, a line not understood ends
    // the list).
    const bool scan = list_all || !array.empty();
    const auto array_head = [&](const std::string& key) {
        ArrayHead a;
        a.kind = to_lower(key);
        for (char& ch : a.kind) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
        a.tuples = npoints;
        if (key == "scalars") {
            if (tk.size() < 3) throw FormatError(path + ": bad SCALARS line '" + escape_field(line) + "'");
            a.name = tk[1];
            a.type_name = tk[2];
            a.scalars = true;
            if (tk.size() >= 4) {
                a.components_text = tk[3];
                a.components = parse_int(tk[3], path, "SCALARS components");
            }
            // optional LOOKUP_TABLE line
            const std::uint64_t save = c.pos;
            std::string l2;
            if (c.next_line(l2) && to_lower(split_ws(l2)[0]) == "lookup_table") {
                // data starts after this line
            } else {
                c.pos = save;
            }
        } else if (key == "field") {
            need("the FIELD array");
            const auto f = split_ws(line);
            if (f.size() != 4) throw FormatError(path + ": bad FIELD array line '" + escape_field(line) + "'");
            a.name = f[0];
            a.components_text = f[1];
            a.components = parse_int(f[1], path, "FIELD components");
            a.tuples = parse_int(f[2], path, "FIELD tuples");
            a.type_name = f[3];
            a.scalars = true;
        } else {  // VECTORS NORMALS TENSORS name type; TEXTURE_COORDINATES name dim type; COLOR_SCALARS name n
            const bool sized = key == "texture_coordinates" || key == "color_scalars";
            if (tk.size() < (key == "color_scalars" ? 3u : sized ? 4u : 3u))
                throw FormatError(path + ": bad " + a.kind + " line '" + escape_field(line) + "'");
            a.name = tk[1];
            a.components = key == "vectors" || key == "normals" ? 3 : key == "tensors" ? 9 : parse_int(tk[2], path, a.kind.c_str());
            a.type_name = key == "color_scalars" ? std::string(binary ? "unsigned_char" : "float") : sized ? tk[3] : tk[2];
        }
        return a;
    };
    // The chosen array's checks (the messages the first array always had) and its plan.
    const auto plan_array = [&](const ArrayHead& a) {
        if (a.kind == "SCALARS" && a.components != 1)
            throw FormatError(path + ": unsupported SCALARS with " + escape_field(a.components_text) + " components");
        if (a.kind == "FIELD") {
            if (a.components != 1)
                throw FormatError(path + ": unsupported FIELD array with " + escape_field(a.components_text) + " components");
            if (a.tuples != npoints)
                throw FormatError(path + ": FIELD array has " + std::to_string(a.tuples) + " tuples, POINT_DATA is " + std::to_string(npoints));
        }
        if (!a.scalars)
            throw FormatError(path + ": unsupported " + a.kind + " array '" + escape_field(a.name) + "' with " +
                              std::to_string(a.components) + " components");
        if (to_lower(a.type_name) == "bit") throw FormatError(path + ": unsupported VTK scalar type 'bit'");
        const auto t = vtk_type(a.type_name);
        if (!t) throw FormatError(path + ": unknown VTK scalar type '" + escape_field(a.type_name) + "'");
        plan.type = *t;
        plan.file_offset = c.pos;
    };
    const auto listed = [&](const ArrayHead& a) {
        VolumeArray v;
        v.name = a.name;
        const auto t = vtk_type(a.type_name);
        v.type = t ? to_string(*t) : escape_field(a.type_name);
        v.components = a.components;
        return v;
    };
    const auto skip_data = [&](const ArrayHead& a) {
        const std::string what = a.kind + " '" + escape_field(a.name) + "'";
        const auto n = data_size(a, binary, path);
        if (!n) throw FormatError(path + ": unknown VTK type '" + escape_field(a.type_name) + "' of " + what + ": its values cannot be skipped");
        c.whole_file = true;
        if (binary)
            c.skip_bytes(*n, what);
        else
            c.skip_values(*n, what);
    };
    bool found = false;  // the array to read has been planned
    std::optional<ArrayHead> first;  // the first point array met in the header (scan: its values skipped next)
    bool have_default = false;
    std::int64_t field_left = 0;  // FIELD arrays still to come in the current FIELD block
    const auto is_array_key = [](const std::string& k) {
        return k == "vectors" || k == "normals" || k == "tensors" || k == "texture_coordinates" || k == "color_scalars";
    };
    // the header, up to the first point array
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
        } else if (key == "scalars" || key == "field" || (scan && npoints >= 0 && is_array_key(key))) {
            if (npoints < 0) throw FormatError(path + ": " + tk[0] + " before POINT_DATA (cell data is not supported)");
            if (key == "field" && scan) {  // FIELD name k: k arrays, each followed by its values
                if (tk.size() < 3) throw FormatError(path + ": bad FIELD line '" + escape_field(line) + "'");
                field_left = parse_int(tk[2], path, "FIELD arrays");
                if (field_left < 1) throw FormatError(path + ": bad FIELD line '" + escape_field(line) + "'");
            }
            const ArrayHead a = array_head(key);
            if (key == "field" && scan) --field_left;
            const std::size_t k = plan.arrays.size();
            plan.arrays.push_back(listed(a));
            if (a.scalars && !have_default) plan.default_array = k, have_default = true;
            if ((array.empty() && a.scalars) || (!array.empty() && a.name == array)) {
                plan_array(a);
                plan.read_array = k;
                found = true;
            }
            first = a;
            break;
        }
        // other keywords (e.g. METADATA) are ignored
    }
    // the point arrays after the first (scan only): listed, their values skipped, the one to read planned
    if (scan) {
        // lists `a`, makes it the default when it is the first scalars, plans it when it is the one
        // read, else skips its values; false: stop here (the array read is found, nothing more to list)
        const auto take = [&](const ArrayHead& a, bool scalars) -> bool {
            const std::size_t k = plan.arrays.size();
            plan.arrays.push_back(listed(a));
            const bool first_scalars = scalars && !have_default;
            if (first_scalars) plan.default_array = k, have_default = true;
            if (!found && ((array.empty() && first_scalars) || (!array.empty() && a.name == array))) {
                plan_array(a);
                plan.read_array = k, found = true;
                if (!list_all) return false;
            }
            skip_data(a);
            return true;
        };
        const auto next_array = [&]() -> bool {  // false: the point data ends (or what follows is not understood)
            if (field_left > 0) {
                const ArrayHead a = array_head("field");
                --field_left;
                return take(a, true);
            }
            if (!c.next_line(line)) return false;
            tk = split_ws(line);
            const std::string key = to_lower(tk[0]);
            if (key == "lookup_table") {  // a table of a SCALARS array: size RGBA entries
                if (tk.size() < 3) return false;
                ArrayHead t;
                t.kind = "LOOKUP_TABLE", t.name = tk[1], t.components = 4, t.type_name = binary ? "unsigned_char" : "float";
                t.tuples = parse_int(tk[2], path, "LOOKUP_TABLE size");
                skip_data(t);
                return true;
            }
            if (key == "field") {
                if (tk.size() < 3) throw FormatError(path + ": bad FIELD line '" + escape_field(line) + "'");
                field_left = parse_int(tk[2], path, "FIELD arrays");
                if (field_left < 0) throw FormatError(path + ": bad FIELD line '" + escape_field(line) + "'");
                return true;
            }
            if (key != "scalars" && !is_array_key(key)) return false;  // CELL_DATA, METADATA, ...
            const ArrayHead a = array_head(key);
            return take(a, a.scalars);
        };
        // listing past the array read, a damaged tail ends the list: it is not an error (the payload's
        // own checks report a truncation of the array read, as they always did)
        const auto step = [&](const auto& fn) -> bool {
            try {
                return fn();
            } catch (const FormatError&) {
                if (!found) throw;
                return false;
            }
        };
        if (!found || list_all)
            for (bool more = step([&] { skip_data(*first); return true; }); more;) more = step(next_array);
        if (!found) {
            if (array.empty()) throw FormatError(path + ": VTK header ends before the point scalars");
            choose_volume_array(plan.arrays, plan.default_array, array, path);  // throws: lists the arrays
        }
    }
    if (!have_dims) throw FormatError(path + ": missing DIMENSIONS");
    for (int a = 0; a < 3; ++a) honour_signed_spacing(plan.grid, plan.flip, a, signed_spacing[a]);
    validate_grid(plan.grid, path);
    if (npoints != plan.grid.voxel_count())
        throw FormatError(path + ": POINT_DATA " + std::to_string(npoints) + " does not match DIMENSIONS " +
                          dims_string(plan.grid));
    return plan;
}

VolumeInfo probe_vtk_legacy(const std::string& path, const std::string& array, bool list_all) {
    return info_from_plan(plan_vtk_legacy(path, array, list_all));
}
Volume read_vtk_legacy(const std::string& path, const std::string& array) { return read_payload(plan_vtk_legacy(path, array)); }

}  // namespace meshless
