#include "formats/slc.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

#include "formats/binary_file.hpp"
#include "formats/stored_type.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

struct Scanner {
    const std::string& path;
    const std::byte* data;
    std::size_t size;
    std::size_t pos = 0;

    std::string token(const char* what) {
        while (pos < size && std::isspace(static_cast<unsigned char>(data[pos]))) ++pos;
        const std::size_t s = pos;
        while (pos < size && !std::isspace(static_cast<unsigned char>(data[pos])) && data[pos] != std::byte{'X'}) ++pos;
        if (s == pos) throw FormatError(path + ": SLC header ends before " + what + " (offset " + std::to_string(s) + ")");
        return std::string(reinterpret_cast<const char*>(data + s), pos - s);
    }
    std::int64_t integer(const char* what) { return parse_int(token(what), path, what); }
    double real(const char* what) { return parse_double(token(what), path, what); }
    void expect_x(const char* what) {
        while (pos < size && data[pos] == std::byte{' '}) ++pos;
        if (pos >= size || data[pos] != std::byte{'X'})
            throw FormatError(path + ": expected 'X' after " + what + " at offset " + std::to_string(pos));
        ++pos;
    }
};

struct SlcHeader {
    GridSpec grid;
    std::int64_t compression = 0;
};

SlcHeader parse_header(Scanner& s) {
    const std::string magic = s.token("magic");
    if (magic != "11111") throw FormatError(s.path + ": not an SLC file (wrong magic '" + escape_field(magic, 16) + "', expected 11111)");
    SlcHeader h;
    for (int a = 0; a < 3; ++a) {
        h.grid.dims[a] = s.integer("dimensions");
        if (h.grid.dims[a] < 1 || h.grid.dims[a] > (1 << 20))
            throw FormatError(s.path + ": bad SLC dimensions (" + std::to_string(h.grid.dims[a]) + " along axis " +
                              std::to_string(a) + ", 1.." + std::to_string(1 << 20) + ")");
    }
    const std::int64_t bits = s.integer("bits per voxel");
    if (bits != 8) throw FormatError(s.path + ": unsupported SLC bits per voxel " + std::to_string(bits) + " (8 supported)");
    for (int a = 0; a < 3; ++a) {
        const double v = s.real("spacing");
        if (!(v > 0) || !std::isfinite(v)) throw FormatError(s.path + ": bad SLC spacing (must be finite and > 0)");
        h.grid.spacing[a] = v;
    }
    s.integer("unit type");
    s.integer("data origin");
    s.integer("data modification");
    h.compression = s.integer("data compression");
    if (h.compression != 0 && h.compression != 1)
        throw FormatError(s.path + ": unsupported SLC compression " + std::to_string(h.compression));
    validate_grid(h.grid, s.path);
    return h;
}

}  // namespace

namespace {

// After the header: skips the icon and proves the slice bytes can hold the claimed voxels
// (before anything is allocated). Returns the voxel count.
std::uint64_t check_body(std::uint64_t file_size, Scanner& s, const SlcHeader& h, const std::string& path) {
    const std::int64_t iw = s.integer("icon width"), ih = s.integer("icon height");
    s.expect_x("icon size");
    const std::string icon_ctx = path + ": SLC icon size";
    const std::uint64_t icon = checked_mul(checked_mul(checked_count(iw, icon_ctx), checked_count(ih, icon_ctx), icon_ctx), 3, icon_ctx);
    if (icon > file_size - s.pos)
        throw FormatError(path + ": SLC icon " + std::to_string(iw) + "x" + std::to_string(ih) + " at offset " +
                          std::to_string(s.pos) + " runs past the end of the file");
    s.pos += static_cast<std::size_t>(icon);

    // Before allocating: a slice decodes to at least half its plane (the tolerated shortfall is at
    // most half a plane, see below) and run-length coding expands at most 127 bytes per 2, so
    // the file must hold at least voxels/254 slice bytes (raw slices: every voxel).
    const std::uint64_t voxels = static_cast<std::uint64_t>(h.grid.voxel_count());
    const std::uint64_t rest = file_size - s.pos;
    if ((h.compression == 0 && voxels > rest) || (h.compression == 1 && voxels / 254 > rest))
        throw FormatError(path + ": SLC header claims " + dims_string(h.grid) + " voxels, more than the " +
                          std::to_string(rest) + " slice bytes after offset " + std::to_string(s.pos) + " can hold");
    return voxels;
}

// Decodes every slice; slice z goes to plane(z) (a zeroed plane: a tolerated short slice leaves
// the rest as it is).
template <class Plane>
void decode_slices(const std::vector<std::byte>& file, Scanner& s, const SlcHeader& h, const std::string& path, Plane&& plane_at) {
    const std::size_t nx = static_cast<std::size_t>(h.grid.dims[0]);
    const std::size_t plane = nx * static_cast<std::size_t>(h.grid.dims[1]);
    const auto* in = reinterpret_cast<const unsigned char*>(file.data());
    for (std::int64_t z = 0; z < h.grid.dims[2]; ++z) {
        const std::string zs = std::to_string(z);
        const std::int64_t n = s.integer("slice size");
        s.expect_x("slice size");
        if (n < 0 || static_cast<std::uint64_t>(n) > file.size() - s.pos)
            throw FormatError(path + ": truncated: slice " + zs + " needs " + std::to_string(n) + " bytes at offset " +
                              std::to_string(s.pos) + ", file has " + std::to_string(file.size()));
        const unsigned char* p = in + s.pos;
        const unsigned char* end = p + n;
        unsigned char* dst = plane_at(z);
        std::size_t filled = 0;
        if (h.compression == 0) {
            if (static_cast<std::size_t>(n) != plane)
                throw FormatError(path + ": uncompressed slice " + zs + " has " + std::to_string(n) + " bytes, expected " +
                                  std::to_string(plane));
            std::memcpy(dst, p, plane);
            filled = plane;
        } else {
            while (p < end) {
                const unsigned char c = *p++;
                const std::size_t run = c & 0x7f;
                if (run == 0) break;
                if (filled + run > plane)
                    throw FormatError(path + ": corrupt RLE in slice " + zs + ": decodes to more than " + std::to_string(plane) + " bytes");
                if (c & 0x80) {
                    if (static_cast<std::size_t>(end - p) < run)
                        throw FormatError(path + ": corrupt RLE in slice " + zs + ": literal run past the slice data");
                    std::memcpy(dst + filled, p, run);
                    p += run;
                } else {
                    if (p >= end) throw FormatError(path + ": corrupt RLE in slice " + zs + ": repeat run without a value");
                    std::memset(dst + filled, *p++, run);
                }
                filled += run;
            }
        }
        if (filled < plane) {
            if (plane - filled > std::min(nx, plane / 2))
                throw FormatError(path + ": slice " + zs + " decodes to " + std::to_string(filled) + " bytes, expected " +
                                  std::to_string(plane));
            // tolerated short slice (see header): the rest stays as it was (zero)
        }
        s.pos += static_cast<std::size_t>(n);
    }
}

}  // namespace

VolumeInfo probe_slc(const std::string& path) {
    // the header and the icon's size are text at the start; the claim is checked against the file's
    // size as read_slc checks it, so a bomb is refused here with read_slc's message
    const std::string text = read_file_prefix(path, 4096);
    Scanner s{path, reinterpret_cast<const std::byte*>(text.data()), text.size()};
    const SlcHeader h = parse_header(s);
    check_body(regular_file_size(path), s, h, path);
    VolumeInfo i;
    i.format = "slc";
    i.grid = h.grid;
    i.type = SampleType::u8;
    i.encoding = h.compression == 1 ? "rle" : "raw";
    i.data_files = {path};
    return i;
}

Volume read_slc(const std::string& path) {
    const std::vector<std::byte> file = read_file_bytes(path);
    Scanner s{path, file.data(), file.size()};
    const SlcHeader h = parse_header(s);
    const std::uint64_t voxels = check_body(file.size(), s, h, path);
    Volume v;
    v.grid = h.grid;
    v.type = SampleType::u8;
    v.bytes = SampleBytes::lazy_zeroed(static_cast<std::size_t>(voxels));  // resident as slices decode
    const std::size_t plane = static_cast<std::size_t>(h.grid.dims[0] * h.grid.dims[1]);
    auto* out = reinterpret_cast<unsigned char*>(v.bytes.data());
    decode_slices(file, s, h, path, [&](std::int64_t z) { return out + static_cast<std::size_t>(z) * plane; });
    return v;
}

void prove_slc(const std::string& path) {
    const std::vector<std::byte> file = read_file_bytes(path);
    Scanner s{path, file.data(), file.size()};
    const SlcHeader h = parse_header(s);
    check_body(file.size(), s, h, path);
    // one plane, reused (its size was bounded by the file above)
    SampleBytes plane = SampleBytes::lazy_zeroed(static_cast<std::size_t>(h.grid.dims[0] * h.grid.dims[1]));
    decode_slices(file, s, h, path, [&](std::int64_t) { return reinterpret_cast<unsigned char*>(plane.data()); });
}

}  // namespace meshless
