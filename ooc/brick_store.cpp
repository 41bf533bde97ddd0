#include "ooc/brick_store.hpp"
#include "formats/binary_file.hpp"
#include "formats/length_unit.hpp"
#include "formats/store_framing.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <mutex>

#include "kernels/errors.hpp"
#include "kernels/morton.hpp"

namespace meshless {

namespace {

template <class T>
void put(std::byte* p, std::size_t off, T v) {
    std::memcpy(p + off, &v, sizeof(T));
}
template <class T>
T get(const std::byte* p, std::size_t off) {
    T v;
    std::memcpy(&v, p + off, sizeof(T));
    return v;
}

// Reads exactly n bytes at offset; IoError on a read failure, FormatError when the file ends first.
void pread_exact(int fd, const std::string& path, std::uint64_t offset, std::size_t n, std::byte* dst,
                 const char* what) {
    std::size_t done = 0;
    while (done < n) {
        const ssize_t r = ::pread(fd, dst + done, n - done, static_cast<off_t>(offset + done));
        if (r < 0) {
            if (errno == EINTR) continue;
            throw IoError(path + ": read failed at offset " + std::to_string(offset + done) + " (" + std::strerror(errno) + ")");
        }
        if (r == 0)
            throw FormatError(path + ": truncated: " + what + " needs " + std::to_string(n) + " bytes at offset " +
                              std::to_string(offset));
        done += static_cast<std::size_t>(r);
    }
}

}  // namespace

std::array<std::int64_t, 3> brick_store_bricks_per_axis(const std::array<std::int64_t, 3>& dims, std::uint32_t edge) {
    std::array<std::int64_t, 3> n{};
    for (int a = 0; a < 3; ++a) n[a] = std::max<std::int64_t>(1, (dims[a] - 1 + edge - 1) / edge);
    return n;
}

BrickBox brick_store_box(const std::array<std::int64_t, 3>& volume_dims, std::uint32_t edge,
                         const std::array<std::uint32_t, 3>& coord) {
    BrickBox b;
    for (int a = 0; a < 3; ++a) {
        b.first[a] = static_cast<std::int64_t>(coord[a]) * edge;
        b.dims[a] = std::min<std::int64_t>(b.first[a] + edge + 1, volume_dims[a]) - b.first[a];
    }
    return b;
}

std::string voxel_range_string(const BrickBox& b) {
    char buf[192];
    std::snprintf(buf, sizeof buf, "[%lld,%lld)x[%lld,%lld)x[%lld,%lld)", static_cast<long long>(b.first[0]),
                  static_cast<long long>(b.first[0] + b.dims[0]), static_cast<long long>(b.first[1]),
                  static_cast<long long>(b.first[1] + b.dims[1]), static_cast<long long>(b.first[2]),
                  static_cast<long long>(b.first[2] + b.dims[2]));
    return buf;
}

std::uint32_t brick_store_crc32(const void* data, std::size_t n) {
    uLong c = crc32(0L, Z_NULL, 0);
    const auto* p = static_cast<const Bytef*>(data);
    while (n > 0) {
        const std::size_t chunk = std::min<std::size_t>(n, 1u << 30);
        c = crc32(c, p, static_cast<uInt>(chunk));
        p += chunk;
        n -= chunk;
    }
    return static_cast<std::uint32_t>(c);
}

std::vector<std::byte> encode_brick_store_header(const BrickStoreInfo& info) {
    std::vector<std::byte> h(kBrickStoreHeaderBytes);
    std::byte* p = h.data();
    std::memcpy(p, kBrickStoreMagic, 8);
    put<std::uint32_t>(p, 8, kBrickStoreVersion);
    put<std::uint32_t>(p, 12, static_cast<std::uint32_t>(kBrickStoreHeaderBytes));
    for (int a = 0; a < 3; ++a) {
        put<std::int64_t>(p, 16 + 8 * a, info.grid.dims[a]);
        put<double>(p, 40 + 8 * a, info.grid.origin[a]);
        put<double>(p, 64 + 8 * a, info.grid.spacing[a]);
        put<std::int64_t>(p, 128 + 8 * a, info.bricks_per_axis[a]);
    }
    put<std::uint32_t>(p, 88, static_cast<std::uint32_t>(info.type));
    put<std::uint32_t>(p, 92, info.brick_edge);
    put<std::uint32_t>(p, 96, info.ghost);
    put<std::int32_t>(p, 100, info.zstd_level);
    put<double>(p, 104, info.value_min);
    put<double>(p, 112, info.value_max);
    put<std::uint64_t>(p, 120, info.brick_count);
    if (info.patient_axes) {
        put<std::uint32_t>(p, 152, 1);
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) put<double>(p, static_cast<std::size_t>(160 + 8 * (3 * i + k)), (*info.patient_axes)[i][k]);
    }
    put<std::uint32_t>(p, 232, length_unit_code(info.length_unit));
    const std::string vu = value_unit_text(info.value_unit);
    std::memcpy(p + 236, vu.data(), vu.size());
    put<std::uint32_t>(p, 252, brick_store_crc32(p, 252));
    return h;
}

void encode_brick_index_entry(const BrickEntry& e, std::byte* p) {
    put<std::uint64_t>(p, 0, e.key);
    put<std::uint64_t>(p, 8, e.offset);
    put<std::uint64_t>(p, 16, e.stored_bytes);
    put<std::uint32_t>(p, 24, e.crc);
    for (int a = 0; a < 3; ++a) put<std::uint32_t>(p, 28 + 4 * a, e.coord[a]);
    put<double>(p, 40, e.vmin);
    put<double>(p, 48, e.vmax);
    put<std::uint64_t>(p, 56, e.raw_bytes);
}

std::vector<std::byte> encode_brick_store_footer(std::uint64_t index_offset, std::uint64_t brick_count,
                                                 std::uint32_t index_crc) {
    const auto f = encode_store_footer(index_offset, brick_count, index_crc, kBrickStoreVersion,
                                       std::string_view(kBrickStoreEndMagic, 8));
    const auto* p = reinterpret_cast<const std::byte*>(f.data());
    return std::vector<std::byte>(p, p + f.size());
}

// ---------------------------------------------------------------------------------------------

struct BrickStore::ContextPool {
    std::mutex mu;
    std::vector<ZSTD_DCtx*> free;
    ~ContextPool() {
        for (ZSTD_DCtx* c : free) ZSTD_freeDCtx(c);
    }
};

BrickStore::BrickStore() : pool_(std::make_unique<ContextPool>()) {}

BrickStore::~BrickStore() {
    if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<BrickStore> BrickStore::open(const std::string& path) {
    std::unique_ptr<BrickStore> s(new BrickStore());  // private constructor
    s->path_ = path;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw IoError(path + ": is a directory, expected a brick store (.mlb)");
    require_regular_file(path);
    s->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (s->fd_ < 0) throw IoError(path + ": cannot open (" + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(s->fd_, &st) != 0) throw IoError(path + ": cannot stat (" + std::strerror(errno) + ")");
    const std::uint64_t size = static_cast<std::uint64_t>(st.st_size);

    // Header.
    std::byte h[kBrickStoreHeaderBytes];
    if (size < 8) throw FormatError(path + ": not a brick store (file has " + std::to_string(size) + " bytes)");
    pread_exact(s->fd_, path, 0, 8, h, "magic");
    if (std::memcmp(h, kBrickStoreMagic, 8) != 0) throw FormatError(path + ": not a brick store (wrong magic)");
    if (size < kBrickStoreHeaderBytes + kBrickStoreFooterBytes)
        throw FormatError(path + ": truncated brick store (file has " + std::to_string(size) + " bytes)");
    pread_exact(s->fd_, path, 0, kBrickStoreHeaderBytes, h, "header");
    const auto version = get<std::uint32_t>(h, 8);
    if (version != kBrickStoreVersion)
        throw FormatError(path + ": unsupported brick store version " + std::to_string(version) + " (this build reads " +
                          std::to_string(kBrickStoreVersion) + ")");
    if (get<std::uint32_t>(h, 252) != brick_store_crc32(h, 252))
        throw FormatError(path + ": header checksum mismatch (corrupt header)");
    if (get<std::uint32_t>(h, 12) != kBrickStoreHeaderBytes)
        throw FormatError(path + ": header size " + std::to_string(get<std::uint32_t>(h, 12)) + ", expected 256");
    BrickStoreInfo& in = s->info_;
    for (int a = 0; a < 3; ++a) {
        in.grid.dims[a] = get<std::int64_t>(h, 16 + 8 * a);
        in.grid.origin[a] = get<double>(h, 40 + 8 * a);
        in.grid.spacing[a] = get<double>(h, 64 + 8 * a);
        in.bricks_per_axis[a] = get<std::int64_t>(h, 128 + 8 * a);
    }
    const auto type = get<std::uint32_t>(h, 88);
    if (type < 1 || type > 4) throw FormatError(path + ": unknown sample type code " + std::to_string(type));
    in.type = static_cast<SampleType>(type);
    in.brick_edge = get<std::uint32_t>(h, 92);
    in.ghost = get<std::uint32_t>(h, 96);
    in.zstd_level = get<std::int32_t>(h, 100);
    in.value_min = get<double>(h, 104);
    in.value_max = get<double>(h, 112);
    if (get<std::uint32_t>(h, 152) == 1) {  // patient axes: finite unit vectors, else ignored (they only frame a picture)
        std::array<std::array<double, 3>, 3> ax{};
        bool ok = true;
        for (int i = 0; i < 3; ++i) {
            double n2 = 0;
            for (int k = 0; k < 3; ++k) {
                ax[i][k] = get<double>(h, static_cast<std::size_t>(160 + 8 * (3 * i + k)));
                n2 += ax[i][k] * ax[i][k];
            }
            ok = ok && std::isfinite(n2) && std::fabs(n2 - 1) < 1e-6;
        }
        if (ok) in.patient_axes = ax;
    }
    in.length_unit = length_unit_of_code(get<std::uint32_t>(h, 232));  // (an unknown code: no unit, it only labels pictures)
    {
        const char* vu = reinterpret_cast<const char*>(h + 236);
        in.value_unit = value_unit_text(std::string_view(vu, ::strnlen(vu, 16)));
    }
    in.brick_count = get<std::uint64_t>(h, 120);
    for (int a = 0; a < 3; ++a)
        if (in.grid.dims[a] < 1 || in.grid.dims[a] > (std::int64_t{1} << 40))
            throw FormatError(path + ": invalid dimensions in header");
    validate_grid(in.grid, path);  // voxel count, finite spacing > 0, finite origin (a header `verify` must not pass)
    if (in.brick_edge < 2 || in.brick_edge > 1024)
        throw FormatError(path + ": invalid brick edge " + std::to_string(in.brick_edge) + " (2..1024)");
    if (in.ghost != 1) throw FormatError(path + ": unsupported ghost width " + std::to_string(in.ghost) + " (expected 1)");
    const auto bpa = brick_store_bricks_per_axis(in.grid.dims, in.brick_edge);
    if (bpa != in.bricks_per_axis) throw FormatError(path + ": bricks per axis do not match dims and brick edge");
    for (int a = 0; a < 3; ++a)
        if (bpa[a] >= (std::int64_t{1} << 21)) throw FormatError(path + ": too many bricks along an axis");
    if (in.brick_count != static_cast<std::uint64_t>(bpa[0] * bpa[1] * bpa[2]))
        throw FormatError(path + ": brick count " + std::to_string(in.brick_count) + " does not match the brick grid");

    // Footer.
    std::byte f[kBrickStoreFooterBytes];
    pread_exact(s->fd_, path, size - kBrickStoreFooterBytes, kBrickStoreFooterBytes, f, "footer");
    if (std::memcmp(f + 24, kBrickStoreEndMagic, 8) != 0)
        throw FormatError(path + ": truncated or unfinished brick store (no footer at the end of the file)");
    if (get<std::uint32_t>(f, 20) != kBrickStoreVersion)
        throw FormatError(path + ": footer version " + std::to_string(get<std::uint32_t>(f, 20)) + " does not match");
    const auto index_offset = get<std::uint64_t>(f, 0);
    const auto count = get<std::uint64_t>(f, 8);
    if (count != in.brick_count)
        throw FormatError(path + ": footer brick count " + std::to_string(count) + " differs from the header's " +
                          std::to_string(in.brick_count));
    if (index_offset < kBrickStoreHeaderBytes || index_offset > size || count > size / kBrickIndexEntryBytes ||
        index_offset + count * kBrickIndexEntryBytes + kBrickStoreFooterBytes != size)
        throw FormatError(path + ": index offset " + std::to_string(index_offset) + " inconsistent with the file size " +
                          std::to_string(size) + " (truncated or corrupt footer)");

    // Index.
    std::vector<std::byte> idx(static_cast<std::size_t>(count * kBrickIndexEntryBytes));
    pread_exact(s->fd_, path, index_offset, idx.size(), idx.data(), "index");
    if (brick_store_crc32(idx.data(), idx.size()) != get<std::uint32_t>(f, 16))
        throw FormatError(path + ": index checksum mismatch (corrupt index or footer)");
    const std::uint64_t ss = sample_size(in.type);
    s->bricks_.resize(static_cast<std::size_t>(count));
    std::uint64_t expect_offset = kBrickStoreHeaderBytes;
    for (std::size_t i = 0; i < count; ++i) {
        const std::byte* p = idx.data() + i * kBrickIndexEntryBytes;
        BrickEntry& e = s->bricks_[i];
        e.key = get<std::uint64_t>(p, 0);
        e.offset = get<std::uint64_t>(p, 8);
        e.stored_bytes = get<std::uint64_t>(p, 16);
        e.crc = get<std::uint32_t>(p, 24);
        for (int a = 0; a < 3; ++a) e.coord[a] = get<std::uint32_t>(p, 28 + 4 * a);
        e.vmin = get<double>(p, 40);
        e.vmax = get<double>(p, 48);
        e.raw_bytes = get<std::uint64_t>(p, 56);
        const std::string where = path + ": index entry " + std::to_string(i) + ": ";
        for (int a = 0; a < 3; ++a)
            if (e.coord[a] >= bpa[a]) throw FormatError(where + "brick coordinate out of range");
        if (e.key != morton_encode(e.coord[0], e.coord[1], e.coord[2]))
            throw FormatError(where + "Morton key does not match its coordinates");
        if (i > 0 && e.key <= s->bricks_[i - 1].key) throw FormatError(where + "not in ascending Morton order");
        if (e.offset != expect_offset || e.stored_bytes > index_offset - e.offset)
            throw FormatError(where + "frame offset/size inconsistent with the file layout");
        expect_offset += e.stored_bytes;
        const BrickBox b = brick_store_box(in.grid.dims, in.brick_edge, e.coord);
        if (e.raw_bytes != static_cast<std::uint64_t>(b.voxel_count()) * ss)
            throw FormatError(where + "raw size " + std::to_string(e.raw_bytes) + " does not match its voxel box " +
                              voxel_range_string(b));
    }
    if (expect_offset != index_offset) throw FormatError(path + ": bytes between the last brick and the index");
    return s;
}

BrickBox BrickStore::box(std::size_t i) const {
    return brick_store_box(info_.grid.dims, info_.brick_edge, bricks_.at(i).coord);
}

GridSpec BrickStore::brick_grid(std::size_t i) const {
    const BrickBox b = box(i);
    GridSpec g;
    g.dims = b.dims;
    g.spacing = info_.grid.spacing;
    for (int a = 0; a < 3; ++a) g.origin[a] = info_.grid.origin[a] + static_cast<double>(b.first[a]) * info_.grid.spacing[a];
    return g;
}

std::array<std::int64_t, 3> BrickStore::brick_first_voxel(std::size_t i) const { return box(i).first; }

std::uint64_t BrickStore::max_brick_bytes() const {
    std::uint64_t m = 0;
    for (const auto& e : bricks_) m = std::max(m, e.raw_bytes);
    return m;
}

void BrickStore::read_brick(std::size_t i, std::vector<std::byte>& out) const {
    const BrickEntry& e = bricks_.at(i);
    auto fail = [&](const std::string& what) {
        return FormatError(path_ + ": brick " + std::to_string(i) + " (voxels " + voxel_range_string(box(i)) + "): " + what);
    };
    std::vector<std::byte> frame(static_cast<std::size_t>(e.stored_bytes));
    try {
        pread_exact(fd_, path_, e.offset, frame.size(), frame.data(), "brick");
    } catch (const FormatError&) {
        throw fail("truncated (the file ends inside the brick)");
    }
    if (brick_store_crc32(frame.data(), frame.size()) != e.crc) throw fail("checksum mismatch (corrupt data)");
    const unsigned long long content = ZSTD_getFrameContentSize(frame.data(), frame.size());
    if (content != e.raw_bytes) throw fail("frame content size does not match the index");
    out.resize(static_cast<std::size_t>(e.raw_bytes));
    ZSTD_DCtx* ctx = nullptr;
    {
        std::lock_guard<std::mutex> lock(pool_->mu);
        if (!pool_->free.empty()) {
            ctx = pool_->free.back();
            pool_->free.pop_back();
        }
    }
    if (!ctx) ctx = ZSTD_createDCtx();
    if (!ctx) throw std::bad_alloc();
    const std::size_t n = ZSTD_decompressDCtx(ctx, out.data(), out.size(), frame.data(), frame.size());
    {
        std::lock_guard<std::mutex> lock(pool_->mu);
        pool_->free.push_back(ctx);
    }
    if (ZSTD_isError(n)) throw fail(std::string("corrupt zstd frame (") + ZSTD_getErrorName(n) + ")");
    if (n != out.size()) throw fail("decompressed to " + std::to_string(n) + " bytes, expected " + std::to_string(out.size()));
}

bool is_brick_store(const std::string& path) { return file_starts_with(path, std::string_view(kBrickStoreMagic, 8)); }

}  // namespace meshless
