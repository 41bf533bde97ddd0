#include "formats/voreen_dat.hpp"

#include <cmath>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"

namespace meshless {

PayloadPlan plan_voreen_dat(const std::string& path) {
    if (regular_file_size(path) > (1 << 20)) throw FormatError(path + ": too large for a .dat header");
    const std::string text = read_file_prefix(path, 1 << 20);
    PayloadPlan plan;
    plan.header = path;
    plan.format = "voreen-dat";
    plan.exact_size = true;
    std::string object;
    bool have_res = false, have_fmt = false;
    for (const auto& raw_line : split_lines(text)) {
        const std::string line = trim(raw_line);
        if (line.empty() || line[0] == '#') continue;
        const auto colon = line.find(':');
        if (colon == std::string::npos)
            throw FormatError(path + ": bad .dat line '" + escape_field(line) + "': expected 'Key: value'");
        const std::string key = to_lower(trim(line.substr(0, colon)));
        const std::string val = trim(line.substr(colon + 1));
        if (key == "objectfilename") {
            object = val;
        } else if (key == "resolution") {
            const auto d = parse_ints(val, 3, path, "Resolution");
            for (int a = 0; a < 3; ++a) {
                if (d[a] < 1) throw FormatError(path + ": bad Resolution '" + escape_field(val) + "': sizes must be >= 1");
                plan.grid.dims[a] = d[a];
            }
            have_res = true;
        } else if (key == "slicethickness") {
            const auto s = parse_doubles(val, 3, path, "SliceThickness");
            for (int a = 0; a < 3; ++a) {
                if (!(s[a] > 0) || !std::isfinite(s[a])) throw FormatError(path + ": bad SliceThickness '" + escape_field(val) + "': must be > 0");
                plan.grid.spacing[a] = s[a];
            }
        } else if (key == "format") {
            std::string f = to_lower(val);
            if (f == "ushort_12") f = "ushort";
            const auto t = parse_stored_type(f);
            if (!t) throw FormatError(path + ": unknown Format '" + escape_field(val) + "'");
            plan.type = *t;
            have_fmt = true;
        } else if (key == "endianness" || key == "byteorder") {
            plan.big_endian = to_lower(val).find("big") != std::string::npos;
        }
    }
    if (object.empty()) throw FormatError(path + ": missing ObjectFileName");
    if (!have_res) throw FormatError(path + ": missing Resolution");
    if (!have_fmt) throw FormatError(path + ": missing Format");
    validate_grid(plan.grid, path);
    plan.files = {resolve_relative(path, object)};
    return plan;
}

VolumeInfo probe_voreen_dat(const std::string& path) { return info_from_plan(plan_voreen_dat(path)); }
Volume read_voreen_dat(const std::string& path) { return read_payload(plan_voreen_dat(path)); }

}  // namespace meshless
