#include "formats/point_store_format.hpp"

#include <zstd.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "formats/crc32.hpp"
#include "formats/store_framing.hpp"
#include "kernels/errors.hpp"
#include "kernels/morton.hpp"

namespace meshless {

namespace {


bool finite3(const std::array<double, 3>& a) { return std::isfinite(a[0]) && std::isfinite(a[1]) && std::isfinite(a[2]); }

std::string text_field(const unsigned char* p, std::size_t n) {
    const char* c = reinterpret_cast<const char*>(p);
    return std::string(c, strnlen(c, n));
}

}  // namespace

PointStoreGrid::PointStoreGrid(const std::array<double, 3>& l, const std::array<double, 3>& hi, std::uint32_t lv)
    : lo(l), level(lv) {
    const double s = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    scale = s > 0 ? std::ldexp(1.0, static_cast<int>(level)) / s : 0.0;
}

std::uint64_t PointStoreGrid::key(double x, double y, double z) const {
    const double top = std::ldexp(1.0, static_cast<int>(level)) - 1;
    const double p[3] = {x, y, z};
    std::uint32_t q[3];
    for (int a = 0; a < 3; ++a) {
        double t = std::floor((p[a] - lo[a]) * scale);
        if (!(t >= 0)) t = 0;  // NaN too (never stored: callers drop non-finite points)
        q[a] = static_cast<std::uint32_t>(std::min(t, top));
    }
    return morton_encode(q[0], q[1], q[2]);
}

std::uint32_t point_store_crc32(const void* data, std::size_t n) { return crc32_ieee(0, data, n); }

std::array<unsigned char, kPointStoreHeaderBytes> encode_point_store_header(const PointStoreInfo& info) {
    std::array<unsigned char, kPointStoreHeaderBytes> a{};
    unsigned char* h = a.data();
    std::memcpy(h, kPointStoreMagic, 8);
    put_le<std::uint32_t>(h + 8, kPointStoreVersion);
    put_le<std::uint32_t>(h + 12, kPointStoreHeaderBytes);
    put_le<std::uint64_t>(h + 16, info.points);
    put_le<std::uint64_t>(h + 24, info.dropped_nonfinite);
    put_le<std::uint64_t>(h + 32, info.dropped_blanked);
    put_le<std::uint64_t>(h + 40, info.brick_count);
    for (int i = 0; i < 3; ++i) {
        put_le<double>(h + 48 + 8 * i, info.lo[i]);
        put_le<double>(h + 72 + 8 * i, info.hi[i]);
    }
    put_le<double>(h + 96, info.value_min);
    put_le<double>(h + 104, info.value_max);
    put_le<std::uint32_t>(h + 112, info.level);
    put_le<std::uint32_t>(h + 116, info.brick_points);
    put_le<std::int32_t>(h + 120, info.zstd_level);
    put_le<std::uint32_t>(h + 124, info.has_values ? 1u : 0u);
    std::memcpy(h + 128, info.value_name.data(), std::min(info.value_name.size(), kPointStoreValueNameBytes - 1));
    std::memcpy(h + 192, info.source.data(), std::min(info.source.size(), kPointStoreSourceBytes - 1));
    put_le<std::uint32_t>(h + 508, point_store_crc32(h, 508));
    return a;
}

void encode_point_brick_entry(const PointBrickEntry& e, unsigned char* p) {
    put_le<std::uint64_t>(p, e.key);
    put_le<std::uint32_t>(p + 8, e.level);
    put_le<std::uint32_t>(p + 12, e.crc);
    put_le<std::uint64_t>(p + 16, e.offset);
    put_le<std::uint64_t>(p + 24, e.stored_bytes);
    put_le<std::uint64_t>(p + 32, e.count);
    put_le<std::uint64_t>(p + 40, e.first);
    for (int a = 0; a < 3; ++a) {
        put_le<double>(p + 48 + 8 * a, e.lo[a]);
        put_le<double>(p + 72 + 8 * a, e.hi[a]);
    }
    put_le<double>(p + 96, e.vmin);
    put_le<double>(p + 104, e.vmax);
}

std::array<unsigned char, kPointStoreFooterBytes> encode_point_store_footer(std::uint64_t index_offset,
                                                                            std::uint64_t brick_count,
                                                                            std::uint32_t index_crc) {
    return encode_store_footer(index_offset, brick_count, index_crc, kPointStoreVersion,
                               std::string_view(kPointStoreEndMagic, 8));
}

PointStoreLayout decode_point_store_layout(const PointStoreReadAt& read, std::uint64_t size, const std::string& name) {
    auto bad = [&](const std::string& what) { return FormatError(name + ": " + what); };
    check_store_preamble(read, size, name,
                         {"point store", std::string_view(kPointStoreMagic, 8), kPointStoreVersion, kPointStoreHeaderBytes, ""});
    unsigned char h[kPointStoreHeaderBytes];
    read(h, sizeof h, 0);
    PointStoreLayout out;
    out.header_crc = get_le<std::uint32_t>(h + 508);
    if (!crc_matches(out.header_crc, point_store_crc32(h, 508))) throw bad("point store header checksum mismatch (corrupt header)");
    if (get_le<std::uint32_t>(h + 12) != kPointStoreHeaderBytes) throw bad("unexpected header size in point store header");
    PointStoreInfo& in = out.info;
    in.points = get_le<std::uint64_t>(h + 16);
    in.dropped_nonfinite = get_le<std::uint64_t>(h + 24);
    in.dropped_blanked = get_le<std::uint64_t>(h + 32);
    in.brick_count = get_le<std::uint64_t>(h + 40);
    for (int a = 0; a < 3; ++a) {
        in.lo[a] = get_le<double>(h + 48 + 8 * a);
        in.hi[a] = get_le<double>(h + 72 + 8 * a);
    }
    in.value_min = get_le<double>(h + 96);
    in.value_max = get_le<double>(h + 104);
    in.level = get_le<std::uint32_t>(h + 112);
    in.brick_points = get_le<std::uint32_t>(h + 116);
    in.zstd_level = get_le<std::int32_t>(h + 120);
    const std::uint32_t flags = get_le<std::uint32_t>(h + 124);
    in.has_values = (flags & 1u) != 0;
    in.value_name = text_field(h + 128, kPointStoreValueNameBytes - 1);
    in.source = text_field(h + 192, kPointStoreSourceBytes - 1);
    if (!finite3(in.lo) || !finite3(in.hi)) throw bad("non-finite bounds in point store header");
    for (int a = 0; a < 3; ++a)
        if (!(in.lo[a] <= in.hi[a]) || !(in.hi[a] - in.lo[a] <= kPointStoreMaxExtent))
            throw bad("invalid bounds in point store header");
    if (!std::isfinite(in.value_min) || !std::isfinite(in.value_max) || !(in.value_min <= in.value_max))
        throw bad("invalid value range in point store header");
    if (in.level < 1 || in.level > kPointStoreMaxLevel)
        throw bad("invalid Morton level " + std::to_string(in.level) + " in point store header (1.." +
                  std::to_string(kPointStoreMaxLevel) + ")");
    if (in.brick_points < 1 || in.brick_points > kPointStoreMaxBrickPoints)
        throw bad("invalid brick size " + std::to_string(in.brick_points) + " points in point store header");
    if (flags > 1u) throw bad("unknown flags in point store header");
    if (in.points < 1 || in.brick_count < 1) throw bad("point store header claims no points");

    // sizes: checked against the file before anything is allocated
    const std::uint64_t room = size - kPointStoreHeaderBytes - kPointStoreFooterBytes;
    if (in.brick_count > room / kPointStoreEntryBytes)
        throw bad("truncated point store (" + std::to_string(size) + " bytes cannot hold an index of " +
                  std::to_string(in.brick_count) + " bricks)");
    if (in.brick_count > in.points || in.points / in.brick_points > in.brick_count)
        throw bad("point store header: " + std::to_string(in.points) + " points do not fit " +
                  std::to_string(in.brick_count) + " bricks of at most " + std::to_string(in.brick_points));
    unsigned char f[kPointStoreFooterBytes];
    read(f, sizeof f, size - kPointStoreFooterBytes);
    if (std::memcmp(f + 24, kPointStoreEndMagic, 8) != 0)
        throw bad("truncated or unfinished point store (no footer at the end of the file)");
    if (get_le<std::uint32_t>(f + 20) != kPointStoreVersion || get_le<std::uint64_t>(f + 8) != in.brick_count)
        throw bad("point store footer does not match its header (corrupt or truncated file)");
    out.index_offset = get_le<std::uint64_t>(f);
    out.index_crc = get_le<std::uint32_t>(f + 16);
    if (out.index_offset < kPointStoreHeaderBytes || out.index_offset > size ||
        size - out.index_offset != in.brick_count * kPointStoreEntryBytes + kPointStoreFooterBytes)
        throw bad("index offset " + std::to_string(out.index_offset) + " inconsistent with the file size " +
                  std::to_string(size) + " (truncated or corrupt footer)");

    std::vector<unsigned char> idx(static_cast<std::size_t>(in.brick_count * kPointStoreEntryBytes));
    read(idx.data(), idx.size(), out.index_offset);
    if (!crc_matches(out.index_crc, point_store_crc32(idx.data(), idx.size())))
        throw bad("point store index checksum mismatch (corrupt index or footer)");
    const PointStoreGrid grid = out.grid();
    out.bricks.resize(static_cast<std::size_t>(in.brick_count));
    std::uint64_t at = kPointStoreHeaderBytes, first = 0;
    for (std::size_t i = 0; i < out.bricks.size(); ++i) {
        const unsigned char* p = idx.data() + i * kPointStoreEntryBytes;
        PointBrickEntry& e = out.bricks[i];
        e.key = get_le<std::uint64_t>(p);
        e.level = get_le<std::uint32_t>(p + 8);
        e.crc = get_le<std::uint32_t>(p + 12);
        e.offset = get_le<std::uint64_t>(p + 16);
        e.stored_bytes = get_le<std::uint64_t>(p + 24);
        e.count = get_le<std::uint64_t>(p + 32);
        e.first = get_le<std::uint64_t>(p + 40);
        for (int a = 0; a < 3; ++a) {
            e.lo[a] = get_le<double>(p + 48 + 8 * a);
            e.hi[a] = get_le<double>(p + 72 + 8 * a);
        }
        e.vmin = get_le<double>(p + 96);
        e.vmax = get_le<double>(p + 104);
        const std::string where = "index entry " + std::to_string(i) + ": ";
        if (e.level > in.level || e.key >= (std::uint64_t{1} << (3 * e.level)))
            throw bad(where + "cell level " + std::to_string(e.level) + " key " + std::to_string(e.key) + " out of range");
        if (e.offset != at || e.stored_bytes > out.index_offset - e.offset)
            throw bad(where + "frame offset " + std::to_string(e.offset) + " / size " + std::to_string(e.stored_bytes) +
                      " out of range of the file layout");
        if (e.count < 1 || e.count > in.brick_points)
            throw bad(where + "count " + std::to_string(e.count) + " outside 1.." + std::to_string(in.brick_points));
        if (e.first != first || e.count > in.points - first)
            throw bad(where + "first point " + std::to_string(e.first) + " / count " + std::to_string(e.count) +
                      " do not follow the previous bricks (header: " + std::to_string(in.points) + " points)");
        if (!finite3(e.lo) || !finite3(e.hi) || !std::isfinite(e.vmin) || !std::isfinite(e.vmax))
            throw bad(where + "non-finite bounds or value range");
        for (int a = 0; a < 3; ++a)
            if (!(e.lo[a] <= e.hi[a]) || e.lo[a] < in.lo[a] || e.hi[a] > in.hi[a])
                throw bad(where + "bounds outside the store's");
        if (!(e.vmin <= e.vmax) || e.vmin < in.value_min || e.vmax > in.value_max)
            throw bad(where + "value range outside the store's");
        if (i > 0) {
            const PointBrickEntry& q = out.bricks[i - 1];
            const bool same_leaf = e.level == in.level && q.level == in.level && e.key == q.key;
            if (!same_leaf && grid.cell_begin(e.level, e.key) < grid.cell_end(q.level, q.key))
                throw bad(where + "cell not after the previous brick's (index not in Morton order)");
        }
        at += e.stored_bytes;
        first += e.count;
    }
    if (at != out.index_offset) throw bad("bytes between the last brick and the index");
    if (first != in.points)
        throw bad("the bricks hold " + std::to_string(first) + " points, the header says " + std::to_string(in.points));
    return out;
}

std::string point_brick_where(const PointStoreLayout& layout, std::size_t i) {
    const PointBrickEntry& e = layout.bricks[i];
    return "brick " + std::to_string(i) + " (cell level " + std::to_string(e.level) + " key " + std::to_string(e.key) +
           ", points [" + std::to_string(e.first) + "," + std::to_string(e.first + e.count) + "))";
}

void decode_point_brick(const PointStoreLayout& layout, std::size_t i, std::span<const unsigned char> frame,
                        std::vector<double>& out, const std::string& name) {
    const PointBrickEntry& e = layout.bricks[i];
    auto fail = [&](const std::string& what) { return FormatError(name + ": " + point_brick_where(layout, i) + ": " + what); };
    if (frame.size() != e.stored_bytes) throw fail("truncated (the file ends inside the brick)");
    if (!crc_matches(e.crc, point_store_crc32(frame.data(), frame.size()))) throw fail("checksum mismatch (corrupt data)");
    const std::uint64_t raw = e.count * kPointStoreRecordBytes;  // count <= 2^20: no overflow
    const unsigned long long content = ZSTD_getFrameContentSize(frame.data(), frame.size());
    if (content != raw)
        throw fail(content == ZSTD_CONTENTSIZE_ERROR || content == ZSTD_CONTENTSIZE_UNKNOWN
                       ? std::string("not a complete zstd frame")
                       : "frame holds " + std::to_string(content) + " bytes, the index says " + std::to_string(e.count) +
                             " points (" + std::to_string(raw) + " bytes)");
    out.resize(static_cast<std::size_t>(e.count) * 4);
    const std::size_t n = ZSTD_decompress(out.data(), raw, frame.data(), frame.size());
    if (ZSTD_isError(n)) throw fail(std::string("corrupt zstd frame (") + ZSTD_getErrorName(n) + ")");
    if (n != raw) throw fail("decompressed to " + std::to_string(n) + " bytes, expected " + std::to_string(raw));
    for (std::size_t k = 0; k < e.count; ++k) {
        const double* p = &out[4 * k];
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]) || !std::isfinite(p[3]))
            throw fail("point " + std::to_string(e.first + k) + " is not finite");
        for (int a = 0; a < 3; ++a)
            if (p[a] < e.lo[a] || p[a] > e.hi[a]) throw fail("point " + std::to_string(e.first + k) + " outside the brick's bounds");
        if (p[3] < e.vmin || p[3] > e.vmax) throw fail("point " + std::to_string(e.first + k) + " value outside the brick's range");
    }
}

std::string check_point_brick(const PointStoreLayout& layout, std::size_t i, std::span<const double> pts) {
    const PointBrickEntry& e = layout.bricks[i];
    const PointStoreGrid grid = layout.grid();
    const std::uint64_t b = grid.cell_begin(e.level, e.key), end = grid.cell_end(e.level, e.key);
    std::array<double, 3> lo{pts[0], pts[1], pts[2]}, hi = lo;
    double vmin = pts[3], vmax = pts[3];
    std::uint64_t prev = 0;
    for (std::size_t k = 0; k < pts.size() / 4; ++k) {
        const double* p = &pts[4 * k];
        const std::uint64_t key = grid.key(p[0], p[1], p[2]);
        if (key < b || key >= end)
            return "point " + std::to_string(e.first + k) + " lies outside the brick's cell (Morton key " + std::to_string(key) + ")";
        if (k > 0 && key < prev) return "point " + std::to_string(e.first + k) + " is not in Morton order";
        if (e.level == layout.info.level && key != e.key) return "point " + std::to_string(e.first + k) + " outside its grid cell";
        prev = key;
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], p[a]);
            hi[a] = std::max(hi[a], p[a]);
        }
        vmin = std::min(vmin, p[3]);
        vmax = std::max(vmax, p[3]);
    }
    if (lo != e.lo || hi != e.hi) return "bounds differ from its points'";
    if (vmin != e.vmin || vmax != e.vmax) return "value range differs from its points'";
    return "";
}

PointStoreLayout parse_point_store_bytes(std::span<const unsigned char> bytes, const std::string& name) {
    const PointStoreReadAt read = [&](void* dst, std::size_t n, std::uint64_t off) {
        if (off > bytes.size() || n > bytes.size() - off) throw FormatError(name + ": truncated point store");
        std::memcpy(dst, bytes.data() + off, n);
    };
    PointStoreLayout layout = decode_point_store_layout(read, bytes.size(), name);
    std::vector<double> pts;
    for (std::size_t i = 0; i < layout.bricks.size(); ++i) {
        const PointBrickEntry& e = layout.bricks[i];
        decode_point_brick(layout, i, bytes.subspan(static_cast<std::size_t>(e.offset), static_cast<std::size_t>(e.stored_bytes)),
                           pts, name);
        const std::string why = check_point_brick(layout, i, pts);
        if (!why.empty()) throw FormatError(name + ": " + point_brick_where(layout, i) + ": " + why);
    }
    return layout;
}

}  // namespace meshless
