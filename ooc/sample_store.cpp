#include "ooc/sample_store.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cstddef>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"
#include "kernels/morton.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_store.hpp"

namespace meshless {

namespace {

constexpr char kMagic[8] = {'\x89', 'M', 'L', 'A', '\r', '\n', '\x1a', '\n'};
constexpr char kPointStreamMagic[8] = {'\x89', 'M', 'L', 'S', '\r', '\n', '\x1a', '\n'};
constexpr char kEndMagic[8] = {'M', 'L', 'A', 'E', 'N', 'D', '\0', '\0'};
constexpr std::size_t kSampleBytes = sizeof(CellIntervalSample);
constexpr std::uint32_t kMaxLevels = 1024;
constexpr std::size_t kSourceOffset = 156, kSourceBytes = 96;
constexpr std::uint64_t kReadChunk = 4096;  ///< samples per positional read of a query
// query() copies pos, grad, value (28 contiguous bytes) from the stored sample into the record
static_assert(offsetof(CellIntervalSample, value) == 24 && offsetof(SampleRecord, grad) == 12 &&
              offsetof(SampleRecord, value) == 24 && offsetof(SampleRecord, radius) == 28);

std::uint32_t crc_update(std::uint32_t crc, const void* p, std::size_t n) {
    const auto* b = static_cast<const Bytef*>(p);
    while (n > 0) {  // zlib takes uInt lengths
        const uInt step = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
        crc = static_cast<std::uint32_t>(crc32(crc, b, step));
        b += step;
        n -= step;
    }
    return crc;
}

template <class T>
void put(unsigned char* p, T v) {
    std::memcpy(p, &v, sizeof v);  // little-endian host (x86), as everywhere in meshless
}
template <class T>
T get(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

/// The span-space quantisation shared by writer and reader (monotone in v).
struct Levels {
    double lo = 0, scale = 1;
    std::uint32_t count = 1;
    bool exact = false;

    std::uint32_t operator()(double v) const {
        const double x = (v - lo) * scale;
        if (!(x > 0)) return 0;
        if (x >= static_cast<double>(count - 1)) return count - 1;
        return static_cast<std::uint32_t>(x);
    }
    /// Dense triangular index of bucket (a, b), a <= b, in table order (a-major, then b).
    std::size_t bucket(std::uint32_t a, std::uint32_t b) const {
        const std::size_t L = count;
        return static_cast<std::size_t>(a) * L - static_cast<std::size_t>(a) * (a - 1) / 2 + (b - a);
    }
    std::size_t buckets() const { return static_cast<std::size_t>(count) * (count + 1) / 2; }
};

Levels make_levels(SampleType t, double lo, double hi, std::uint32_t levels) {
    Levels L;
    L.lo = lo;
    if (!(hi > lo)) return L;  // constant (or empty) volume: one level, no samples anyway
    if (t != SampleType::f32 && hi - lo + 1 <= static_cast<double>(levels)) {
        L.exact = true;
        L.count = static_cast<std::uint32_t>(hi - lo + 1);
        L.scale = 1.0;
        return L;
    }
    L.count = levels;
    L.scale = static_cast<double>(levels) / (hi - lo);
    return L;
}

double scale_of(const SampleStoreInfo& info) {
    if (info.exact_levels || !(info.value_hi > info.value_lo)) return 1.0;
    return static_cast<double>(info.levels) / (info.value_hi - info.value_lo);
}

// ---------------------------------------------------------------------------------------------
// Writer

struct BucketAcc {
    std::uint64_t count = 0, cursor = 0;
    std::uint32_t crc = 0;
    float min_vmin = std::numeric_limits<float>::infinity(), max_vmin = -std::numeric_limits<float>::infinity();
    float min_vmax = std::numeric_limits<float>::infinity(), max_vmax = -std::numeric_limits<float>::infinity();
};

/// One brick's samples, in Morton order of bricks; called with a callback per brick.
using BrickVisitor = std::function<void(const std::function<void(const std::vector<CellIntervalSample>&)>&,
                                        CellIntervalStats&)>;

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

SampleStoreBuildStats write_store(const std::string& path, SampleStoreInfo info, const BrickVisitor& visit,
                                  const SampleStoreParams& params) {
    if (path == "-") throw UsageError("-: a sample store must be written to a file, not standard output");
    if (params.levels < 1 || params.levels > kMaxLevels)
        throw UsageError("sample store: levels must be in 1.." + std::to_string(kMaxLevels) + ", got " +
                         std::to_string(params.levels));
    const Levels L = make_levels(info.type, info.value_lo, info.value_hi, params.levels);
    info.levels = L.count;
    info.exact_levels = L.exact;

    // pass 1: count samples per bucket
    std::vector<BucketAcc> acc(L.buckets());
    CellIntervalStats st1;
    visit(
        [&](const std::vector<CellIntervalSample>& ss) {
            for (const CellIntervalSample& s : ss) {
                BucketAcc& b = acc[L.bucket(L(s.vmin), L(s.vmax))];
                ++b.count;
                b.min_vmin = std::min(b.min_vmin, s.vmin);
                b.max_vmin = std::max(b.max_vmin, s.vmin);
                b.min_vmax = std::min(b.min_vmax, s.vmax);
                b.max_vmax = std::max(b.max_vmax, s.vmax);
            }
        },
        st1);
    std::uint64_t total = 0, nonempty = 0;
    for (BucketAcc& b : acc) {
        b.cursor = total;
        total += b.count;
        nonempty += b.count > 0;
    }
    info.sample_count = total;
    info.bucket_count = nonempty;
    info.constant_cells = static_cast<std::uint64_t>(st1.constant_cells);
    info.nonfinite_cells = static_cast<std::uint64_t>(st1.nonfinite_cells);

    // header
    unsigned char h[kSampleStoreHeaderBytes] = {};
    std::memcpy(h, kMagic, 8);
    put<std::uint32_t>(h + 8, kSampleStoreVersion);
    put<std::uint32_t>(h + 12, kSampleStoreHeaderBytes);
    for (int a = 0; a < 3; ++a) {
        put<std::int64_t>(h + 16 + 8 * a, info.grid.dims[a]);
        put<double>(h + 40 + 8 * a, info.grid.origin[a]);
        put<double>(h + 64 + 8 * a, info.grid.spacing[a]);
    }
    put<std::uint32_t>(h + 88, static_cast<std::uint32_t>(info.type));
    put<std::uint32_t>(h + 92, kSampleBytes);
    put<double>(h + 96, info.value_lo);
    put<double>(h + 104, info.value_hi);
    put<std::uint32_t>(h + 112, info.levels);
    put<std::uint32_t>(h + 116, info.exact_levels ? 1u : 0u);
    put<std::uint64_t>(h + 120, info.sample_count);
    put<std::uint64_t>(h + 128, info.bucket_count);
    put<std::uint64_t>(h + 136, info.constant_cells);
    put<std::uint64_t>(h + 144, info.nonfinite_cells);
    put<std::uint32_t>(h + 152, info.brick_edge);
    std::memcpy(h + kSourceOffset, info.source.data(), std::min(info.source.size(), kSourceBytes - 1));
    put<std::uint32_t>(h + 252, crc_update(0, h, 252));

    AtomicFile file(path);
    file.write(h, sizeof h);
    if (std::fflush(file.handle()) != 0) throw IoError(path + ": write failed (" + std::strerror(errno) + ")");
    const int fd = ::fileno(file.handle());

    // pass 2: recompute, gather up to buffer_samples, write each bucket's run at its cursor
    const std::size_t cap = std::max<std::size_t>(params.buffer_samples, 1);
    std::vector<CellIntervalSample> buf, sorted;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> keys;  // (bucket, index in buf)
    buf.reserve(std::min<std::size_t>(cap, 1u << 16));
    auto flush = [&]() {
        if (buf.empty()) return;
        keys.resize(buf.size());
        for (std::size_t i = 0; i < buf.size(); ++i)
            keys[i] = {static_cast<std::uint32_t>(L.bucket(L(buf[i].vmin), L(buf[i].vmax))), static_cast<std::uint32_t>(i)};
        std::sort(keys.begin(), keys.end());  // by bucket, then generation order
        sorted.resize(buf.size());
        for (std::size_t i = 0; i < keys.size(); ++i) sorted[i] = buf[keys[i].second];
        for (std::size_t i = 0; i < keys.size();) {
            std::size_t j = i;
            while (j < keys.size() && keys[j].first == keys[i].first) ++j;
            BucketAcc& b = acc[keys[i].first];
            const std::size_t bytes = (j - i) * kSampleBytes;
            pwrite_all(fd, &sorted[i], bytes, kSampleStoreHeaderBytes + b.cursor * kSampleBytes, path);
            b.crc = crc_update(b.crc, &sorted[i], bytes);
            b.cursor += j - i;
            i = j;
        }
        buf.clear();
    };
    CellIntervalStats st2;
    visit(
        [&](const std::vector<CellIntervalSample>& ss) {
            for (std::size_t i = 0; i < ss.size();) {
                const std::size_t n = std::min(ss.size() - i, cap - buf.size());
                buf.insert(buf.end(), ss.begin() + static_cast<std::ptrdiff_t>(i), ss.begin() + static_cast<std::ptrdiff_t>(i + n));
                i += n;
                if (buf.size() >= cap) flush();
            }
        },
        st2);
    flush();
    if (st2.samples != st1.samples) throw std::logic_error(path + ": sample store writer: the two passes disagree");

    // bucket table + footer
    std::vector<unsigned char> table(nonempty * kSampleStoreBucketBytes);
    std::uint64_t first = 0;
    std::size_t t = 0;
    for (std::uint32_t a = 0; a < L.count; ++a) {
        for (std::uint32_t b = a; b < L.count; ++b) {
            const BucketAcc& x = acc[L.bucket(a, b)];
            if (x.count == 0) continue;
            if (x.cursor != first + x.count) throw std::logic_error(path + ": sample store writer: bucket overrun");
            unsigned char* e = table.data() + t * kSampleStoreBucketBytes;
            put<std::uint16_t>(e, static_cast<std::uint16_t>(a));
            put<std::uint16_t>(e + 2, static_cast<std::uint16_t>(b));
            put<std::uint32_t>(e + 4, x.crc);
            put<std::uint64_t>(e + 8, first);
            put<std::uint64_t>(e + 16, x.count);
            put<float>(e + 24, x.min_vmin);
            put<float>(e + 28, x.max_vmin);
            put<float>(e + 32, x.min_vmax);
            put<float>(e + 36, x.max_vmax);
            first += x.count;
            ++t;
        }
    }
    const std::uint64_t table_offset = kSampleStoreHeaderBytes + total * kSampleBytes;
    pwrite_all(fd, table.data(), table.size(), table_offset, path);
    unsigned char f[kSampleStoreFooterBytes] = {};
    put<std::uint64_t>(f, table_offset);
    put<std::uint64_t>(f + 8, nonempty);
    put<std::uint32_t>(f + 16, crc_update(0, table.data(), table.size()));
    put<std::uint32_t>(f + 20, kSampleStoreVersion);
    std::memcpy(f + 24, kEndMagic, 8);
    pwrite_all(fd, f, sizeof f, table_offset + table.size(), path);
    file.commit();

    SampleStoreBuildStats out;
    out.samples = total;
    out.buckets = nonempty;
    out.constant_cells = info.constant_cells;
    out.nonfinite_cells = info.nonfinite_cells;
    out.file_bytes = table_offset + table.size() + sizeof f;
    out.levels = L.count;
    out.exact_levels = L.exact;
    return out;
}

std::string file_name(const std::string& source_name) {
    return std::filesystem::path(source_name).filename().string();
}

std::array<double, 2> finite_range(const VolumeView& v) {
    return visit_samples(v, [&](auto* p) {
        using T = std::remove_const_t<std::remove_pointer_t<decltype(p)>>;
        const std::int64_t n = v.grid.voxel_count();
        bool any = false;
        T lo{}, hi{};
        for (std::int64_t i = 0; i < n; ++i) {
            const T x = p[i];
            if constexpr (std::is_floating_point_v<T>)
                if (!std::isfinite(x)) continue;
            if (!any) {
                lo = hi = x;
                any = true;
            } else {
                lo = std::min(lo, x);
                hi = std::max(hi, x);
            }
        }
        return any ? std::array<double, 2>{static_cast<double>(lo), static_cast<double>(hi)} : std::array<double, 2>{0.0, 0.0};
    });
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Writers

SampleStoreBuildStats write_sample_store_from_volume(const VolumeView& v, const std::string& path,
                                                     const std::string& source_name, const SampleStoreParams& params) {
    if (params.brick_edge < 1) throw UsageError("sample store: brick edge must be >= 1");
    SampleStoreInfo info;
    info.grid = v.grid;
    info.type = v.type;
    const auto r = finite_range(v);
    info.value_lo = r[0];
    info.value_hi = r[1];
    info.brick_edge = params.brick_edge;
    info.source = file_name(source_name);
    // virtual bricks of B cells, Morton order (the order of ooc/brick_store.hpp)
    const std::int64_t B = params.brick_edge;
    const CellBox all = all_cells(v.grid);
    std::array<std::int64_t, 3> nb{};
    for (int a = 0; a < 3; ++a) nb[a] = all.count() == 0 ? 0 : (all.hi[a] + B - 1) / B;
    std::vector<std::pair<std::uint64_t, std::array<std::int64_t, 3>>> bricks;
    bricks.reserve(static_cast<std::size_t>(nb[0] * nb[1] * nb[2]));
    for (std::int64_t z = 0; z < nb[2]; ++z)
        for (std::int64_t y = 0; y < nb[1]; ++y)
            for (std::int64_t x = 0; x < nb[0]; ++x)
                bricks.push_back({morton_encode(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y),
                                                static_cast<std::uint32_t>(z)),
                                  {x, y, z}});
    std::sort(bricks.begin(), bricks.end());
    const std::array<std::int64_t, 3> zero{0, 0, 0};
    std::vector<CellIntervalSample> samples;
    BrickVisitor visit = [&](const std::function<void(const std::vector<CellIntervalSample>&)>& f, CellIntervalStats& st) {
        for (const auto& [key, c] : bricks) {
            CellBox box;
            for (int a = 0; a < 3; ++a) {
                box.lo[a] = c[a] * B;
                box.hi[a] = std::min(c[a] * B + B, all.hi[a]);
            }
            samples.clear();
            sample_cell_intervals(v, box, zero, v.grid.origin, samples, st);
            f(samples);
        }
    };
    return write_store(path, info, visit, params);
}

SampleStoreBuildStats write_sample_store_from_brick_store(const BrickStore& store, BrickCache& cache,
                                                          const std::string& path, const std::string& source_name,
                                                          const SampleStoreParams& params) {
    const BrickStoreInfo& bi = store.info();
    SampleStoreInfo info;
    info.grid = bi.grid;
    info.type = bi.type;
    info.value_lo = std::isfinite(bi.value_min) ? bi.value_min : 0.0;
    info.value_hi = std::isfinite(bi.value_max) ? bi.value_max : 0.0;
    info.brick_edge = bi.brick_edge;
    info.source = file_name(source_name);
    std::vector<CellIntervalSample> samples;
    BrickVisitor visit = [&](const std::function<void(const std::vector<CellIntervalSample>&)>& f, CellIntervalStats& st) {
        const auto& entries = store.bricks();
        for (std::size_t i = 0; i < entries.size(); ++i) {
            const BrickEntry& e = entries[i];
            const CellBox box = all_cells(store.brick_grid(i));
            // a brick whose samples are all equal (integer types) or all non-finite has no
            // non-constant finite cell (a float brick with equal finite samples may hold NaN cells)
            if (e.vmin == e.vmax && bi.type != SampleType::f32) {
                st.constant_cells += box.count();
                continue;
            }
            if (std::isnan(e.vmin) && std::isnan(e.vmax)) {
                st.nonfinite_cells += box.count();
                continue;
            }
            const auto bytes = cache.get(i);
            const VolumeView view = cache.view(i, *bytes);
            samples.clear();
            sample_cell_intervals(view, box, store.brick_first_voxel(i), bi.grid.origin, samples, st);
            f(samples);
        }
    };
    return write_store(path, info, visit, params);
}

bool is_sample_store(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    char m[8] = {};
    const bool ok = ::pread(fd, m, 8, 0) == 8 && std::memcmp(m, kMagic, 8) == 0;
    ::close(fd);
    return ok;
}

// ---------------------------------------------------------------------------------------------
// Reader

namespace {

void pread_all(int fd, void* dst, std::size_t n, std::uint64_t offset, const std::string& path) {
    auto* p = static_cast<char*>(dst);
    while (n > 0) {
        const ssize_t r = ::pread(fd, p, n, static_cast<off_t>(offset));
        if (r < 0) {
            if (errno == EINTR) continue;
            throw IoError(path + ": read failed (" + std::strerror(errno) + ")");
        }
        if (r == 0) throw FormatError(path + ": truncated sample store (unexpected end of file at byte " + std::to_string(offset) + ")");
        p += r;
        n -= static_cast<std::size_t>(r);
        offset += static_cast<std::uint64_t>(r);
    }
}

}  // namespace

SampleStore::~SampleStore() {
    if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<SampleStore> SampleStore::open(const std::string& path) {
    std::unique_ptr<SampleStore> s(new SampleStore());  // private constructor
    s->path_ = path;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a sample store");
    s->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (s->fd_ < 0) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    struct stat sb {};
    if (::fstat(s->fd_, &sb) != 0) throw IoError(path + ": cannot stat (" + std::strerror(errno) + ")");
    const std::uint64_t size = static_cast<std::uint64_t>(sb.st_size);

    unsigned char h[kSampleStoreHeaderBytes];
    if (size >= 8) {
        char m[8];
        pread_all(s->fd_, m, 8, 0, path);
        if (std::memcmp(m, kPointStreamMagic, 8) == 0)
            throw FormatError(path + ": is a meshless point stream, not a sample store (make one with 'meshless generate VOLUME --all -o vol.mls')");
        if (std::memcmp(m, kMagic, 8) != 0) throw FormatError(path + ": not a meshless sample store (bad magic)");
    } else {
        throw FormatError(path + ": not a meshless sample store (file of " + std::to_string(size) + " bytes)");
    }
    if (size < kSampleStoreHeaderBytes + kSampleStoreFooterBytes)
        throw FormatError(path + ": truncated sample store (" + std::to_string(size) + " bytes, header and footer need " +
                          std::to_string(kSampleStoreHeaderBytes + kSampleStoreFooterBytes) + ")");
    pread_all(s->fd_, h, sizeof h, 0, path);
    const std::uint32_t version = get<std::uint32_t>(h + 8);
    if (version != kSampleStoreVersion)
        throw FormatError(path + ": unsupported sample store version " + std::to_string(version) + " (this build reads " +
                          std::to_string(kSampleStoreVersion) + ")");
    if (get<std::uint32_t>(h + 252) != crc_update(0, h, 252)) throw FormatError(path + ": sample store header checksum mismatch (corrupt header)");
    if (get<std::uint32_t>(h + 12) != kSampleStoreHeaderBytes || get<std::uint32_t>(h + 92) != kSampleBytes)
        throw FormatError(path + ": unexpected header or sample size in sample store header");

    SampleStoreInfo& info = s->info_;
    for (int a = 0; a < 3; ++a) {
        info.grid.dims[a] = get<std::int64_t>(h + 16 + 8 * a);
        info.grid.origin[a] = get<double>(h + 40 + 8 * a);
        info.grid.spacing[a] = get<double>(h + 64 + 8 * a);
        if (info.grid.dims[a] < 1 || !(info.grid.spacing[a] > 0) || !std::isfinite(info.grid.origin[a]))
            throw FormatError(path + ": invalid grid in sample store header");
    }
    const std::uint32_t type = get<std::uint32_t>(h + 88);
    if (type < 1 || type > 4) throw FormatError(path + ": unknown sample type " + std::to_string(type) + " in sample store header");
    info.type = static_cast<SampleType>(type);
    info.value_lo = get<double>(h + 96);
    info.value_hi = get<double>(h + 104);
    info.levels = get<std::uint32_t>(h + 112);
    info.exact_levels = (get<std::uint32_t>(h + 116) & 1u) != 0;
    info.sample_count = get<std::uint64_t>(h + 120);
    info.bucket_count = get<std::uint64_t>(h + 128);
    info.constant_cells = get<std::uint64_t>(h + 136);
    info.nonfinite_cells = get<std::uint64_t>(h + 144);
    info.brick_edge = get<std::uint32_t>(h + 152);
    const char* src = reinterpret_cast<const char*>(h + kSourceOffset);
    info.source.assign(src, strnlen(src, kSourceBytes));
    if (info.levels < 1 || info.levels > 65536 || !(info.value_hi >= info.value_lo))
        throw FormatError(path + ": invalid span-space levels in sample store header");
    if (info.sample_count > (size / kSampleBytes) || info.bucket_count > size / kSampleStoreBucketBytes)
        throw FormatError(path + ": truncated sample store (" + std::to_string(size) + " bytes cannot hold " +
                          std::to_string(info.sample_count) + " samples)");
    const std::uint64_t table_offset = kSampleStoreHeaderBytes + info.sample_count * kSampleBytes;
    const std::uint64_t expected = table_offset + info.bucket_count * kSampleStoreBucketBytes + kSampleStoreFooterBytes;
    if (size < expected)
        throw FormatError(path + ": truncated sample store: expected " + std::to_string(expected) + " bytes, file has " +
                          std::to_string(size));
    if (size > expected)
        throw FormatError(path + ": sample store has " + std::to_string(size - expected) + " unexpected trailing bytes");

    unsigned char f[kSampleStoreFooterBytes];
    pread_all(s->fd_, f, sizeof f, expected - sizeof f, path);
    if (std::memcmp(f + 24, kEndMagic, 8) != 0 || get<std::uint32_t>(f + 20) != kSampleStoreVersion ||
        get<std::uint64_t>(f) != table_offset || get<std::uint64_t>(f + 8) != info.bucket_count)
        throw FormatError(path + ": sample store footer does not match its header (corrupt or truncated file)");
    std::vector<unsigned char> table(info.bucket_count * kSampleStoreBucketBytes);
    pread_all(s->fd_, table.data(), table.size(), table_offset, path);
    if (crc_update(0, table.data(), table.size()) != get<std::uint32_t>(f + 16))
        throw FormatError(path + ": sample store bucket table checksum mismatch (corrupt index)");

    s->scale_ = scale_of(info);
    s->buckets_.resize(info.bucket_count);
    s->row_begin_.assign(info.levels + 1, 0);
    std::uint64_t next = 0;
    for (std::size_t i = 0; i < s->buckets_.size(); ++i) {
        const unsigned char* e = table.data() + i * kSampleStoreBucketBytes;
        SampleBucket& b = s->buckets_[i];
        b.a = get<std::uint16_t>(e);
        b.b = get<std::uint16_t>(e + 2);
        b.crc = get<std::uint32_t>(e + 4);
        b.first = get<std::uint64_t>(e + 8);
        b.count = get<std::uint64_t>(e + 16);
        b.min_vmin = get<float>(e + 24);
        b.max_vmin = get<float>(e + 28);
        b.min_vmax = get<float>(e + 32);
        b.max_vmax = get<float>(e + 36);
        const bool ordered = i == 0 || s->buckets_[i - 1].a < b.a || (s->buckets_[i - 1].a == b.a && s->buckets_[i - 1].b < b.b);
        if (b.a > b.b || b.b >= info.levels || !ordered || b.first != next || b.count == 0 || b.count > info.sample_count - next ||
            !(b.min_vmin <= b.max_vmin && b.min_vmax <= b.max_vmax && b.min_vmin < b.max_vmax))
            throw FormatError(path + ": inconsistent bucket " + std::to_string(i) + " in sample store index");
        next += b.count;
    }
    if (next != info.sample_count) throw FormatError(path + ": sample store index does not cover its samples");
    // row_begin_[a] = first bucket with level(vmin) >= a
    std::size_t i = 0;
    for (std::uint32_t a = 0; a <= info.levels; ++a) {
        while (i < s->buckets_.size() && s->buckets_[i].a < a) ++i;
        s->row_begin_[a] = static_cast<std::uint32_t>(i);
    }
    return s;
}

std::uint32_t SampleStore::level(double v) const {
    Levels L;
    L.lo = info_.value_lo;
    L.scale = scale_;
    L.count = info_.levels;
    return L(v);
}

void SampleStore::read_samples(std::uint64_t first, std::uint64_t count, CellIntervalSample* dst) const {
    pread_all(fd_, dst, count * kSampleBytes, kSampleStoreHeaderBytes + first * kSampleBytes, path_);
    samples_read_ += count;
    bytes_read_ += count * kSampleBytes;
}

SampleStoreStats SampleStore::stats() const {
    SampleStoreStats s;
    s.queries = queries_.load();
    s.buckets_read = buckets_read_.load();
    s.samples_read = samples_read_.load();
    s.bytes_read = bytes_read_.load();
    s.samples_emitted = samples_emitted_.load();
    return s;
}

void SampleStore::reset_stats() const {
    queries_ = 0;
    buckets_read_ = 0;
    samples_read_ = 0;
    bytes_read_ = 0;
    samples_emitted_ = 0;
}

std::uint64_t SampleStore::query(double iso, const std::function<void(std::span<const SampleRecord>)>& emit,
                                 const SamplingParams& params, std::size_t max_batch) const {
    SampleQuery q(*this, iso, params);
    std::vector<SampleRecord> out;
    max_batch = std::clamp<std::size_t>(max_batch, 1, 65536);
    while (q.next(out, max_batch)) emit(std::span<const SampleRecord>(out.data(), out.size()));
    return q.emitted();
}

std::uint64_t SampleStore::count_upper_bound(double iso) const {
    if (std::isnan(iso)) throw UsageError("sample store query: the isovalue is NaN");
    const double thr = active_threshold(info_.type, iso);
    const std::uint32_t l = level(thr);
    std::uint64_t n = 0;
    for (std::uint32_t a = 0; a <= l; ++a)
        for (std::uint32_t i = row_begin_[a]; i < row_begin_[a + 1]; ++i) {
            const SampleBucket& b = buckets_[i];
            if (b.b < l || !(b.min_vmin < thr) || !(b.max_vmax >= thr)) continue;
            n += b.count;
        }
    return n;
}

void SampleStore::verify() const {
    std::vector<CellIntervalSample> buf;
    const std::uint64_t chunk = 1u << 18;
    for (std::size_t i = 0; i < buckets_.size(); ++i) {
        const SampleBucket& b = buckets_[i];
        std::uint32_t crc = 0;
        for (std::uint64_t o = 0; o < b.count; o += chunk) {
            const std::uint64_t n = std::min(chunk, b.count - o);
            buf.resize(n);
            read_samples(b.first + o, n, buf.data());
            crc = crc_update(crc, buf.data(), n * kSampleBytes);
        }
        ++buckets_read_;
        if (crc != b.crc)
            throw FormatError(path_ + ": bucket " + std::to_string(i) + " (levels " + std::to_string(b.a) + ".." +
                              std::to_string(b.b) + ", samples " + std::to_string(b.first) + ".." +
                              std::to_string(b.first + b.count) + ") checksum mismatch (corrupt samples)");
    }
}

// ---------------------------------------------------------------------------------------------
// Query cursor

SampleQuery::SampleQuery(const SampleStore& store, double iso, const SamplingParams& params) : store_(store) {
    if (std::isnan(iso)) throw UsageError("sample store query: the isovalue is NaN");
    const SampleStoreInfo& info = store.info();
    thr_ = active_threshold(info.type, iso);
    const GridSpec& g = info.grid;
    origin_ = g.origin;
    spacing_ = g.spacing;
    for (int a = 0; a < 3; ++a) inv_spacing_[a] = 1.0 / g.spacing[a];
    const double sx = g.spacing[0], sy = g.spacing[1], sz = g.spacing[2];
    proto_.radius = static_cast<float>(params.radius_scale * 0.5 * std::sqrt(sx * sx + sy * sy + sz * sz));
    for (int a = 0; a < 3; ++a) proto_.cell_size[a] = static_cast<float>(g.spacing[a]);
    for (float& c : proto_.corner) c = std::numeric_limits<float>::quiet_NaN();
    // span space: candidate buckets have level(vmin) <= level(thr) <= level(vmax); their exact
    // bounds decide between skip, whole, and filter
    const std::uint32_t l = store.level(thr_);
    const auto& bk = store.buckets_;
    for (std::uint32_t a = 0; a <= l && a < info.levels; ++a) {
        const std::uint32_t end = store.row_begin_[a + 1];
        std::uint32_t i = static_cast<std::uint32_t>(
            std::lower_bound(bk.begin() + store.row_begin_[a], bk.begin() + end, l,
                             [](const SampleBucket& b, std::uint32_t lv) { return b.b < lv; }) -
            bk.begin());
        for (; i < end; ++i) {
            const SampleBucket& b = bk[i];
            if (!(b.min_vmin < thr_) || !(b.max_vmax >= thr_)) continue;
            const bool whole = b.max_vmin < thr_ && b.min_vmax >= thr_;
            plan_.push_back({i, !whole});
        }
    }
    ++store.queries_;
}

bool SampleQuery::next(std::vector<SampleRecord>& out, std::size_t max) {
    out.clear();
    max = std::max<std::size_t>(max, 1);
    const auto& bk = store_.buckets_;
    while (out.size() < max && item_ < plan_.size()) {
        // one positional read over consecutive plan buckets that are contiguous on disk
        // small reads keep the buffer in cache while it is checksummed and converted
        const std::uint64_t want = std::min<std::uint64_t>(max - out.size(), kReadChunk);
        const std::uint64_t first = bk[plan_[item_].bucket].first + offset_;
        std::uint64_t n = 0;
        {
            std::size_t it = item_;
            std::uint64_t off = offset_;
            while (it < plan_.size() && n < want) {
                const SampleBucket& b = bk[plan_[it].bucket];
                if (b.first + off != first + n) break;  // not contiguous
                const std::uint64_t take = std::min(b.count - off, want - n);
                n += take;
                if (off + take < b.count) break;
                ++it;
                off = 0;
            }
        }
        buf_.resize(n);
        store_.read_samples(first, n, buf_.data());
        std::uint64_t pos = 0;
        while (pos < n) {
            const Item item = plan_[item_];
            const SampleBucket& b = bk[item.bucket];
            if (offset_ == 0) ++store_.buckets_read_;
            const std::uint64_t take = std::min(b.count - offset_, n - pos);
            const CellIntervalSample* s = buf_.data() + pos;
            crc_ = crc_update(crc_, s, take * kSampleBytes);
            const std::size_t base = out.size();
            out.resize(base + take);
            SampleRecord* o = out.data() + base;
            const double ox = origin_[0], oy = origin_[1], oz = origin_[2];
            const double sx = spacing_[0], sy = spacing_[1], sz = spacing_[2];
            const double ix = inv_spacing_[0], iy = inv_spacing_[1], iz = inv_spacing_[2];
            for (std::uint64_t k = 0; k < take; ++k) {
                const CellIntervalSample& c = s[k];
                if (item.filter && !(c.vmin < thr_ && thr_ <= c.vmax)) continue;
                SampleRecord& r = *o++;
                r = proto_;
                std::memcpy(r.pos, c.pos, sizeof r.pos + sizeof r.grad + sizeof r.value);  // pos, grad, value
                // the cell's lower corner exactly as paradigm (C) computes it, origin + i * s, with
                // the index i >= 0 recovered from the cell centre (exact up to float rounding)
                const double px = c.pos[0], py = c.pos[1], pz = c.pos[2];
                r.cell_lo[0] = static_cast<float>(ox + static_cast<double>(static_cast<std::int64_t>((px - ox) * ix)) * sx);
                r.cell_lo[1] = static_cast<float>(oy + static_cast<double>(static_cast<std::int64_t>((py - oy) * iy)) * sy);
                r.cell_lo[2] = static_cast<float>(oz + static_cast<double>(static_cast<std::int64_t>((pz - oz) * iz)) * sz);
            }
            out.resize(static_cast<std::size_t>(o - out.data()));
            pos += take;
            offset_ += take;
            if (offset_ == b.count) {
                if (crc_ != b.crc)
                    throw FormatError(store_.path_ + ": bucket " + std::to_string(item.bucket) + " (levels " +
                                      std::to_string(b.a) + ".." + std::to_string(b.b) + ", samples " +
                                      std::to_string(b.first) + ".." + std::to_string(b.first + b.count) +
                                      ") checksum mismatch (corrupt samples)");
                crc_ = 0;
                offset_ = 0;
                ++item_;
            }
        }
    }
    emitted_ += out.size();
    store_.samples_emitted_ += out.size();
    return !out.empty();
}

}  // namespace meshless
