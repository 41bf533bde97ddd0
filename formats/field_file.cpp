#include "formats/field_file.hpp"

#include <sys/mman.h>
#include <zstd.h>

#include <algorithm>
#include <filesystem>
#include <bit>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <functional>

#include "formats/atomic_file.hpp"
#include "formats/binary_file.hpp"
#include "formats/crc32.hpp"
#include "kernels/errors.hpp"
#include "kernels/field_state.hpp"

namespace meshless {

static_assert(std::endian::native == std::endian::little, "the .mlf codec assumes a little-endian host");

namespace {

constexpr std::uint32_t kTypeBytes = 0;
constexpr std::uint32_t kFlagZstd = 1, kFlagShuffled = 2;
constexpr std::size_t kParamsBytes = 80, kStatsBytes = 168, kIdentityFixedBytes = 104, kMaxNameBytes = 1024;
constexpr std::size_t kNameBytes = 16;


std::size_t element_size(std::uint32_t type) { return type == kTypeBytes ? 1 : state_type_size(type); }

// ---- byte shuffling: element i's byte b at b * n + i (byte planes compress better)
template <std::size_t E>
void shuffle_t(const unsigned char* in, unsigned char* out, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t b = 0; b < E; ++b) out[b * n + i] = in[i * E + b];
}
template <std::size_t E>
void unshuffle_t(const unsigned char* in, unsigned char* out, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t b = 0; b < E; ++b) out[i * E + b] = in[b * n + i];
}
void shuffle(const unsigned char* in, unsigned char* out, std::size_t n, std::size_t es) {
    if (es == 8) return shuffle_t<8>(in, out, n);
    if (es == 4) return shuffle_t<4>(in, out, n);
    std::memcpy(out, in, n * es);
}
void unshuffle(const unsigned char* in, unsigned char* out, std::size_t n, std::size_t es) {
    if (es == 8) return unshuffle_t<8>(in, out, n);
    if (es == 4) return unshuffle_t<4>(in, out, n);
    std::memcpy(out, in, n * es);
}

/// Sizes `vec` to n elements, asking for transparent huge pages first when it is large: filling
/// hundreds of MB page by page costs more in page faults (about 10 us per 4 KiB page on a VM)
/// than decoding them. Advisory; the contents are the same either way.
template <class T>
void resize_large(std::vector<T>& vec, std::size_t n) {
    constexpr std::size_t kHuge = std::size_t{2} << 20;
    if (n * sizeof(T) >= 4 * kHuge && vec.capacity() < n) {
        vec.reserve(n);
        const auto a = reinterpret_cast<std::uintptr_t>(vec.data());
        const std::uintptr_t lo = (a + kHuge - 1) & ~(kHuge - 1), hi = (a + n * sizeof(T)) & ~(kHuge - 1);
        if (hi > lo) ::madvise(reinterpret_cast<void*>(lo), hi - lo, MADV_HUGEPAGE);
    }
    vec.resize(n);
}

// ---- little-endian encoding of the metadata sections
struct Enc {
    std::vector<unsigned char> b;
    template <class T>
    void put(T v) {
        unsigned char tmp[sizeof(T)];
        std::memcpy(tmp, &v, sizeof(T));
        b.insert(b.end(), tmp, tmp + sizeof(T));
    }
};

struct Dec {
    const unsigned char* p;
    std::size_t n, at = 0;
    template <class T>
    T get() {
        T v;
        std::memcpy(&v, p + at, sizeof(T));  // callers checked the size
        at += sizeof(T);
        return v;
    }
};

std::string hex(std::uint64_t v) {
    char buf[20];
    std::snprintf(buf, sizeof buf, "%016" PRIx64, v);
    return buf;
}

std::vector<unsigned char> encode_params(const FieldParams& p) {
    Enc e;
    e.put<std::uint32_t>(static_cast<std::uint32_t>(p.kind));
    e.put<std::uint32_t>(static_cast<std::uint32_t>(p.rbf_grid_support));
    e.put<std::uint32_t>(p.rbf_grid_max_local);
    e.put<std::uint32_t>(p.rbf_grid_min_local);
    e.put<std::uint32_t>(p.mpu_max_points);
    e.put<std::uint32_t>(p.mpu_min_points);
    e.put<std::uint32_t>(p.mpu_max_depth);
    e.put<std::uint32_t>(p.global_max_points);
    e.put<std::uint32_t>(p.normalise_axes ? 1 : 0);
    e.put<std::uint32_t>(p.rbf_grid_local_points);
    e.put<double>(p.hardy_c_rel);
    e.put<double>(p.hardy_c_world);
    e.put<double>(p.binning_m);
    e.put<double>(p.mpu_alpha);
    e.put<double>(p.merge_rel);
    return e.b;
}

std::vector<unsigned char> encode_identity(const FittedData& d) {
    Enc e;
    const PointSetIdentity& id = d.identity;
    e.put<std::uint64_t>(id.count);
    for (int k = 0; k < 2; ++k)
        for (int a = 0; a < 3; ++a) e.put<double>(id.bounds[k][a]);
    e.put<double>(id.value_range[0]);
    e.put<double>(id.value_range[1]);
    e.put<std::uint64_t>(id.hash);
    e.put<std::uint64_t>(d.dropped_nonfinite);
    e.put<std::uint64_t>(d.dropped_blanked);
    e.put<std::uint32_t>(d.has_values ? 1 : 0);
    const std::size_t nb = std::min(d.value_name.size(), kMaxNameBytes);
    e.put<std::uint32_t>(static_cast<std::uint32_t>(nb));
    e.b.insert(e.b.end(), d.value_name.begin(), d.value_name.begin() + static_cast<std::ptrdiff_t>(nb));
    return e.b;
}

std::vector<unsigned char> encode_stats(const FieldBuildStats& s) {
    Enc e;
    for (std::uint64_t v : {s.input_points, s.merged_points, s.used_points, s.locals, s.interpolated, s.rank_deficient,
                            s.regularised, s.linear_fallback, s.polynomial_only, s.capped, s.grown, s.max_local_points,
                            s.octree_nodes, s.memory_bytes})
        e.put<std::uint64_t>(v);
    for (std::int64_t v : s.grid_dims) e.put<std::int64_t>(v);
    e.put<std::uint32_t>(s.octree_depth);
    e.put<std::uint32_t>(0);
    e.put<double>(s.merge_tolerance);
    e.put<double>(s.hardy_c_world);
    e.put<double>(s.mean_local_points);
    return e.b;
}

// ---- writing

/// Writes sections into the AtomicFile as the field hands over its arrays.
class SectionWriter final : public FieldStateWriter {
public:
    SectionWriter(AtomicFile& out, int level) : out_(out), level_(level) {}
    ~SectionWriter() override { ZSTD_freeCCtx(cctx_); }
    void put(std::string_view name, StateType type, const void* data, std::size_t count) override {
        write_section(name, static_cast<std::uint32_t>(type), data, count);
    }
    void write_section(std::string_view name, std::uint32_t type, const void* data, std::size_t count) {
        const std::size_t es = element_size(type);
        const std::size_t raw = count * es;
        const unsigned char* payload = static_cast<const unsigned char*>(data);
        std::size_t stored = raw;
        std::uint32_t flags = 0;
        if (level_ > 0 && raw >= 256) {
            const unsigned char* src = payload;
            if (es > 1) {  // byte planes: exponents and high mantissa bytes compress, low ones barely
                shuffled_.resize(raw);
                shuffle(payload, shuffled_.data(), count, es);
                src = shuffled_.data();
            }
            if (!cctx_) cctx_ = ZSTD_createCCtx();
            if (!cctx_) throw std::bad_alloc();
            z_.resize(ZSTD_compressBound(raw));
            const std::size_t n = ZSTD_compressCCtx(cctx_, z_.data(), z_.size(), src, raw, level_);
            if (ZSTD_isError(n)) throw IoError(out_.path() + ": zstd compression failed (" + ZSTD_getErrorName(n) + ")");
            if (n < raw - raw / 33) {  // keep it when it saves at least 3%
                payload = z_.data();
                stored = n;
                flags = kFlagZstd | (es > 1 ? kFlagShuffled : 0);
            }
        }
        unsigned char h[kFieldFileSectionHeaderBytes] = {};
        if (name.empty() || name.size() > kNameBytes) throw InvalidArgument("field file: bad section name");
        std::memcpy(h, name.data(), name.size());
        const std::uint64_t cnt = count, st = stored;
        const std::uint32_t pcrc = crc32_ieee(0, payload, stored);
        std::memcpy(h + 16, &type, 4);
        std::memcpy(h + 20, &flags, 4);
        std::memcpy(h + 24, &cnt, 8);
        std::memcpy(h + 32, &st, 8);
        std::memcpy(h + 40, &pcrc, 4);
        const std::uint32_t hcrc = crc32_ieee(0, h, 44);
        std::memcpy(h + 44, &hcrc, 4);
        out_.write(h, sizeof h);
        out_.write(payload, stored);
        bytes_ += sizeof h + stored;
        ++sections_;
    }
    std::uint64_t bytes() const { return bytes_; }
    std::uint32_t sections() const { return sections_; }

private:
    AtomicFile& out_;
    int level_;
    ZSTD_CCtx* cctx_ = nullptr;
    std::vector<unsigned char> shuffled_, z_;
    std::uint64_t bytes_ = 0;
    std::uint32_t sections_ = 0;
};

std::array<unsigned char, kFieldFileHeaderBytes> encode_header(FieldKind kind, std::uint32_t sections, std::uint64_t file_bytes) {
    std::array<unsigned char, kFieldFileHeaderBytes> h{};
    std::memcpy(h.data(), kFieldFileMagic, 8);
    const std::uint32_t v[4] = {kFieldFileVersion, static_cast<std::uint32_t>(kFieldFileHeaderBytes),
                                static_cast<std::uint32_t>(kind), sections};
    std::memcpy(h.data() + 8, v, 16);
    std::memcpy(h.data() + 24, &file_bytes, 8);
    const std::uint32_t crc = crc32_ieee(0, h.data(), 60);
    std::memcpy(h.data() + 60, &crc, 4);
    return h;
}

// ---- reading

using ReadAt = std::function<void(void* dst, std::size_t n, std::uint64_t offset)>;

class Parser {
public:
    Parser(ReadAt read, std::uint64_t size, std::string name) : read_(std::move(read)), size_(size), name_(std::move(name)) {}

    [[noreturn]] void fail(std::uint64_t offset, const std::string& what) const {
        throw FormatError(name_ + ": offset " + std::to_string(offset) + ": " + what);
    }

    FieldFile parse() {
        FieldFile out;
        FieldFileInfo& info = out.info;
        info.file_bytes = size_;
        unsigned char h[kFieldFileHeaderBytes];
        if (size_ < 8) fail(0, "truncated: " + std::to_string(size_) + " bytes, not a meshless field file (.mlf)");
        read_(h, 8, 0);
        if (std::memcmp(h, kFieldFileMagic, 8) != 0) fail(0, "not a meshless field file (.mlf): wrong magic");
        if (size_ < kFieldFileHeaderBytes)
            fail(size_, "truncated: " + std::to_string(size_) + " bytes, the header alone has " + std::to_string(kFieldFileHeaderBytes));
        read_(h, kFieldFileHeaderBytes, 0);
        std::uint32_t version, header_bytes, kind, count;
        std::uint64_t file_bytes;
        std::memcpy(&version, h + 8, 4);
        std::memcpy(&header_bytes, h + 12, 4);
        std::memcpy(&kind, h + 16, 4);
        std::memcpy(&count, h + 20, 4);
        std::memcpy(&file_bytes, h + 24, 8);
        if (version > kFieldFileVersion)
            fail(8, "made by a newer version of meshless (format version " + std::to_string(version) + "; this one reads " +
                        std::to_string(kFieldFileVersion) + "): refit the field or update meshless");
        if (version < kFieldFileVersion)
            fail(8, "made by an older version of meshless (format version " + std::to_string(version) + "; this one reads " +
                        std::to_string(kFieldFileVersion) + "): refit the field with meshless fit");
        std::uint32_t crc;
        std::memcpy(&crc, h + 60, 4);
        if (!crc_matches(crc, crc32_ieee(0, h, 60))) fail(60, "header checksum mismatch (the file is damaged)");
        if (header_bytes != kFieldFileHeaderBytes) fail(12, "header size " + std::to_string(header_bytes) + ", expected 64");
        if (kind > static_cast<std::uint32_t>(FieldKind::global_rbf)) fail(16, "unknown field kind " + std::to_string(kind));
        if (file_bytes != size_)
            fail(24, file_bytes > size_ ? "truncated: the header says " + std::to_string(file_bytes) + " bytes, the file has " + std::to_string(size_)
                                        : "the header says " + std::to_string(file_bytes) + " bytes, the file has " + std::to_string(size_) + " (bytes appended)");
        for (int k = 32; k < 60; ++k)
            if (h[k] != 0) fail(static_cast<std::uint64_t>(k), "non-zero reserved header bytes");
        if (count < 3 || count > (size_ - kFieldFileHeaderBytes) / kFieldFileSectionHeaderBytes)
            fail(20, "section count " + std::to_string(count) + " does not fit the file");
        const FieldKind fk = static_cast<FieldKind>(kind);

        FieldState state(name_ + ": ", "offset " + std::to_string(size_));
        state.set_resizer(&resize_large<double>);
        std::uint64_t at = kFieldFileHeaderBytes;
        for (std::uint32_t s = 0; s < count; ++s) {
            FieldFileSection sec = section_header(at);
            std::vector<unsigned char> bytes;
            const std::string where = "offset " + std::to_string(at) + ": section '" + sec.name + "'";
            const std::uint64_t payload_at = at + kFieldFileSectionHeaderBytes;
            if (s < 3) {
                static const char* const kMeta[3] = {"params", "identity", "build_stats"};
                if (sec.name != kMeta[s]) fail(at, "section " + std::to_string(s) + " is '" + sec.name + "', expected '" + kMeta[s] + "'");
                if (sec.type != kTypeBytes) fail(at + 16, "section '" + sec.name + "' is not of type bytes");
                bytes = payload(sec, payload_at);
                if (s == 0) decode_params(bytes, payload_at, fk, info.params);
                else if (s == 1) decode_identity(bytes, payload_at, info.data);
                else decode_stats(bytes, payload_at, info.stats);
            } else {
                if (sec.type == kTypeBytes) fail(at + 16, "state section '" + sec.name + "' of type bytes");
                state.add(sec.name, payload_array(sec, payload_at), where);
            }
            at = payload_at + sec.stored_bytes;
            info.sections.push_back(std::move(sec));
        }
        if (at != size_) fail(at, std::to_string(size_ - at) + " bytes after the last of " + std::to_string(count) + " sections");
        out.field = load_field_state(fk, state);
        return out;
    }

private:
    FieldFileSection section_header(std::uint64_t at) {
        if (size_ - at < kFieldFileSectionHeaderBytes) fail(at, "truncated section header");
        unsigned char h[kFieldFileSectionHeaderBytes];
        read_(h, sizeof h, at);
        std::uint32_t hcrc;
        std::memcpy(&hcrc, h + 44, 4);
        if (!crc_matches(hcrc, crc32_ieee(0, h, 44))) fail(at, "section header checksum mismatch (the file is damaged)");
        FieldFileSection s;
        s.offset = at;
        std::size_t len = 0;
        while (len < kNameBytes && h[len] != 0) ++len;
        for (std::size_t k = 0; k < kNameBytes; ++k) {
            const unsigned char c = h[k];
            const bool ok = k < len ? ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_') : c == 0;
            if (!ok) fail(at + k, "bad section name byte 0x" + hex(c).substr(14));
        }
        if (len == 0) fail(at, "empty section name");
        s.name.assign(reinterpret_cast<const char*>(h), len);
        std::uint32_t flags;
        std::memcpy(&s.type, h + 16, 4);
        std::memcpy(&flags, h + 20, 4);
        std::memcpy(&s.count, h + 24, 8);
        std::memcpy(&s.stored_bytes, h + 32, 8);
        const std::size_t es = element_size(s.type);
        if (es == 0) fail(at + 16, "section '" + s.name + "': unknown element type " + std::to_string(s.type));
        if (flags & ~(kFlagZstd | kFlagShuffled)) fail(at + 20, "section '" + s.name + "': unknown flags");
        s.compressed = flags & kFlagZstd;
        s.shuffled = flags & kFlagShuffled;
        if (s.shuffled && !s.compressed) fail(at + 20, "section '" + s.name + "': shuffled but not compressed");
        if (s.count > (std::uint64_t{1} << 58)) fail(at + 24, "section '" + s.name + "': element count " + std::to_string(s.count) + " too large");
        s.raw_bytes = s.count * es;
        const std::uint64_t left = size_ - at - kFieldFileSectionHeaderBytes;
        if (s.stored_bytes > left)
            fail(at + 32, "truncated: section '" + s.name + "' has " + std::to_string(s.stored_bytes) + " payload bytes, the file " +
                              std::to_string(left) + " left");
        if (!s.compressed && s.stored_bytes != s.raw_bytes)
            fail(at + 32, "section '" + s.name + "': " + std::to_string(s.stored_bytes) + " payload bytes for " +
                              std::to_string(s.count) + " elements of " + std::to_string(es) + " bytes");
        std::memcpy(&s.stored_crc, h + 40, 4);
        return s;
    }

    /// The payload bytes as stored (decompressed, still shuffled), proven by the file before any
    /// allocation, in buffers reused from section to section (large fresh allocations cost a page
    /// fault per 4 KiB); valid until the next call.
    std::span<const unsigned char> payload_bytes(const FieldFileSection& s, std::uint64_t at) {
        resize_large(stored_, static_cast<std::size_t>(s.stored_bytes));  // <= the bytes left in the file
        if (!stored_.empty()) read_(stored_.data(), stored_.size(), at);
        if (!crc_matches(s.stored_crc, crc32_ieee(0, stored_.data(), stored_.size())))
            fail(at, "section '" + s.name + "': payload checksum mismatch (the file is damaged)");
        if (!s.compressed) return stored_;
        return decompress(s, at);
    }

    /// The raw payload bytes of a metadata section (unshuffled).
    std::vector<unsigned char> payload(const FieldFileSection& s, std::uint64_t at) {
        const std::span<const unsigned char> b = payload_bytes(s, at);
        std::vector<unsigned char> out(b.size());
        if (s.shuffled) unshuffle(b.data(), out.data(), static_cast<std::size_t>(s.count), element_size(s.type));
        else if (!b.empty()) std::memcpy(out.data(), b.data(), b.size());
        return out;
    }

    std::span<const unsigned char> decompress(const FieldFileSection& s, std::uint64_t at) {
        if (!dctx_) dctx_ = ZSTD_createDCtx();
        if (!dctx_) throw std::bad_alloc();
        ZSTD_DCtx_reset(dctx_, ZSTD_reset_session_only);
        const std::size_t cap = static_cast<std::size_t>(s.raw_bytes);
        std::vector<unsigned char>& out = raw_;
        // Grow as data arrives (a small frame may claim a huge output), never beyond the declared
        // size; shuffled doubles compress about 1.1-4x, so the first guess usually holds it all.
        resize_large(out, std::min<std::size_t>(cap, std::max<std::size_t>(1 << 16, 16 * stored_.size())));
        ZSTD_inBuffer ib{stored_.data(), stored_.size(), 0};
        std::size_t produced = 0;
        for (;;) {
            ZSTD_outBuffer ob{out.data(), out.size(), produced};
            const std::size_t r = ZSTD_decompressStream(dctx_, &ob, &ib);
            produced = ob.pos;
            if (ZSTD_isError(r)) fail(at, "section '" + s.name + "': corrupt zstd payload (" + ZSTD_getErrorName(r) + ")");
            if (r == 0) break;  // frame complete
            if (produced == out.size()) {
                if (out.size() == cap) {
                    // full: anything more than the declared size is an error
                    unsigned char extra;
                    ZSTD_outBuffer ob2{&extra, 1, 0};
                    const std::size_t r2 = ZSTD_decompressStream(dctx_, &ob2, &ib);
                    if (ZSTD_isError(r2) || ob2.pos > 0)
                        fail(at, "section '" + s.name + "': payload decompresses to more than the declared " + std::to_string(cap) + " bytes");
                    if (r2 == 0) break;
                    if (ib.pos == ib.size) fail(at, "section '" + s.name + "': truncated zstd payload");
                    continue;
                }
                out.resize(std::min(cap, out.size() * 2));
            } else if (ib.pos == ib.size) {
                fail(at, "section '" + s.name + "': truncated zstd payload");
            }
        }
        if (ib.pos != ib.size) fail(at, "section '" + s.name + "': bytes after the zstd frame");
        if (produced != cap)
            fail(at, "section '" + s.name + "': payload decompresses to " + std::to_string(produced) + " bytes, declared " + std::to_string(cap));
        return std::span<const unsigned char>(out.data(), produced);
    }

    StateArray payload_array(const FieldFileSection& s, std::uint64_t at) {
        auto fill = [&](auto vec) {
            using T = typename decltype(vec)::value_type;
            if (!s.compressed) {  // straight into the array: the file has proven its size
                resize_large(vec, static_cast<std::size_t>(s.count));
                if (s.stored_bytes > 0) read_(vec.data(), static_cast<std::size_t>(s.stored_bytes), at);
                if (!crc_matches(s.stored_crc, crc32_ieee(0, vec.data(), static_cast<std::size_t>(s.stored_bytes))))
                    fail(at, "section '" + s.name + "': payload checksum mismatch (the file is damaged)");
            } else {
                const std::span<const unsigned char> b = payload_bytes(s, at);
                resize_large(vec, b.size() / sizeof(T));
                if (s.shuffled) unshuffle(b.data(), reinterpret_cast<unsigned char*>(vec.data()), vec.size(), sizeof(T));
                else if (!b.empty()) std::memcpy(vec.data(), b.data(), b.size());
            }
            return StateArray(std::move(vec));
        };
        switch (static_cast<StateType>(s.type)) {
            case StateType::f64: return fill(std::vector<double>());
            case StateType::i64: return fill(std::vector<std::int64_t>());
            case StateType::u32: return fill(std::vector<std::uint32_t>());
            case StateType::i32: return fill(std::vector<std::int32_t>());
        }
        fail(s.offset + 16, "unknown element type");
    }

    void decode_params(const std::vector<unsigned char>& b, std::uint64_t at, FieldKind kind, FieldParams& p) {
        if (b.size() != kParamsBytes) fail(at, "section 'params': " + std::to_string(b.size()) + " bytes, expected 80");
        Dec d{b.data(), b.size()};
        const std::uint32_t k = d.get<std::uint32_t>();
        if (k != static_cast<std::uint32_t>(kind)) fail(at, "section 'params': field kind " + std::to_string(k) + " differs from the header's");
        p.kind = kind;
        const std::uint32_t support = d.get<std::uint32_t>();
        if (support > 1) fail(at + 4, "section 'params': unknown support " + std::to_string(support));
        p.rbf_grid_support = static_cast<RbfGridSupport>(support);
        p.rbf_grid_max_local = d.get<std::uint32_t>();
        p.rbf_grid_min_local = d.get<std::uint32_t>();
        p.mpu_max_points = d.get<std::uint32_t>();
        p.mpu_min_points = d.get<std::uint32_t>();
        p.mpu_max_depth = d.get<std::uint32_t>();
        p.global_max_points = d.get<std::uint32_t>();
        const std::uint32_t norm = d.get<std::uint32_t>();
        if (norm > 1) fail(at + 32, "section 'params': normalise_axes is neither 0 nor 1");
        p.normalise_axes = norm == 1;
        p.rbf_grid_local_points = d.get<std::uint32_t>();  // 0 in files made before it existed: all points
        p.hardy_c_rel = d.get<double>();
        p.hardy_c_world = d.get<double>();
        p.binning_m = d.get<double>();
        p.mpu_alpha = d.get<double>();
        p.merge_rel = d.get<double>();
        for (double v : {p.hardy_c_rel, p.hardy_c_world, p.binning_m, p.mpu_alpha, p.merge_rel})
            if (!std::isfinite(v)) fail(at + 40, "section 'params': non-finite parameter");
    }

    void decode_identity(const std::vector<unsigned char>& b, std::uint64_t at, FittedData& f) {
        if (b.size() < kIdentityFixedBytes) fail(at, "section 'identity': " + std::to_string(b.size()) + " bytes, at least 104 expected");
        Dec d{b.data(), b.size()};
        PointSetIdentity& id = f.identity;
        id.count = d.get<std::uint64_t>();
        for (int k = 0; k < 2; ++k) {
            const double x = d.get<double>(), y = d.get<double>(), z = d.get<double>();
            id.bounds[k] = Vec3{x, y, z};
        }
        id.value_range[0] = d.get<double>();
        id.value_range[1] = d.get<double>();
        id.hash = d.get<std::uint64_t>();
        f.dropped_nonfinite = d.get<std::uint64_t>();
        f.dropped_blanked = d.get<std::uint64_t>();
        const std::uint32_t hv = d.get<std::uint32_t>();
        if (hv > 1) fail(at + 96, "section 'identity': has_values is neither 0 nor 1");
        f.has_values = hv == 1;
        const std::uint32_t nb = d.get<std::uint32_t>();
        if (nb > kMaxNameBytes || nb != b.size() - kIdentityFixedBytes)
            fail(at + 100, "section 'identity': value name of " + std::to_string(nb) + " bytes in " +
                               std::to_string(b.size() - kIdentityFixedBytes));
        f.value_name.assign(reinterpret_cast<const char*>(b.data()) + kIdentityFixedBytes, nb);
    }

    void decode_stats(const std::vector<unsigned char>& b, std::uint64_t at, FieldBuildStats& s) {
        if (b.size() != kStatsBytes) fail(at, "section 'build_stats': " + std::to_string(b.size()) + " bytes, expected 168");
        Dec d{b.data(), b.size()};
        for (std::uint64_t* v : {&s.input_points, &s.merged_points, &s.used_points, &s.locals, &s.interpolated,
                                 &s.rank_deficient, &s.regularised, &s.linear_fallback, &s.polynomial_only, &s.capped,
                                 &s.grown, &s.max_local_points, &s.octree_nodes, &s.memory_bytes})
            *v = d.get<std::uint64_t>();
        for (std::int64_t& v : s.grid_dims) v = d.get<std::int64_t>();
        s.octree_depth = d.get<std::uint32_t>();
        d.get<std::uint32_t>();
        s.merge_tolerance = d.get<double>();
        s.hardy_c_world = d.get<double>();
        s.mean_local_points = d.get<double>();
    }

    ReadAt read_;
    std::uint64_t size_;
    std::string name_;
    std::vector<unsigned char> stored_, raw_;  // reused from section to section
    ZSTD_DCtx* dctx_ = nullptr;

public:
    ~Parser() { ZSTD_freeDCtx(dctx_); }
};

}  // namespace

void write_field_file(const std::string& path, const Field& field, const FieldParams& params, const FittedData& data,
                      const FieldBuildStats& stats, int zstd_level) {
    const FieldKind kind = fitted_field_kind(field);
    if (kind != params.kind) throw InvalidArgument(path + ": the field is " + field.name() + ", the parameters say " + std::string(field_kind_name(params.kind)));
    if (is_streaming_output(path)) throw InvalidArgument(path + ": a field file (.mlf) must be a regular file, not a stream or device");
    if (zstd_level < 0 || zstd_level > ZSTD_maxCLevel()) throw InvalidArgument("field file: zstd level out of range");
    AtomicFile out(path, Durability::fsync);
    const auto placeholder = encode_header(kind, 0, 0);
    out.write(placeholder.data(), placeholder.size());
    SectionWriter w(out, zstd_level);
    const auto p = encode_params(params), id = encode_identity(data), st = encode_stats(stats);
    w.write_section("params", kTypeBytes, p.data(), p.size());
    w.write_section("identity", kTypeBytes, id.data(), id.size());
    w.write_section("build_stats", kTypeBytes, st.data(), st.size());
    save_field_state(field, w);
    const auto header = encode_header(kind, w.sections(), kFieldFileHeaderBytes + w.bytes());
    out.pwrite(0, header.data(), header.size());
    out.commit();
}

FieldFile read_field_file(const std::string& path) {
    const std::uint64_t size = regular_file_size(path);
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    struct Closer {
        std::FILE* f;
        ~Closer() { std::fclose(f); }
    } closer{f};
    ReadAt read = [&](void* dst, std::size_t n, std::uint64_t offset) {
        if (fseeko(f, static_cast<off_t>(offset), SEEK_SET) != 0 || std::fread(dst, 1, n, f) != n)
            throw IoError(path + ": offset " + std::to_string(offset) + ": read failed (" +
                          (std::ferror(f) ? std::strerror(errno) : "the file shrank while being read") + ")");
    };
    return Parser(read, size, path).parse();
}

FieldFile parse_field_file_bytes(std::span<const unsigned char> bytes, const std::string& name) {
    ReadAt read = [&](void* dst, std::size_t n, std::uint64_t offset) {
        std::memcpy(dst, bytes.data() + offset, n);  // the parser checks every range against the size first
    };
    return Parser(read, bytes.size(), name).parse();
}

bool is_field_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the open
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    char m[8];
    const bool ok = std::fread(m, 1, 8, f) == 8 && std::memcmp(m, kFieldFileMagic, 8) == 0;
    std::fclose(f);
    return ok;
}

void check_fitted_to(const FieldFileInfo& info, const PointSetIdentity& data, const std::string& path) {
    if (info.data.identity.same_data(data)) return;
    throw FormatError(path + " was fitted to other data: " + describe_identity(info.data.identity) + "; these are " +
                      describe_identity(data));
}

}  // namespace meshless
