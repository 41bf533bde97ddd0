#include "formats/nifti.hpp"
#include "kernels/flip_axes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "formats/binary_file.hpp"
#include "formats/gzip.hpp"
#include "formats/length_unit.hpp"
#include "formats/payload.hpp"
#include "formats/reference_policy.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr std::size_t kHeaderBytes = 348;

struct NiftiHeader {
    GridSpec grid;
    StoredType type = StoredType::u8;
    bool big_endian = false;
    std::uint64_t vox_offset = 0;
    float slope = 0, inter = 0;
    bool pair = false;  // "ni1": data in a separate .img
    std::optional<AnatomicalFrame> frame;  // sform, else qform
    std::string length_unit;               // xyzt_units (byte 123)
    std::array<bool, 3> flip{false, false, false};  // axes the sform/qform runs backwards along (samples reversed)
};

bool ends_with(const std::string& s, const std::string& suf) {
    return s.size() >= suf.size() && s.compare(s.size() - suf.size(), suf.size(), suf) == 0;
}

bool is_gz_path(const std::string& path) {
    const std::string l = path;
    return ends_with(l, ".gz") || ends_with(l, ".GZ");
}

// Gzipped: named .gz, or a single-file NIfTI (a header file, whose first bytes are sizeof_hdr = 348
// when it is not gzipped) starting with gzip's magic (a .nii.gz on standard input is spooled to a
// file without its name). A pair's .img is gzipped only when named so: its samples may start 1f 8b.
bool is_gz(const std::string& path) {
    if (is_gz_path(path)) return true;
    if (ends_with(path, ".img") || ends_with(path, ".IMG")) return false;
    const std::string head = read_file_prefix(path, 2);
    return head.size() == 2 && static_cast<unsigned char>(head[0]) == 0x1f && static_cast<unsigned char>(head[1]) == 0x8b;
}

// An sform/qform whose index axes run along the RAS axes (forward or back: FSL's "LAS" x = -2 is
// the common case) gives world coordinates: the backward axes are flipped (origin moved to their
// last sample, samples reversed, the frame's axes negated). A rotating matrix keeps the index frame.
// sform columns carry the voxel size (their lengths), qform ones are unit (pixdim gives it).
void world_axes(NiftiHeader& r, const std::array<Vec3, 3>& col, bool sized) {
    const auto signs = axis_aligned_signs(col);
    if (!signs) return;
    for (int a = 0; a < 3; ++a) {
        const double len = sized ? norm(col[static_cast<std::size_t>(a)]) : r.grid.spacing[a];
        honour_signed_spacing(r.grid, r.flip, a, (*signs)[static_cast<std::size_t>(a)] * len);
    }
    flip_frame(r.frame, r.flip);
}


NiftiHeader parse_header(const unsigned char* h, const std::string& path) {
    std::int32_t sz;
    std::memcpy(&sz, h, 4);
    NiftiHeader r;
    if (sz == 348) {
        r.big_endian = !host_is_little_endian();
    } else if (static_cast<std::int32_t>(__builtin_bswap32(static_cast<std::uint32_t>(sz))) == 348) {
        r.big_endian = host_is_little_endian();
    } else {
        if (sz == 540 || static_cast<std::int32_t>(__builtin_bswap32(static_cast<std::uint32_t>(sz))) == 540)
            throw FormatError(path + ": NIfTI-2 header is not supported (NIfTI-1 only)");
        throw FormatError(path + ": not a NIfTI-1 file (sizeof_hdr is " + std::to_string(sz) +
                          ", expected 348 in either byte order)");
    }
    const bool swap = r.big_endian == host_is_little_endian();
    auto i16 = [&](std::size_t off) {
        std::uint16_t v;
        std::memcpy(&v, h + off, 2);
        if (swap) v = static_cast<std::uint16_t>((v >> 8) | (v << 8));
        return static_cast<std::int16_t>(v);
    };
    auto f32 = [&](std::size_t off) {
        std::uint32_t v;
        std::memcpy(&v, h + off, 4);
        if (swap) v = __builtin_bswap32(v);
        float f;
        std::memcpy(&f, &v, 4);
        return f;
    };
    const char* magic = reinterpret_cast<const char*>(h + 344);
    if (std::memcmp(magic, "n+1\0", 4) == 0)
        r.pair = false;
    else if (std::memcmp(magic, "ni1\0", 4) == 0)
        r.pair = true;
    else
        throw FormatError(path + ": bad NIfTI magic (expected 'n+1' or 'ni1'; ANALYZE 7.5 is not supported)");
    const int ndim = i16(40);
    if (ndim < 1 || ndim > 7) throw FormatError(path + ": bad NIfTI dim[0] " + std::to_string(ndim) + " (1..7)");
    for (int a = 0; a < 3; ++a) {
        const std::int64_t d = a < ndim ? i16(42 + 2 * a) : 1;
        if (d < 1) throw FormatError(path + ": bad NIfTI dim[" + std::to_string(a + 1) + "] " + std::to_string(d));
        r.grid.dims[a] = d;
    }
    for (int a = 3; a < ndim; ++a)
        if (i16(42 + 2 * a) > 1)
            throw FormatError(path + ": unsupported NIfTI with dim[" + std::to_string(a + 1) + "] = " +
                              std::to_string(i16(42 + 2 * a)) + " (3-D volumes only)");
    const int dt = i16(70);
    switch (dt) {
        case 2: r.type = StoredType::u8; break;
        case 4: r.type = StoredType::i16; break;
        case 8: r.type = StoredType::i32; break;
        case 16: r.type = StoredType::f32; break;
        case 64: r.type = StoredType::f64; break;
        case 256: r.type = StoredType::i8; break;
        case 512: r.type = StoredType::u16; break;
        case 768: r.type = StoredType::u32; break;
        case 1024: r.type = StoredType::i64; break;
        case 1280: r.type = StoredType::u64; break;
        default: throw FormatError(path + ": unsupported NIfTI datatype " + std::to_string(dt));
    }
    for (int a = 0; a < 3; ++a) {
        const double s = std::fabs(static_cast<double>(f32(80 + 4 * a)));
        r.grid.spacing[a] = (s > 0 && std::isfinite(s)) ? s : 1.0;
    }
    const float vo = f32(108);
    if (!(vo >= 0) || !std::isfinite(vo) || vo > static_cast<float>(kMaxPayloadBytes))
        throw FormatError(path + ": bad NIfTI vox_offset at byte 108");
    r.vox_offset = static_cast<std::uint64_t>(vo);
    if (!r.pair && r.vox_offset < kHeaderBytes) r.vox_offset = 352;  // n+1 data never overlaps the header
    r.slope = f32(112);
    r.length_unit = nifti_length_unit(static_cast<std::uint8_t>(h[123]));
    r.inter = f32(116);
    const int qform = i16(252), sform = i16(254);
    if (sform > 0) {
        for (int a = 0; a < 3; ++a) r.grid.origin[a] = f32(280 + 16 * a + 12);
        // srow_x/y/z: column i of their 3x3 is index axis i in RAS
        std::array<Vec3, 3> col;
        for (int i = 0; i < 3; ++i) col[i] = Vec3{f32(280 + 4 * i), f32(296 + 4 * i), f32(312 + 4 * i)};
        r.frame = ras_frame(col, "NIfTI sform");
        world_axes(r, col, /*sized=*/true);
    } else if (qform > 0) {
        for (int a = 0; a < 3; ++a) r.grid.origin[a] = f32(268 + 4 * a);
        // quaternion (b, c, d), a = sqrt(1 - b^2 - c^2 - d^2); qfac = pixdim[0] (-1 reverses the third axis)
        const double b = f32(256), c = f32(260), d = f32(264);
        const double a = std::sqrt(std::max(0.0, 1.0 - (b * b + c * c + d * d)));
        const double qfac = f32(76) < 0 ? -1.0 : 1.0;
        const std::array<Vec3, 3> col{Vec3{a * a + b * b - c * c - d * d, 2 * (b * c + a * d), 2 * (b * d - a * c)},
                                      Vec3{2 * (b * c - a * d), a * a + c * c - b * b - d * d, 2 * (c * d + a * b)},
                                      Vec3{qfac * 2 * (b * d + a * c), qfac * 2 * (c * d - a * b), qfac * (a * a + d * d - c * c - b * b)}};
        r.frame = ras_frame(col, "NIfTI qform");
        world_axes(r, col, /*sized=*/false);
    }
    validate_grid(r.grid, path);
    return r;
}

// The .img beside a .hdr (or .img.gz), checked against the policy before it is opened.
std::string image_file_for(const std::string& path, const ReferencePolicy& refs) {
    std::string base = path;
    if (is_gz_path(base)) base = base.substr(0, base.size() - 3);
    const std::string stem = base.substr(0, base.size() - std::filesystem::path(base).extension().string().size());
    std::error_code ec;
    for (const char* ext : {".img", ".img.gz", ".IMG"})
        if (std::filesystem::is_regular_file(stem + ext, ec)) {
            check_reference(refs, path, stem + ext);
            return stem + ext;
        }
    throw IoError(path + ": cannot open the image file " + stem + ".img");
}

NiftiHeader read_header(const std::string& path) {
    unsigned char h[kHeaderBytes];
    if (is_gz(path)) {
        InflateReader r(path);
        r.read_exact(h, kHeaderBytes, "NIfTI header");
    } else {
        const auto b = read_file_range(path, 0, kHeaderBytes);
        std::memcpy(h, b.data(), kHeaderBytes);
    }
    return parse_header(h, path);
}

Volume apply_scaling(Volume v, const NiftiHeader& h) {
    if (h.slope == 0 || !std::isfinite(h.slope) || (h.slope == 1 && h.inter == 0)) return v;
    Volume out(v.grid, SampleType::f32);
    auto* o = reinterpret_cast<float*>(out.bytes.data());
    const std::int64_t n = v.grid.voxel_count();
    visit_samples(v.view(), [&](auto* p) {
        for (std::int64_t i = 0; i < n; ++i) o[i] = static_cast<float>(h.slope * static_cast<double>(p[i]) + h.inter);
    });
    return out;
}

}  // namespace


namespace {
// A gzipped payload's size, proven against deflate's largest expansion before anything is allocated.
std::uint64_t gz_payload_bytes(const NiftiHeader& h, const std::string& data) {
    const std::uint64_t bytes = checked_mul(static_cast<std::uint64_t>(h.grid.voxel_count()), stored_size(h.type),
                                            data + ": NIfTI payload size");
    if (checked_add(bytes, h.vox_offset, data + ": NIfTI vox_offset") / kMaxDeflateRatio > regular_file_size(data) + 64)
        throw FormatError(data + ": NIfTI header claims " + std::to_string(bytes) +
                          " payload bytes, more than the compressed file can hold");
    return bytes;
}

PayloadPlan raw_plan(const NiftiHeader& h, const std::string& data) {
    PayloadPlan plan;
    plan.format = "nifti";
    plan.grid = h.grid;
    plan.type = h.type;
    plan.big_endian = h.big_endian;
    plan.files = {data};
    plan.file_offset = h.vox_offset;
    plan.flip = h.flip;
    return plan;
}
}  // namespace

VolumeInfo probe_nifti(const std::string& path, const ReferencePolicy& refs) {
    const NiftiHeader h = read_header(path);
    VolumeInfo i;
    i.format = "nifti";
    i.grid = h.grid;
    const std::string data = h.pair ? image_file_for(path, refs) : path;
    i.type = (h.slope != 0 && std::isfinite(h.slope) && !(h.slope == 1 && h.inter == 0)) ? SampleType::f32
                                                                                         : volume_type_for(h.type);
    // the payload's claim against the file, as read_nifti checks it before allocating
    if (is_gz(data))
        gz_payload_bytes(h, data);
    else
        check_payload_plan(raw_plan(h, data));
    i.encoding = is_gz(data) ? "gzip" : "raw";
    i.data_files = {data};
    i.frame = h.frame;
    i.length_unit = h.length_unit;
    return i;
}

void prove_nifti(const std::string& path, const ReferencePolicy& refs) {
    const NiftiHeader h = read_header(path);
    const std::string data = h.pair ? image_file_for(path, refs) : path;
    if (!is_gz(data)) return prove_payload(raw_plan(h, data));
    const std::uint64_t bytes = gz_payload_bytes(h, data);
    InflateReader r(data);
    r.skip(h.vox_offset + bytes);  // streamed through a small buffer: nothing kept
    r.expect_end(h.vox_offset + bytes);  // the gzip tail rule, as read_nifti applies it
}

Volume read_nifti(const std::string& path, const ReferencePolicy& refs) {
    const NiftiHeader h = read_header(path);
    const std::string data = h.pair ? image_file_for(path, refs) : path;
    if (is_gz(data)) {
        const std::uint64_t bytes = gz_payload_bytes(h, data);  // deflate expands at most 1032:1
        // inflate_file's output pages become resident as the data arrives
        Volume v = make_volume(inflate_file(data, 0, h.vox_offset, bytes), h.type, h.big_endian, h.grid, data);
        flip_axes(v, h.flip);
        return apply_scaling(std::move(v), h);
    }
    return apply_scaling(read_payload(raw_plan(h, data)), h);
}

}  // namespace meshless
