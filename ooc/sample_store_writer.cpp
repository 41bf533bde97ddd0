#include "ooc/sample_store_writer.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "formats/atomic_file.hpp"
#include "formats/terminal_safe.hpp"
#include "kernels/errors.hpp"
#include "ooc/brick_store_identity.hpp"
#include "ooc/row_key_codec.hpp"
#include "ooc/sample_store_format.hpp"
#include "ooc/span_space_levels.hpp"

namespace meshless {

namespace {

namespace fs = std::filesystem;

void pwrite_all(int fd, const void* data, std::size_t n, std::uint64_t offset, const std::string& path) {
    const auto* p = static_cast<const char*>(data);
    while (n > 0) {
        const ssize_t w = ::pwrite(fd, p, n, static_cast<off_t>(offset));
        if (w < 0) {
            if (errno == EINTR) continue;
            throw IoError(path + ": write failed (" + std::strerror(errno) + ")");
        }
        p += w;
        n -= static_cast<std::size_t>(w);
        offset += static_cast<std::uint64_t>(w);
    }
}

struct CellCounts {
    std::uint64_t cells = 0, constant = 0, nonfinite = 0;
};

/// Calls f(bucket, key) for every indexed cell of brick n (row-major), see the key definition in
/// ooc/sample_store_format.hpp.
template <class T, class F>
void visit_brick_cells(const T* d, const GridSpec& g, std::uint64_t key0, const SpanSpaceLevels& L, CellCounts& c, F&& f) {
    const std::int64_t nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    const std::int64_t sy = nx, sz = nx * ny;
    for (std::int64_t k = 0; k + 1 < nz; ++k)
        for (std::int64_t j = 0; j + 1 < ny; ++j) {
            const T* p00 = d + j * sy + k * sz;
            const T* p10 = p00 + sy;
            const T* p01 = p00 + sz;
            const T* p11 = p01 + sy;
            const std::uint64_t key = key0 + static_cast<std::uint64_t>(j + (ny - 1) * k);
            for (std::int64_t i = 0; i + 1 < nx; ++i) {
                const T v[8] = {p00[i], p00[i + 1], p10[i], p10[i + 1], p01[i], p01[i + 1], p11[i], p11[i + 1]};
                if constexpr (std::is_floating_point_v<T>) {
                    bool finite = true;
                    for (T x : v) finite = finite && std::isfinite(x);
                    if (!finite) {
                        ++c.nonfinite;
                        continue;
                    }
                }
                T lo = v[0], hi = v[0];
                for (int a = 1; a < 8; ++a) {
                    lo = std::min(lo, v[a]);
                    hi = std::max(hi, v[a]);
                }
                if (lo == hi) {
                    ++c.constant;
                    continue;
                }
                ++c.cells;
                f(static_cast<std::uint32_t>(L.bucket(L(static_cast<double>(lo)), L(static_cast<double>(hi)))), key);
            }
        }
}

/// One pass over every brick (Morton order); constant and all-NaN bricks are counted unread.
/// progress (optional) gets the fraction of bricks visited, mapped into [at, at + span].
template <class F>
CellCounts visit_all_cells(const BrickStore& store, const SpanSpaceLevels& L, F&& f,
                           const std::function<void(double)>& progress = {}, double at = 0, double span = 1) {
    CellCounts c;
    const BrickStoreInfo& bi = store.info();
    const std::uint64_t B = bi.brick_edge;
    std::vector<std::byte> buf;
    const std::size_t nb = store.bricks().size();
    for (std::size_t n = 0; n < nb; ++n) {
        if (progress) progress(at + span * static_cast<double>(n) / static_cast<double>(nb));
        const BrickEntry& e = store.bricks()[n];
        const GridSpec g = store.brick_grid(n);
        const std::uint64_t cells = static_cast<std::uint64_t>(std::max<std::int64_t>(0, g.dims[0] - 1)) *
                                    static_cast<std::uint64_t>(std::max<std::int64_t>(0, g.dims[1] - 1)) *
                                    static_cast<std::uint64_t>(std::max<std::int64_t>(0, g.dims[2] - 1));
        if (e.vmin == e.vmax && bi.type != SampleType::f32) {  // a float brick with equal finite values may hold NaN
            c.constant += cells;
            continue;
        }
        if (std::isnan(e.vmin) && std::isnan(e.vmax)) {
            c.nonfinite += cells;
            continue;
        }
        store.read_brick(n, buf);
        const VolumeView v{buf.data(), bi.type, g};
        const std::uint64_t key0 = static_cast<std::uint64_t>(n) * B * B;
        visit_samples(v, [&](auto* p) { visit_brick_cells(p, g, key0, L, c, f); });
    }
    return c;
}

std::string recorded_path(const std::string& mlb, const std::string& mls) {
    std::error_code ec;
    const fs::path a = fs::weakly_canonical(fs::absolute(mlb), ec);
    const fs::path dir = fs::weakly_canonical(fs::absolute(mls), ec).parent_path();
    fs::path rel = a.lexically_relative(dir);
    std::string s = rel.empty() ? a.string() : rel.string();
    if (s.size() >= kSampleStorePathBytes) s = a.string();
    if (s.size() >= kSampleStorePathBytes)
        throw InvalidArgument(mlb + ": path too long to record in a sample store (" + std::to_string(s.size()) +
                              " bytes; at most " + std::to_string(kSampleStorePathBytes - 1) + ")");
    return s;
}

}  // namespace

SampleStoreBuildStats write_sample_store(const BrickStore& store, const std::string& path, const SampleStoreParams& params) {
    if (path == "-") throw InvalidArgument("-: a sample store must be written to a file, not standard output");
    if (params.levels < 1 || params.levels > kMaxSpanSpaceLevels)
        throw InvalidArgument("sample store: levels must be in 1.." + std::to_string(kMaxSpanSpaceLevels) + ", got " +
                              std::to_string(params.levels));
    const BrickStoreInfo& bi = store.info();
    SampleStoreInfo info;
    info.grid = bi.grid;
    info.type = bi.type;
    info.brick_edge = bi.brick_edge;
    info.value_lo = std::isfinite(bi.value_min) ? bi.value_min : 0.0;
    info.value_hi = std::isfinite(bi.value_max) ? bi.value_max : 0.0;
    info.mlb = brick_store_identity(store.path());
    info.mlb_path = recorded_path(store.path(), path);
    const SpanSpaceLevels L = SpanSpaceLevels::make(info.type, info.value_lo, info.value_hi, params.levels);
    info.levels = L.count;
    info.exact_levels = L.exact;

    // pass 1: keys and key bytes per bucket (a cell row is listed once per bucket)
    struct Acc {
        std::uint64_t count = 0, bytes = 0, last = 0, cursor = 0;  ///< last: previous key + 1 (0: none)
        std::uint32_t crc = 0;
    };
    std::vector<Acc> acc(L.buckets());
    const CellCounts c1 = visit_all_cells(store, L, [&](std::uint32_t b, std::uint64_t key) {
        Acc& x = acc[b];
        if (x.last == key + 1) return;
        x.bytes += varint_bytes(key + 1 - x.last);
        ++x.count;
        x.last = key + 1;
    }, params.progress, 0.0, 0.5);
    std::vector<SampleBucket> table;
    for (std::uint32_t a = 0; a < L.count; ++a)
        for (std::uint32_t b = a; b < L.count; ++b) {
            Acc& x = acc[L.bucket(a, b)];
            x.last = 0;
            if (x.count == 0) continue;
            SampleBucket e;
            e.a = static_cast<std::uint16_t>(a);
            e.b = static_cast<std::uint16_t>(b);
            e.offset = info.key_bytes;
            e.bytes = x.bytes;
            e.count = x.count;
            x.cursor = info.key_bytes;
            info.key_bytes += x.bytes;
            info.key_count += x.count;
            table.push_back(e);
        }
    info.bucket_count = table.size();
    info.cells = c1.cells;
    info.constant_cells = c1.constant;
    info.nonfinite_cells = c1.nonfinite;

    AtomicFile file(path, Durability::fsync);
    const auto header = encode_sample_store_header(info);
    file.write(header.data(), header.size());
    if (std::fflush(file.handle()) != 0) throw IoError(path + ": write failed (" + std::strerror(errno) + ")");
    const int fd = ::fileno(file.handle());

    // pass 2: encode; pending (bucket, gap) pairs are sorted by bucket (stable: keys stay in
    // order) and each bucket's run is written at its cursor
    const std::size_t cap = std::max<std::size_t>(params.buffer_keys, 1);
    std::vector<std::pair<std::uint32_t, std::uint64_t>> pending;
    pending.reserve(std::min<std::size_t>(cap, 1u << 16));
    std::vector<unsigned char> bytes;
    auto flush = [&]() {
        std::stable_sort(pending.begin(), pending.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
        for (std::size_t i = 0; i < pending.size();) {
            std::size_t j = i;
            bytes.clear();
            while (j < pending.size() && pending[j].first == pending[i].first) put_varint(bytes, pending[j++].second);
            Acc& x = acc[pending[i].first];
            pwrite_all(fd, bytes.data(), bytes.size(), kSampleStoreHeaderBytes + x.cursor, path);
            x.crc = sample_store_crc32(x.crc, bytes.data(), bytes.size());
            x.cursor += bytes.size();
            i = j;
        }
        pending.clear();
    };
    const CellCounts c2 = visit_all_cells(store, L, [&](std::uint32_t b, std::uint64_t key) {
        Acc& x = acc[b];
        if (x.last == key + 1) return;
        pending.emplace_back(b, key + 1 - x.last);
        x.last = key + 1;
        if (pending.size() >= cap) flush();
    }, params.progress, 0.5, 0.5);
    flush();
    if (c2.cells != c1.cells) throw std::logic_error(path + ": sample store writer: the two passes disagree");

    std::vector<unsigned char> tb(table.size() * kSampleStoreBucketBytes);
    for (std::size_t i = 0; i < table.size(); ++i) {
        const Acc& x = acc[L.bucket(table[i].a, table[i].b)];
        if (x.cursor != table[i].offset + table[i].bytes) throw std::logic_error(path + ": sample store writer: bucket overrun");
        table[i].crc = x.crc;
        encode_sample_store_bucket(table[i], tb.data() + i * kSampleStoreBucketBytes);
    }
    const std::uint64_t table_offset = kSampleStoreHeaderBytes + info.key_bytes;
    pwrite_all(fd, tb.data(), tb.size(), table_offset, path);
    const auto footer = encode_sample_store_footer(table_offset, table.size(), sample_store_crc32(0, tb.data(), tb.size()));
    pwrite_all(fd, footer.data(), footer.size(), table_offset + tb.size(), path);
    file.commit();

    SampleStoreBuildStats out;
    out.cells = info.cells;
    out.keys = info.key_count;
    out.buckets = info.bucket_count;
    out.constant_cells = info.constant_cells;
    out.nonfinite_cells = info.nonfinite_cells;
    out.file_bytes = table_offset + tb.size() + footer.size();
    out.levels = L.count;
    out.exact_levels = L.exact;
    return out;
}

std::string sample_store_stats_line(const SampleStoreBuildStats& st, const std::string& source) {
    char tail[320];
    std::snprintf(tail, sizeof tail,
                  ": %llu non-constant cells as %llu cell-row keys in %llu span-space buckets (%u levels%s), %llu constant and "
                  "%llu NaN/Inf cells skipped, %.1f MiB",
                  static_cast<unsigned long long>(st.cells), static_cast<unsigned long long>(st.keys),
                  static_cast<unsigned long long>(st.buckets), st.levels, st.exact_levels ? ", exact" : "",
                  static_cast<unsigned long long>(st.constant_cells), static_cast<unsigned long long>(st.nonfinite_cells),
                  static_cast<double>(st.file_bytes) / 1048576.0);
    return "generate --all: " + terminal_safe(source) + tail;
}

}  // namespace meshless
