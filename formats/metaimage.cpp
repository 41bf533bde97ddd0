#include "formats/metaimage.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"
#include "kernels/flip_axes.hpp"

namespace meshless {

namespace {
std::optional<StoredType> met_type(const std::string& v) {
    struct M { const char* n; StoredType t; };
    static constexpr M table[] = {
        {"MET_UCHAR", StoredType::u8},    {"MET_CHAR", StoredType::i8},
        {"MET_USHORT", StoredType::u16},  {"MET_SHORT", StoredType::i16},
        {"MET_UINT", StoredType::u32},    {"MET_INT", StoredType::i32},
        {"MET_ULONG", StoredType::u32},   {"MET_LONG", StoredType::i32},
        {"MET_ULONG_LONG", StoredType::u64}, {"MET_LONG_LONG", StoredType::i64},
        {"MET_FLOAT", StoredType::f32},   {"MET_DOUBLE", StoredType::f64},
    };
    for (const auto& m : table)
        if (v == m.n) return m.t;
    return std::nullopt;
}
}  // namespace

PayloadPlan plan_metaimage(const std::string& path) {
    const std::uint64_t fsize = regular_file_size(path);
    const std::string text = read_file_prefix(path, static_cast<std::size_t>(std::min<std::uint64_t>(fsize, 1 << 20)));
    PayloadPlan plan;
    plan.header = path;
    plan.format = "metaimage";
    std::int64_t ndims = -1;
    std::vector<std::int64_t> dims;
    std::string spacing_v, size_v, origin_v, type_v, data_file, transform_v, anatomical_v;
    std::int64_t header_size = 0, channels = 1;
    bool compressed = false, binary = true, have_data_file = false;
    std::uint64_t pos = 0, data_offset = 0;
    std::vector<std::string> list_files;
    const auto lines = split_lines(text);
    for (std::size_t li = 0; li < lines.size(); ++li) {
        const std::string& raw_line = lines[li];
        {
            const auto nl = text.find('\n', pos);
            pos = nl == std::string::npos ? text.size() : nl + 1;
        }
        const std::string line = trim(raw_line);
        if (line.empty() || line[0] == '#') continue;
        const auto eq = line.find('=');
        if (eq == std::string::npos)
            throw FormatError(path + ": bad MetaImage header line " + std::to_string(li + 1) + " '" +
                              escape_field(line) + "': expected 'Key = Value'");
        const std::string key = to_lower(trim(line.substr(0, eq)));
        const std::string val = trim(line.substr(eq + 1));
        if (key == "ndims") {
            ndims = parse_int(val, path, "NDims");
            if (ndims < 1 || ndims > 4) throw FormatError(path + ": unsupported NDims " + escape_field(val) + " (1..4 supported)");
        } else if (key == "dimsize") {
            for (const auto& t : split_ws(val)) dims.push_back(parse_int(t, path, "DimSize"));
        } else if (key == "elementspacing") {
            spacing_v = val;
        } else if (key == "elementsize") {
            size_v = val;
        } else if (key == "offset" || key == "position" || key == "origin") {
            origin_v = val;
        } else if (key == "transformmatrix" || key == "orientation" || key == "rotation") {
            transform_v = val;
        } else if (key == "anatomicalorientation") {
            anatomical_v = val;
        } else if (key == "elementtype") {
            type_v = val;
        } else if (key == "elementbyteordermsb" || key == "binarydatabyteordermsb") {
            plan.big_endian = parse_bool(val, path, "ByteOrderMSB");
        } else if (key == "elementnumberofchannels") {
            channels = parse_int(val, path, "ElementNumberOfChannels");
        } else if (key == "compresseddata") {
            compressed = parse_bool(val, path, "CompressedData");
        } else if (key == "binarydata") {
            binary = parse_bool(val, path, "BinaryData");
        } else if (key == "headersize") {
            header_size = parse_int(val, path, "HeaderSize");
            if (header_size < -1) throw FormatError(path + ": bad HeaderSize '" + escape_field(val) + "'");
        } else if (key == "elementdatafile") {
            have_data_file = true;
            data_file = val;
            data_offset = pos;
            const auto tk = split_ws(val);
            if (!tk.empty() && tk[0] == "LIST") {
                for (std::size_t lj = li + 1; lj < lines.size(); ++lj) {
                    const std::string f = trim(lines[lj]);
                    if (!f.empty()) list_files.push_back(resolve_relative(path, f));
                }
            } else if (tk.size() >= 4) {
                const std::int64_t a = parse_int(tk[1], path, "ElementDataFile min");
                const std::int64_t b = parse_int(tk[2], path, "ElementDataFile max");
                const std::int64_t s = parse_int(tk[3], path, "ElementDataFile step");
                for (const std::int64_t i : file_range_indices(a, b, s, path, "ElementDataFile"))
                    list_files.push_back(resolve_relative(path, format_file_pattern(tk[0], i, path)));
            }
            break;  // ElementDataFile is the last header field
        }
    }
    if (!have_data_file) throw FormatError(path + ": not a MetaImage header (missing ElementDataFile)");
    if (ndims < 0) throw FormatError(path + ": missing NDims");
    if (dims.size() != static_cast<std::size_t>(ndims))
        throw FormatError(path + ": DimSize has " + std::to_string(dims.size()) + " entries, NDims is " + std::to_string(ndims));
    for (std::size_t a = 0; a < dims.size(); ++a) {
        if (dims[a] < 1) throw FormatError(path + ": bad DimSize: sizes must be >= 1");
        if (a >= 3 && dims[a] != 1) throw FormatError(path + ": unsupported 4-D MetaImage (4th size " + std::to_string(dims[a]) + ")");
        if (a < 3) plan.grid.dims[a] = dims[a];
    }
    for (std::size_t a = dims.size(); a < 3; ++a) plan.grid.dims[a] = 1;
    if (channels != 1)
        throw FormatError(path + ": unsupported ElementNumberOfChannels " + std::to_string(channels) + " (1 supported)");
    if (type_v.empty()) throw FormatError(path + ": missing ElementType");
    const auto t = met_type(type_v);
    if (!t) throw FormatError(path + ": unsupported ElementType '" + escape_field(type_v) + "'");
    plan.type = *t;
    const std::string& sp = !spacing_v.empty() ? spacing_v : size_v;
    std::array<double, 3> signed_spacing{1.0, 1.0, 1.0};
    if (!sp.empty()) {
        const auto s = parse_doubles(sp, static_cast<std::size_t>(ndims), path, "ElementSpacing");
        for (std::size_t a = 0; a < 3 && a < s.size(); ++a) {
            if (!(s[a] != 0) || !std::isfinite(s[a]))
                throw FormatError(path + ": bad ElementSpacing '" + escape_field(sp) + "': zero or non-finite spacing");
            signed_spacing[a] = s[a];
        }
    }
    if (!origin_v.empty()) {
        const auto o = parse_doubles(origin_v, static_cast<std::size_t>(ndims), path, "Offset");
        for (std::size_t a = 0; a < 3 && a < o.size(); ++a) plan.grid.origin[a] = o[a];
    }
    std::vector<double> tm;  // TransformMatrix: row i = index axis i (ITK's direction cosines)
    for (const auto& t : split_ws(transform_v)) {
        char* end = nullptr;
        const double v = std::strtod(t.c_str(), &end);
        if (end == t.c_str() || *end) break;
        tm.push_back(v);
    }
    // along the axes, forward or back: world coordinates (backward axes flipped); the frame, made
    // from the matrix's rows (index axes), turns round on the matrix's own backward axes (a negative
    // ElementSpacing reverses samples, not the frame: the frame then already says the world's axes)
    std::array<bool, 3> frame_flip{false, false, false};
    if (ndims == 3 && tm.size() == 9)
        if (const auto signs = axis_aligned_signs({Vec3{tm[0], tm[1], tm[2]}, Vec3{tm[3], tm[4], tm[5]}, Vec3{tm[6], tm[7], tm[8]}}))
            for (int a = 0; a < 3; ++a) {
                signed_spacing[a] *= (*signs)[static_cast<std::size_t>(a)];
                frame_flip[static_cast<std::size_t>(a)] = (*signs)[static_cast<std::size_t>(a)] < 0;
            }
    for (int a = 0; a < 3; ++a) honour_signed_spacing(plan.grid, plan.flip, a, signed_spacing[a]);  // negative: flipped
    if (ndims == 3) {  // the patient's axes (a malformed matrix is no frame, not an error: it only frames the picture)
        plan.frame = metaimage_frame(tm.size() == 9 ? tm : std::vector<double>{}, trim(anatomical_v));
        flip_frame(plan.frame, frame_flip);
    }
    plan.encoding = compressed ? PayloadEncoding::gzip : (binary ? PayloadEncoding::raw : PayloadEncoding::ascii);
    if (compressed && header_size == -1) throw FormatError(path + ": HeaderSize -1 with CompressedData is not supported");
    const auto tk = split_ws(data_file);
    if (tk.empty()) throw FormatError(path + ": empty ElementDataFile");
    if (tk[0] == "LOCAL") {
        plan.files = {path};
        plan.file_offset = data_offset;
        if (header_size == -1) plan.byte_skip = -1;
    } else {
        plan.files = list_files.empty() ? std::vector<std::string>{resolve_relative(path, data_file)} : list_files;
        plan.byte_skip = header_size;
    }
    return plan;
}

VolumeInfo probe_metaimage(const std::string& path) { return info_from_plan(plan_metaimage(path)); }
Volume read_metaimage(const std::string& path) { return read_payload(plan_metaimage(path)); }

}  // namespace meshless
