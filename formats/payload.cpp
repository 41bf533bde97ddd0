#include "formats/payload.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <type_traits>
#include <limits>

#include "formats/binary_file.hpp"
#include "formats/gzip.hpp"
#include "formats/mapped_file.hpp"
#include "formats/ply.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/flip_axes.hpp"
#include "kernels/errors.hpp"

namespace meshless {

const char* to_string(PayloadEncoding e) {
    switch (e) {
        case PayloadEncoding::raw: return "raw";
        case PayloadEncoding::gzip: return "gzip";
        case PayloadEncoding::ascii: return "ascii";
    }
    return "?";
}

VolumeInfo info_from_plan(const PayloadPlan& plan) {
    validate_grid(plan.grid, plan.files.empty() ? std::string("?") : plan.files.front());
    VolumeInfo i;
    i.format = plan.format;
    i.grid = plan.grid;
    i.type = volume_type_for(plan.type);
    i.encoding = to_string(plan.encoding);
    i.data_files = plan.files;
    i.frame = plan.frame;
    i.length_unit = plan.length_unit;
    i.value_unit = plan.value_unit;
    i.arrays = plan.arrays;
    i.default_array = plan.default_array;
    i.read_array = plan.read_array;
    return i;
}

std::size_t choose_volume_array(const std::vector<VolumeArray>& arrays, std::size_t fallback, const std::string& name,
                                const std::string& path) {
    if (name.empty()) return fallback;
    for (std::size_t k = 0; k < arrays.size(); ++k)
        if (arrays[k].name == name) return k;
    std::string list;
    for (const VolumeArray& a : arrays) {
        list += (list.empty() ? "'" : ", '") + escape_field(a.name) + "' (" + a.type;
        if (a.components != 1) list += ", " + (a.components > 0 ? std::to_string(a.components) : std::string("?")) + " components";
        list += ")";
    }
    throw FormatError(path + ": no point array named '" + escape_field(name) + "'; " +
                      (arrays.empty() ? std::string("it has none") : "its arrays: " + list));
}

void refuse_array_choice(const std::string& name, const std::string& path, const std::string& format) {
    if (name.empty()) return;
    throw InvalidArgument(path + ": a " + format + " volume holds one unnamed array: no array '" + escape_field(name) +
                          "' to choose (only .vti, VTK legacy .vtk and vtk.js volumes name their arrays)");
}

namespace {

// Offset of the byte after `lines` newlines, starting at `offset` in a file.
std::uint64_t skip_lines(const std::string& path, std::uint64_t offset, std::int64_t lines) {
    if (lines <= 0) return offset;
    const std::uint64_t size = regular_file_size(path);
    std::uint64_t pos = offset;
    std::int64_t seen = 0;
    while (pos < size) {
        const std::uint64_t n = std::min<std::uint64_t>(size - pos, 1 << 16);
        const auto buf = read_file_range(path, pos, n);
        for (std::size_t i = 0; i < buf.size(); ++i)
            if (buf[i] == std::byte{'\n'} && ++seen == lines) return pos + i + 1;
        pos += n;
    }
    throw FormatError(path + ": line skip " + std::to_string(lines) + " runs past the end of the file");
}

template <class T>
void put(std::byte* out, std::size_t i, T v) {
    std::memcpy(out + i * sizeof(T), &v, sizeof(T));
}

/// Sample i, parsed as v from `token`, stored as T: integers truncated toward zero, refused
/// (FormatError naming the file, the value and its index) when the truncation is not a T or v is
/// not a number; floats refused when finite beyond the type's range (converting them is undefined).
template <class T>
void put_checked(std::byte* out, std::size_t i, double v, std::string_view token, StoredType t, const std::string& path) {
    bool ok = true;
    if constexpr (std::is_integral_v<T>) {
        constexpr int digits = std::numeric_limits<T>::digits;  // value bits: 2^digits is one past the largest
        const double hi = std::ldexp(1.0, digits), lo = std::is_signed_v<T> ? -hi - 1.0 : -1.0;
        ok = v > lo && v < hi;  // NaN fails both
    } else if constexpr (std::is_same_v<T, float>) {
        ok = !std::isfinite(v) || std::fabs(v) <= static_cast<double>(std::numeric_limits<float>::max());
    }
    if (!ok)
        throw FormatError(path + ": ascii value '" + ply_escape(token.substr(0, 24)) + "' at value " + std::to_string(i) +
                          " is outside the range of " + to_string(t));
    put(out, i, static_cast<T>(v));
}

/// 64-bit integers: a token that is an integer is read as one (every value of the type exactly: a
/// double holds 53 bits, so 2^63 - 1 would round up beyond the type); other tokens (1e3, 2.5) as
/// put_checked reads them.
template <class T>
void put_checked_wide(std::byte* out, std::size_t i, double v, std::string_view token, StoredType t, const std::string& path) {
    std::string_view digits = token;
    if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
    T n = 0;
    const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), n);
    if (r.ptr == digits.data() + digits.size() && !digits.empty()) {
        if (r.ec == std::errc()) return put(out, i, n);
        throw FormatError(path + ": ascii value '" + ply_escape(token.substr(0, 24)) + "' at value " + std::to_string(i) +
                          " is outside the range of " + to_string(t));
    }
    put_checked<T>(out, i, v, token, t, path);
}

}  // namespace

std::vector<std::byte> parse_ascii_samples(std::string_view text, StoredType t, std::size_t count,
                                           const std::string& path) {
    if (count > text.size() / 2 + 1)  // every value takes a digit and a separator
        throw FormatError(path + ": ascii data of " + std::to_string(text.size()) + " bytes cannot hold the " +
                          std::to_string(count) + " values the header claims");
    std::vector<std::byte> out(count * stored_size(t));
    const char* p = text.data();
    const char* end = text.data() + text.size();
    for (std::size_t i = 0; i < count; ++i) {
        while (p < end && (std::isspace(static_cast<unsigned char>(*p)) || *p == ',')) ++p;
        if (p == end)
            throw FormatError(path + ": ascii data ends after " + std::to_string(i) + " values, expected " +
                              std::to_string(count));
        double v = 0;
        auto r = std::from_chars(p, end, v);
        if (r.ec != std::errc()) {
            // from_chars rejects a leading '+', accept it
            if (*p == '+') r = std::from_chars(p + 1, end, v);
            if (r.ec != std::errc())
                throw FormatError(path + ": bad ascii value '" + ply_escape(std::string_view(p, std::min<std::size_t>(end - p, 16))) +
                                  "' at value " + std::to_string(i));
        }
        const std::string_view token(p, static_cast<std::size_t>(r.ptr - p));
        p = r.ptr;
        switch (t) {
            case StoredType::u8: put_checked<std::uint8_t>(out.data(), i, v, token, t, path); break;
            case StoredType::i8: put_checked<std::int8_t>(out.data(), i, v, token, t, path); break;
            case StoredType::u16: put_checked<std::uint16_t>(out.data(), i, v, token, t, path); break;
            case StoredType::i16: put_checked<std::int16_t>(out.data(), i, v, token, t, path); break;
            case StoredType::u32: put_checked<std::uint32_t>(out.data(), i, v, token, t, path); break;
            case StoredType::i32: put_checked<std::int32_t>(out.data(), i, v, token, t, path); break;
            case StoredType::u64: put_checked_wide<std::uint64_t>(out.data(), i, v, token, t, path); break;
            case StoredType::i64: put_checked_wide<std::int64_t>(out.data(), i, v, token, t, path); break;
            case StoredType::f32: put_checked<float>(out.data(), i, v, token, t, path); break;
            case StoredType::f64: put(out.data(), i, v); break;
        }
    }
    return out;
}

std::vector<std::uint64_t> check_payload_plan(const PayloadPlan& plan) {
    const std::string& head = plan.files.empty() ? std::string("?") : plan.files.front();
    if (plan.files.empty()) throw FormatError("(no data file): empty payload plan");
    validate_grid(plan.grid, head);
    const std::uint64_t n = static_cast<std::uint64_t>(plan.grid.voxel_count());
    const std::uint64_t elem = stored_size(plan.type);
    const std::uint64_t total = checked_mul(n, elem, head + ": payload size (" + dims_string(plan.grid) + " " +
                                                         to_string(plan.type) + ")");
    const std::uint64_t k = plan.files.size();
    if (n % k != 0)
        throw FormatError(head + ": " + std::to_string(n) + " samples do not split evenly over " + std::to_string(k) +
                          " data files");
    const std::uint64_t share = total / k;

    // Validate raw sizes before allocating.
    std::vector<std::uint64_t> starts(k);
    for (std::uint64_t f = 0; f < k; ++f) try {
        const std::string& file = plan.files[f];
        if (plan.encoding == PayloadEncoding::raw) {
            const std::uint64_t size = regular_file_size(file);
            std::uint64_t start = skip_lines(file, plan.file_offset, plan.line_skip);
            if (plan.byte_skip == -1) {
                if (size < share)
                    throw FormatError(file + ": expected " + std::to_string(share) + " bytes for " + dims_string(plan.grid) +
                                      " " + to_string(plan.type) + (k > 1 ? " (one of " + std::to_string(k) + " files)" : "") +
                                      ", file has " + std::to_string(size));
                start = size - share;
            } else {
                start = checked_add(start, static_cast<std::uint64_t>(plan.byte_skip), file + ": byte skip");
            }
            const bool ok = plan.exact_size ? size == start + share : size >= start && size - start >= share;
            if (!ok) {
                std::string what = "expected " + std::to_string(share) + " bytes";
                if (start) what += " after offset " + std::to_string(start);
                throw FormatError(file + ": " + what + " for " + dims_string(plan.grid) + " " + to_string(plan.type) +
                                  (k > 1 ? " (one of " + std::to_string(k) + " files)" : "") + ", file has " +
                                  std::to_string(size));
            }
            starts[f] = start;
        } else {
            if (plan.byte_skip < 0)
                throw FormatError(file + ": byte skip -1 is only allowed with raw encoding");
            starts[f] = skip_lines(file, plan.file_offset, plan.line_skip);
            const std::uint64_t size = regular_file_size(file);
            const std::uint64_t avail = size - std::min(size, starts[f]);
            if (plan.encoding == PayloadEncoding::gzip) {
                // deflate expands at most 1032:1 (zlib's technical note): a header that claims more
                // than the compressed bytes can hold is refused before anything is allocated
                const std::uint64_t claimed = checked_add(share, static_cast<std::uint64_t>(plan.byte_skip),
                                                          file + ": byte skip");
                if (claimed / kMaxDeflateRatio > avail + 64)
                    throw FormatError(file + ": header claims " + std::to_string(claimed) + " decompressed bytes for " +
                                      dims_string(plan.grid) + " " + to_string(plan.type) + ", more than the " +
                                      std::to_string(avail) + " compressed bytes after offset " +
                                      std::to_string(starts[f]) + " can hold");
            } else if (n / k > avail / 2 + 1) {  // ascii: every value takes a digit and a separator
                throw FormatError(file + ": header claims " + std::to_string(n / k) + " ascii values for " +
                                  dims_string(plan.grid) + ", the " + std::to_string(avail) + " bytes after offset " +
                                  std::to_string(starts[f]) + " hold at most " + std::to_string(avail / 2 + 1));
            }
        }
    } catch (const IoError& e) {  // a detached header's data file: the message names the header too
        if (plan.header.empty() || plan.header == plan.files[f]) throw;
        throw IoError(plan.header + ": data file " + e.what());
    } catch (const FormatError& e) {
        if (plan.header.empty() || plan.header == plan.files[f]) throw;
        throw FormatError(plan.header + ": data file " + e.what());
    }
    return starts;
}

bool payload_maps(const PayloadPlan& plan) {
    const bool native = plan.type == StoredType::u8 || plan.type == StoredType::u16 || plan.type == StoredType::i16 ||
                        plan.type == StoredType::f32;
    const bool flipped = plan.flip[0] || plan.flip[1] || plan.flip[2];
    return !flipped && plan.encoding == PayloadEncoding::raw && plan.files.size() == 1 && native &&
           (plan.big_endian != host_is_little_endian() || stored_size(plan.type) == 1);
}

namespace {
void prove_payload_files(const PayloadPlan& plan) {
    const std::vector<std::uint64_t> starts = check_payload_plan(plan);
    if (plan.encoding == PayloadEncoding::raw) return;  // sizes are all a raw payload can get wrong
    const std::uint64_t n = static_cast<std::uint64_t>(plan.grid.voxel_count());
    const std::uint64_t k = plan.files.size();
    const std::uint64_t share = n * stored_size(plan.type) / k;
    for (std::uint64_t f = 0; f < k; ++f) {
        const std::string& file = plan.files[f];
        if (plan.encoding == PayloadEncoding::gzip) {
            InflateReader r(file, starts[f]);
            const std::uint64_t want = static_cast<std::uint64_t>(plan.byte_skip) + share;  // bounded above: no overflow
            r.skip(want);
            r.expect_end(want);  // the gzip tail rule, as read_payload applies it
        } else {
            const std::uint64_t size = regular_file_size(file);
            const auto bytes = read_file_range(file, starts[f], size - std::min(size, starts[f]));
            const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
            parse_ascii_samples(text, plan.type, static_cast<std::size_t>(n / k), file);
        }
    }
}

Volume read_payload_files(const PayloadPlan& plan, bool map_raw) {
    const std::vector<std::uint64_t> starts = check_payload_plan(plan);  // sizes proven before allocating
    const std::string& head = plan.files.front();
    const std::uint64_t n = static_cast<std::uint64_t>(plan.grid.voxel_count());
    const std::uint64_t total = n * stored_size(plan.type);
    const std::uint64_t k = plan.files.size();
    const std::uint64_t share = total / k;
    const bool swapped_host_order = plan.encoding == PayloadEncoding::ascii;

    if (map_raw && payload_maps(plan)) {
        Volume v;
        v.grid = plan.grid;
        v.type = volume_type_for(plan.type);
        v.bytes = map_file_range(plan.files.front(), starts.front(), share);
        return v;
    }

    // gzip: inflated whole (libdeflate) into zero pages that become resident only as the data
    // arrives (a stream that ends early costs what it delivered), one file's share in place
    const bool gzip = plan.encoding == PayloadEncoding::gzip;
    const auto skip = static_cast<std::uint64_t>(std::max<std::int64_t>(plan.byte_skip, 0));
    if (gzip && k == 1) {
        Volume v = make_volume(inflate_file(head, starts.front(), skip, total), plan.type, plan.big_endian, plan.grid, head);
        flip_axes(v, plan.flip);
        return v;
    }
    // raw and ascii sizes were proven against the files above
    SampleBytes payload = gzip ? SampleBytes::lazy_zeroed(static_cast<std::size_t>(total)) : SampleBytes(static_cast<std::size_t>(total));
    for (std::uint64_t f = 0; f < k; ++f) {
        const std::string& file = plan.files[f];
        std::byte* dst = payload.data() + f * share;
        switch (plan.encoding) {
            case PayloadEncoding::raw: read_file_range_into(file, starts[f], share, dst); break;
            case PayloadEncoding::gzip: {
                const SampleBytes part = inflate_file(file, starts[f], skip, share);
                std::memcpy(dst, part.data(), part.size());
                break;
            }
            case PayloadEncoding::ascii: {
                const std::uint64_t size = regular_file_size(file);
                const auto bytes = read_file_range(file, starts[f], size - std::min(size, starts[f]));
                const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
                auto vals = parse_ascii_samples(text, plan.type, static_cast<std::size_t>(n / k), file);
                std::memcpy(dst, vals.data(), vals.size());
                break;
            }
        }
    }
    const bool big = swapped_host_order ? !host_is_little_endian() : plan.big_endian;
    Volume v = make_volume(std::move(payload), plan.type, big, plan.grid, head);
    flip_axes(v, plan.flip);
    return v;
}
}  // namespace

void prove_payload(const PayloadPlan& plan) {
    naming_header(plan, [&] { prove_payload_files(plan); });
}

Volume read_payload(const PayloadPlan& plan, bool map_raw) {
    return naming_header(plan, [&] { return read_payload_files(plan, map_raw); });
}

}  // namespace meshless
