#include "ooc/sample_store_format.hpp"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "formats/store_framing.hpp"
#include "kernels/errors.hpp"
#include "ooc/row_key_codec.hpp"
#include "ooc/row_set.hpp"
#include "ooc/span_space_levels.hpp"

namespace meshless {

namespace {

constexpr char kPointStreamMagic[8] = {'\x89', 'M', 'L', 'S', '\r', '\n', '\x1a', '\n'};


}  // namespace

std::uint32_t sample_store_crc32(std::uint32_t crc, const void* data, std::size_t n) {
    const auto* b = static_cast<const Bytef*>(data);
    while (n > 0) {  // zlib takes uInt lengths
        const uInt step = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
        crc = static_cast<std::uint32_t>(crc32(crc, b, step));
        b += step;
        n -= step;
    }
    return crc;
}

std::uint64_t SampleStoreLayout::key_limit() const {
    const std::uint64_t B = info.brick_edge;
    return info.mlb.brick_count * B * B;  // < 2^40: checked at decode
}

std::array<unsigned char, kSampleStoreHeaderBytes> encode_sample_store_header(const SampleStoreInfo& info) {
    std::array<unsigned char, kSampleStoreHeaderBytes> a{};
    unsigned char* h = a.data();
    std::memcpy(h, kSampleStoreMagic, 8);
    put_le<std::uint32_t>(h + 8, kSampleStoreVersion);
    put_le<std::uint32_t>(h + 12, kSampleStoreHeaderBytes);
    for (int i = 0; i < 3; ++i) {
        put_le<std::int64_t>(h + 16 + 8 * i, info.grid.dims[i]);
        put_le<double>(h + 40 + 8 * i, info.grid.origin[i]);
        put_le<double>(h + 64 + 8 * i, info.grid.spacing[i]);
    }
    put_le<std::uint32_t>(h + 88, static_cast<std::uint32_t>(info.type));
    put_le<std::uint32_t>(h + 92, info.brick_edge);
    put_le<double>(h + 96, info.value_lo);
    put_le<double>(h + 104, info.value_hi);
    put_le<std::uint32_t>(h + 112, info.levels);
    put_le<std::uint32_t>(h + 116, info.exact_levels ? 1u : 0u);
    put_le<std::uint64_t>(h + 120, info.key_count);
    put_le<std::uint64_t>(h + 128, info.bucket_count);
    put_le<std::uint64_t>(h + 136, info.cells);
    put_le<std::uint64_t>(h + 144, info.constant_cells);
    put_le<std::uint64_t>(h + 152, info.nonfinite_cells);
    put_le<std::uint64_t>(h + 160, info.mlb.brick_count);
    put_le<std::uint64_t>(h + 168, info.mlb.file_bytes);
    put_le<std::uint32_t>(h + 176, info.mlb.header_crc);
    put_le<std::uint32_t>(h + 180, info.mlb.index_crc);
    put_le<std::uint64_t>(h + 184, info.key_bytes);
    std::memcpy(h + kSampleStorePathOffset, info.mlb_path.data(),
                std::min(info.mlb_path.size(), kSampleStorePathBytes - 1));
    put_le<std::uint32_t>(h + 508, sample_store_crc32(0, h, 508));
    return a;
}

void encode_sample_store_bucket(const SampleBucket& b, unsigned char* e) {
    put_le<std::uint16_t>(e, b.a);
    put_le<std::uint16_t>(e + 2, b.b);
    put_le<std::uint32_t>(e + 4, b.crc);
    put_le<std::uint64_t>(e + 8, b.offset);
    put_le<std::uint64_t>(e + 16, b.bytes);
    put_le<std::uint64_t>(e + 24, b.count);
}

std::array<unsigned char, kSampleStoreFooterBytes> encode_sample_store_footer(std::uint64_t table_offset,
                                                                              std::uint64_t bucket_count,
                                                                              std::uint32_t table_crc) {
    return encode_store_footer(table_offset, bucket_count, table_crc, kSampleStoreVersion,
                               std::string_view(kSampleStoreEndMagic, 8));
}

SampleStoreLayout decode_sample_store_layout(const ReadAt& read, std::uint64_t size, const std::string& name) {
    auto bad = [&](const std::string& what) { return FormatError(name + ": " + what); };
    if (size >= 8) {
        unsigned char m[8];
        read(m, 8, 0);
        if (std::memcmp(m, kPointStreamMagic, 8) == 0)
            throw bad("is a meshless point stream, not a sample store (make one with 'meshless generate vol.mlb --all -o vol.mls')");
    }
    check_store_preamble(read, size, name,
                         {"sample store", std::string_view(kSampleStoreMagic, 8), kSampleStoreVersion, kSampleStoreHeaderBytes,
                          "; remake it with 'meshless generate vol.mlb --all -o vol.mls'"});
    unsigned char h[kSampleStoreHeaderBytes];
    read(h, sizeof h, 0);
    if (get_le<std::uint32_t>(h + 508) != sample_store_crc32(0, h, 508))
        throw bad("sample store header checksum mismatch (corrupt header)");
    if (get_le<std::uint32_t>(h + 12) != kSampleStoreHeaderBytes) throw bad("unexpected header size in sample store header");

    SampleStoreLayout out;
    SampleStoreInfo& info = out.info;
    for (int a = 0; a < 3; ++a) {
        info.grid.dims[a] = get_le<std::int64_t>(h + 16 + 8 * a);
        info.grid.origin[a] = get_le<double>(h + 40 + 8 * a);
        info.grid.spacing[a] = get_le<double>(h + 64 + 8 * a);
        if (info.grid.dims[a] < 1 || info.grid.dims[a] > (std::int64_t{1} << 31) || !(info.grid.spacing[a] > 0) ||
            !std::isfinite(info.grid.spacing[a]) || !std::isfinite(info.grid.origin[a]))
            throw bad("invalid grid in sample store header");
    }
    const std::uint32_t type = get_le<std::uint32_t>(h + 88);
    if (type < 1 || type > 4) throw bad("unknown sample type " + std::to_string(type) + " in sample store header");
    info.type = static_cast<SampleType>(type);
    info.brick_edge = get_le<std::uint32_t>(h + 92);
    if (info.brick_edge < 2 || info.brick_edge > 1024) throw bad("invalid brick edge " + std::to_string(info.brick_edge) + " in sample store header");
    info.value_lo = get_le<double>(h + 96);
    info.value_hi = get_le<double>(h + 104);
    info.levels = get_le<std::uint32_t>(h + 112);
    info.exact_levels = (get_le<std::uint32_t>(h + 116) & 1u) != 0;
    if (info.levels < 1 || info.levels > kMaxSpanSpaceLevels || !std::isfinite(info.value_lo) ||
        !std::isfinite(info.value_hi) || !(info.value_hi >= info.value_lo))
        throw bad("invalid span-space levels in sample store header");
    info.key_count = get_le<std::uint64_t>(h + 120);
    info.bucket_count = get_le<std::uint64_t>(h + 128);
    info.cells = get_le<std::uint64_t>(h + 136);
    info.constant_cells = get_le<std::uint64_t>(h + 144);
    info.nonfinite_cells = get_le<std::uint64_t>(h + 152);
    info.mlb.brick_count = get_le<std::uint64_t>(h + 160);
    info.mlb.file_bytes = get_le<std::uint64_t>(h + 168);
    info.mlb.header_crc = get_le<std::uint32_t>(h + 176);
    info.mlb.index_crc = get_le<std::uint32_t>(h + 180);
    info.key_bytes = get_le<std::uint64_t>(h + 184);
    // an .mlb holds a 64-byte index entry per brick: its size bounds the brick count (and the keys)
    if (info.mlb.brick_count < 1 || info.mlb.brick_count > info.mlb.file_bytes / 64 ||
        info.mlb.brick_count > (std::uint64_t{1} << 40) / (std::uint64_t{info.brick_edge} * info.brick_edge))
        throw bad("invalid brick store identity in sample store header");
    const char* p = reinterpret_cast<const char*>(h + kSampleStorePathOffset);
    info.mlb_path.assign(p, strnlen(p, kSampleStorePathBytes));
    if (info.mlb_path.empty() || info.mlb_path.size() >= kSampleStorePathBytes)
        throw bad("sample store header names no brick store");

    // sizes: checked against the file before anything is allocated
    const std::uint64_t room = size - kSampleStoreHeaderBytes - kSampleStoreFooterBytes;
    if (info.key_bytes > room || info.bucket_count > (room - info.key_bytes) / kSampleStoreBucketBytes)
        throw bad("truncated sample store (" + std::to_string(size) + " bytes cannot hold " +
                  std::to_string(info.key_bytes) + " key bytes and " + std::to_string(info.bucket_count) + " buckets)");
    if (info.key_count > info.key_bytes) throw bad("sample store header claims more keys than key bytes");
    const std::uint64_t table_offset = kSampleStoreHeaderBytes + info.key_bytes;
    const std::uint64_t expected = table_offset + info.bucket_count * kSampleStoreBucketBytes + kSampleStoreFooterBytes;
    if (size > expected) throw bad("sample store has " + std::to_string(size - expected) + " unexpected trailing bytes");
    if (size < expected) throw bad("truncated sample store: expected " + std::to_string(expected) + " bytes");

    unsigned char f[kSampleStoreFooterBytes];
    read(f, sizeof f, expected - sizeof f);
    if (std::memcmp(f + 24, kSampleStoreEndMagic, 8) != 0 || get_le<std::uint32_t>(f + 20) != kSampleStoreVersion ||
        get_le<std::uint64_t>(f) != table_offset || get_le<std::uint64_t>(f + 8) != info.bucket_count)
        throw bad("sample store footer does not match its header (corrupt or truncated file)");
    // the table, read in chunks (checksummed and decoded as it comes: no second copy of it)
    out.buckets.resize(info.bucket_count);
    std::vector<unsigned char> chunk;
    std::uint32_t crc = 0;
    std::uint64_t next = 0, keys = 0;
    constexpr std::size_t kChunkEntries = 2048;
    for (std::size_t c0 = 0; c0 < out.buckets.size(); c0 += kChunkEntries) {
        const std::size_t n = std::min(kChunkEntries, out.buckets.size() - c0);
        chunk.resize(n * kSampleStoreBucketBytes);
        read(chunk.data(), chunk.size(), table_offset + c0 * kSampleStoreBucketBytes);
        crc = sample_store_crc32(crc, chunk.data(), chunk.size());
        for (std::size_t i = c0; i < c0 + n; ++i) {
            const unsigned char* e = chunk.data() + (i - c0) * kSampleStoreBucketBytes;
            SampleBucket& b = out.buckets[i];
            b.a = get_le<std::uint16_t>(e);
            b.b = get_le<std::uint16_t>(e + 2);
            b.crc = get_le<std::uint32_t>(e + 4);
            b.offset = get_le<std::uint64_t>(e + 8);
            b.bytes = get_le<std::uint64_t>(e + 16);
            b.count = get_le<std::uint64_t>(e + 24);
        }
    }
    if (crc != get_le<std::uint32_t>(f + 16)) throw bad("sample store bucket table checksum mismatch (corrupt index)");
    for (std::size_t i = 0; i < out.buckets.size(); ++i) {
        const SampleBucket& b = out.buckets[i];
        const SampleBucket* prev = i ? &out.buckets[i - 1] : nullptr;
        const bool ordered = !prev || prev->a < b.a || (prev->a == b.a && prev->b < b.b);
        if (b.a > b.b || b.b >= info.levels || !ordered || b.offset != next || b.count == 0 || b.bytes < b.count ||
            b.bytes > info.key_bytes - next || b.bytes / 10 > b.count)
            throw bad("inconsistent bucket " + std::to_string(i) + " in sample store table");
        next += b.bytes;
        keys += b.count;
    }
    if (next != info.key_bytes || keys != info.key_count)
        throw bad("sample store table does not cover its keys (inconsistent table)");
    return out;
}

void decode_sample_store_bucket(const SampleStoreLayout& layout, std::size_t i, const unsigned char* bytes,
                                RowSet* rows, const std::string& name) {
    const SampleBucket& b = layout.buckets[i];
    auto where = [&]() {
        return name + ": bucket " + std::to_string(i) + " (levels " + std::to_string(b.a) + ".." + std::to_string(b.b) +
               ", key bytes " + std::to_string(b.offset) + ".." + std::to_string(b.offset + b.bytes) + ")";
    };
    if (sample_store_crc32(0, bytes, b.bytes) != b.crc) throw FormatError(where() + ": checksum mismatch (corrupt keys)");
    const bool ok = rows ? decode_row_keys(bytes, bytes + b.bytes, b.count, layout.key_limit(),
                                           [rows](std::uint64_t k) { rows->insert(k); })
                         : decode_row_keys(bytes, bytes + b.bytes, b.count, layout.key_limit(), [](std::uint64_t) {});
    if (!ok) throw FormatError(where() + ": malformed keys");
}

SampleStoreLayout parse_sample_store_bytes(std::span<const unsigned char> bytes, const std::string& name) {
    const ReadAt read = [&](void* dst, std::size_t n, std::uint64_t off) {
        if (off > bytes.size() || n > bytes.size() - off) throw FormatError(name + ": truncated sample store");
        std::memcpy(dst, bytes.data() + off, n);
    };
    SampleStoreLayout layout = decode_sample_store_layout(read, bytes.size(), name);
    for (std::size_t i = 0; i < layout.buckets.size(); ++i)
        decode_sample_store_bucket(layout, i, bytes.data() + kSampleStoreHeaderBytes + layout.buckets[i].offset, nullptr, name);
    return layout;
}

}  // namespace meshless
