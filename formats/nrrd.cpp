#include "formats/nrrd.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "formats/binary_file.hpp"
#include "formats/length_unit.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"
#include "kernels/flip_axes.hpp"

namespace meshless {

namespace {

// `space units: "mm" "mm" "mm"` (quoted, as the format writes them; bare words are taken too): the
// unit when there are three and each names the same known unit, else "".
std::string nrrd_space_unit(const std::string& val) {
    std::vector<std::string> tokens;
    if (val.find('"') != std::string::npos) {
        for (std::size_t at = val.find('"'); at != std::string::npos; at = val.find('"', at)) {
            const std::size_t end = val.find('"', at + 1);
            if (end == std::string::npos) return {};
            tokens.push_back(val.substr(at + 1, end - at - 1));
            at = end + 1;
        }
    } else {
        tokens = split_ws(val);
    }
    if (tokens.size() != 3) return {};
    const std::string unit = length_unit_from_name(tokens[0]);
    for (const std::string& t : tokens)
        if (length_unit_from_name(t) != unit) return {};
    return unit;
}

struct HeaderText {
    std::string text;           // header lines (without the blank separator line)
    std::uint64_t data_offset;  // first byte after the blank line (attached data)
    bool has_blank = false;
};

HeaderText read_header_text(const std::string& path) {
    const std::uint64_t size = regular_file_size(path);
    std::size_t want = 1 << 16;
    for (;;) {
        const std::string s = read_file_prefix(path, want);
        for (std::size_t i = 0; i + 1 < s.size(); ++i) {
            if (s[i] != '\n') continue;
            std::size_t j = i + 1;
            if (j < s.size() && s[j] == '\r') ++j;
            if (j < s.size() && s[j] == '\n') return {s.substr(0, i), static_cast<std::uint64_t>(j + 1), true};
        }
        if (s.size() >= size || want >= (std::size_t{1} << 26)) {
            if (s.size() < size)
                throw FormatError(path + ": NRRD header longer than 64 MiB or missing its blank line");
            return {s, size, false};
        }
        want *= 4;
    }
}

}  // namespace

PayloadPlan plan_nrrd(const std::string& path) {
    const HeaderText h = read_header_text(path);
    const auto lines = split_lines(h.text);
    if (lines.empty() || lines[0].rfind("NRRD", 0) != 0)
        throw FormatError(path + ": not a NRRD file (wrong magic, expected NRRD000N)");
    const std::string magic = trim(lines[0]);
    if (magic.size() != 8 || magic.compare(0, 7, "NRRD000") != 0 || magic[7] < '1' || magic[7] > '5')
        throw FormatError(path + ": unsupported NRRD version '" + escape_field(magic) + "' (NRRD0001..NRRD0005 supported)");

    PayloadPlan plan;
    plan.header = path;
    plan.format = "nrrd";
    std::int64_t dimension = -1;
    std::vector<std::int64_t> sizes;
    std::vector<std::string> spacings_tok, directions_tok;
    std::string origin_tok, type_tok, encoding_tok = "", endian_tok, space_tok;
    std::vector<std::string> files;
    bool have_data_file = false;
    for (std::size_t li = 1; li < lines.size(); ++li) {
        const std::string line = trim(lines[li]);
        if (line.empty() || line[0] == '#') continue;
        if (line.find(":=") != std::string::npos) continue;  // key/value pairs: ignored
        const auto colon = line.find(": ");
        const auto colon2 = colon == std::string::npos ? line.find(':') : colon;
        if (colon2 == std::string::npos)
            throw FormatError(path + ": bad NRRD header line " + std::to_string(li + 1) + " '" + escape_field(line) +
                              "': expected 'field: value'");
        const std::string key = to_lower(trim(line.substr(0, colon2)));
        const std::string val = trim(line.substr(colon2 + 1));
        if (key == "dimension") {
            dimension = parse_int(val, path, "dimension");
            if (dimension < 1 || dimension > 16) throw FormatError(path + ": bad dimension '" + escape_field(val) + "'");
        } else if (key == "type") {
            type_tok = val;
        } else if (key == "sizes") {
            for (const auto& t : split_ws(val)) sizes.push_back(parse_int(t, path, "sizes"));
        } else if (key == "spacings") {
            spacings_tok = split_ws(val);
        } else if (key == "space directions") {
            // "(1,0,0) (0,1,0) none" -> one token per axis
            std::string cur;
            int depth = 0;
            for (char c : val) {
                if (c == '(') ++depth;
                if (c == ')') --depth;
                if (std::isspace(static_cast<unsigned char>(c)) && depth == 0) {
                    if (!cur.empty()) directions_tok.push_back(cur), cur.clear();
                } else {
                    cur += c;
                }
            }
            if (!cur.empty()) directions_tok.push_back(cur);
        } else if (key == "space") {
            space_tok = to_lower(val);
        } else if (key == "sample units" || key == "sampleunits") {
            plan.value_unit = value_unit_text(val);
        } else if (key == "space units") {
            plan.length_unit = nrrd_space_unit(val);
        } else if (key == "space origin") {
            origin_tok = val;
        } else if (key == "encoding") {
            encoding_tok = to_lower(val);
        } else if (key == "endian") {
            endian_tok = to_lower(val);
        } else if (key == "byte skip" || key == "byteskip") {
            plan.byte_skip = parse_int(val, path, "byte skip");
            if (plan.byte_skip < -1) throw FormatError(path + ": bad byte skip '" + escape_field(val) + "'");
        } else if (key == "line skip" || key == "lineskip") {
            plan.line_skip = parse_int(val, path, "line skip");
            if (plan.line_skip < 0) throw FormatError(path + ": bad line skip '" + escape_field(val) + "'");
        } else if (key == "data file" || key == "datafile") {
            have_data_file = true;
            const auto tk = split_ws(val);
            if (tk.empty()) throw FormatError(path + ": empty data file field");
            if (tk[0] == "LIST") {
                for (std::size_t lj = li + 1; lj < lines.size(); ++lj) {
                    const std::string f = trim(lines[lj]);
                    if (!f.empty()) files.push_back(resolve_relative(path, f));
                }
                li = lines.size();
            } else if (tk.size() >= 4) {
                const std::int64_t a = parse_int(tk[1], path, "data file min");
                const std::int64_t b = parse_int(tk[2], path, "data file max");
                const std::int64_t s = parse_int(tk[3], path, "data file step");
                for (const std::int64_t i : file_range_indices(a, b, s, path, "data file"))
                    files.push_back(resolve_relative(path, format_file_pattern(tk[0], i, path)));
            } else if (tk.size() == 1) {
                files.push_back(resolve_relative(path, tk[0]));
            } else {
                throw FormatError(path + ": bad data file field '" + escape_field(val) + "'");
            }
        }
        // other fields (kinds, centers, content, units, ...) are ignored
    }
    if (dimension < 0) throw FormatError(path + ": missing NRRD field 'dimension'");
    if (type_tok.empty()) throw FormatError(path + ": missing NRRD field 'type'");
    if (sizes.size() != static_cast<std::size_t>(dimension))
        throw FormatError(path + ": 'sizes' has " + std::to_string(sizes.size()) + " entries, dimension is " +
                          std::to_string(dimension));
    for (auto s : sizes)
        if (s < 1) throw FormatError(path + ": bad sizes: every size must be >= 1");
    if (type_tok == "block") throw FormatError(path + ": unsupported NRRD type 'block'");
    const auto st = parse_stored_type(type_tok);
    if (!st) throw FormatError(path + ": unknown NRRD type '" + escape_field(type_tok) + "'");
    plan.type = *st;

    if (encoding_tok.empty()) throw FormatError(path + ": missing NRRD field 'encoding'");
    if (encoding_tok == "raw")
        plan.encoding = PayloadEncoding::raw;
    else if (encoding_tok == "gzip" || encoding_tok == "gz")
        plan.encoding = PayloadEncoding::gzip;
    else if (encoding_tok == "ascii" || encoding_tok == "text" || encoding_tok == "txt")
        plan.encoding = PayloadEncoding::ascii;
    else
        throw FormatError(path + ": unsupported NRRD encoding '" + escape_field(encoding_tok) + "' (raw, gzip, ascii supported)");
    if (endian_tok.empty() || endian_tok == "little")
        plan.big_endian = false;
    else if (endian_tok == "big")
        plan.big_endian = true;
    else
        throw FormatError(path + ": bad endian '" + escape_field(endian_tok) + "'");

    // Per-axis spacing; an axis is spatial unless its direction is "none".
    const std::size_t d = sizes.size();
    std::vector<double> spacing(d, 1.0);
    std::vector<bool> spatial(d, true);
    if (!directions_tok.empty()) {
        if (directions_tok.size() != d)
            throw FormatError(path + ": 'space directions' has " + std::to_string(directions_tok.size()) +
                              " entries, dimension is " + std::to_string(d));
        for (std::size_t a = 0; a < d; ++a) {
            if (directions_tok[a] == "none") {
                spatial[a] = false;
                continue;
            }
            std::string v = directions_tok[a];
            if (v.size() < 2 || v.front() != '(' || v.back() != ')')
                throw FormatError(path + ": bad space direction '" + escape_field(v) + "'");
            v = v.substr(1, v.size() - 2);
            double n2 = 0;
            std::string w = v;
            for (auto& c : w)
                if (c == ',') c = ' ';
            for (const auto& t : split_ws(w)) {
                const double x = parse_double(t, path, "space directions");
                n2 += x * x;
            }
            if (!(n2 > 0)) throw FormatError(path + ": zero-length space direction '" + escape_field(directions_tok[a]) + "'");
            spacing[a] = std::sqrt(n2);
        }
    } else if (!spacings_tok.empty()) {
        if (spacings_tok.size() != d)
            throw FormatError(path + ": 'spacings' has " + std::to_string(spacings_tok.size()) + " entries, dimension is " +
                              std::to_string(d));
        for (std::size_t a = 0; a < d; ++a) {
            if (to_lower(spacings_tok[a]) == "nan") continue;
            spacing[a] = parse_double(spacings_tok[a], path, "spacings");  // negative: a flipped axis (below)
            if (!(spacing[a] != 0) || !std::isfinite(spacing[a]))
                throw FormatError(path + ": bad spacings: zero or non-finite spacing '" + escape_field(spacings_tok[a]) + "'");
        }
    }
    // Keep spatial axes; drop size-1 non-spatial axes; a non-spatial axis with size > 1 is a
    // multi-component volume, which we do not read.
    std::vector<std::size_t> keep;
    for (std::size_t a = 0; a < d; ++a) {
        if (!spatial[a]) {
            if (sizes[a] != 1)
                throw FormatError(path + ": unsupported NRRD with a non-spatial axis of size " + std::to_string(sizes[a]) +
                                  " (multi-component data)");
            continue;
        }
        keep.push_back(a);
    }
    if (keep.size() > 3) {
        std::vector<std::size_t> k2;
        for (auto a : keep)
            if (sizes[a] != 1) k2.push_back(a);
        while (k2.size() < 3) {  // e.g. 4-D 1x64x64x1: keep the first size-1 axes back in order
            for (auto a : keep)
                if (std::find(k2.begin(), k2.end(), a) == k2.end()) {
                    k2.insert(std::upper_bound(k2.begin(), k2.end(), a), a);
                    break;
                }
        }
        keep = k2;
        if (keep.size() > 3)
            throw FormatError(path + ": unsupported NRRD dimension " + std::to_string(d) + " (at most 3 axes of size > 1)");
    }
    for (std::size_t i = 0; i < 3; ++i) {
        plan.grid.dims[i] = i < keep.size() ? sizes[keep[i]] : 1;
    }
    if (!origin_tok.empty()) {
        std::string w = origin_tok;
        for (auto& c : w)
            if (c == '(' || c == ')' || c == ',') c = ' ';
        const auto tk = split_ws(w);
        for (std::size_t i = 0; i < 3 && i < tk.size(); ++i) plan.grid.origin[i] = parse_double(tk[i], path, "space origin");
    }
    std::vector<Vec3> dirs;  // `space directions` of the kept axes, when given for three of them
    if (!directions_tok.empty() && keep.size() == 3)
        for (const std::size_t a : keep) {
            std::string w = directions_tok[a];
            for (auto& c : w)
                if (c == '(' || c == ')' || c == ',') c = ' ';
            const auto tk = split_ws(w);
            if (tk.size() != 3) break;
            dirs.push_back(Vec3{parse_double(tk[0], path, "space directions"), parse_double(tk[1], path, "space directions"),
                                parse_double(tk[2], path, "space directions")});
        }
    // directions along the space's axes, forward or back: world coordinates (backward axes flipped)
    const auto signs = dirs.size() == 3 ? axis_aligned_signs({dirs[0], dirs[1], dirs[2]}) : std::nullopt;
    for (std::size_t i = 0; i < 3; ++i)
        honour_signed_spacing(plan.grid, plan.flip, static_cast<int>(i),
                              (i < keep.size() ? spacing[keep[i]] : 1.0) * (signs ? (*signs)[i] : 1.0));
    if (!space_tok.empty()) {
        plan.frame = nrrd_frame(space_tok, dirs.size() == 3 ? dirs : std::vector<Vec3>{});
        // a frame made from the directions describes the index axes: those the reader reversed turn
        // round; one made from the space alone (no directions, or the 3D-handed spaces) describes
        // the world axes, which the samples now follow
        if (dirs.size() == 3 && space_tok.rfind("3d-", 0) != 0) flip_frame(plan.frame, plan.flip);
    }

    if (have_data_file) {
        if (files.empty()) throw FormatError(path + ": 'data file' lists no files");
        plan.files = files;
        plan.file_offset = 0;
    } else {
        if (!h.has_blank)
            throw FormatError(path + ": NRRD header has neither a 'data file' field nor attached data after a blank line");
        plan.files = {path};
        plan.file_offset = h.data_offset;
    }
    return plan;
}

VolumeInfo probe_nrrd(const std::string& path) { return info_from_plan(plan_nrrd(path)); }
Volume read_nrrd(const std::string& path) { return read_payload(plan_nrrd(path)); }

}  // namespace meshless
