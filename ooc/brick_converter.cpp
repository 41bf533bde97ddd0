#include "ooc/brick_converter.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>
#include <zstd.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <limits>
#include <numeric>
#include <vector>

#include "formats/spool_file.hpp"
#include "formats/atomic_file.hpp"
#include "formats/temporary_files.hpp"
#include "kernels/errors.hpp"
#include "kernels/morton.hpp"
#include "ooc/brick_store.hpp"

namespace meshless {

namespace {

/// The spool of compressed frames in slab order ("<out>.tmp-<pid>.spool", removed by the destructor).
using Spool = SpoolFile;

struct CompressedBrick {
    std::vector<std::byte> frame;
    BrickEntry entry;  ///< offset = position in the spool until the final layout
};

struct CCtxDeleter {
    void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};
using CCtxPtr = std::unique_ptr<ZSTD_CCtx, CCtxDeleter>;

// Copies brick box b out of a slab (slices [z0, z0+nzs) of the volume) into dst, and returns the
// range of its finite samples (NaN, NaN when it has none).
template <class T>
std::array<double, 2> extract(const T* slab, const GridSpec& g, std::int64_t z0, const BrickBox& b, T* dst) {
    const std::int64_t nx = g.dims[0], ny = g.dims[1];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    T tlo = std::numeric_limits<T>::max(), thi = std::numeric_limits<T>::lowest();
    bool any = false;
    for (std::int64_t k = 0; k < b.dims[2]; ++k)
        for (std::int64_t j = 0; j < b.dims[1]; ++j) {
            const T* src = slab + ((b.first[2] + k - z0) * ny + (b.first[1] + j)) * nx + b.first[0];
            std::memcpy(dst, src, static_cast<std::size_t>(b.dims[0]) * sizeof(T));
            for (std::int64_t i = 0; i < b.dims[0]; ++i) {
                const T v = dst[i];
                if constexpr (std::is_floating_point_v<T>) {
                    if (!std::isfinite(v)) continue;
                    any = true;
                }
                tlo = std::min(tlo, v);
                thi = std::max(thi, v);
            }
            dst += b.dims[0];
        }
    if constexpr (!std::is_floating_point_v<T>) any = b.voxel_count() > 0;
    if (!any) return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    lo = static_cast<double>(tlo);
    hi = static_cast<double>(thi);
    return {lo, hi};
}

}  // namespace

ConvertStats convert_to_brick_store(SliceSource& src, const std::string& out_path, const ConvertParams& p,
                                    const std::function<void(double)>& progress) {
    const auto t0 = std::chrono::steady_clock::now();
    if (p.brick_edge < 2 || p.brick_edge > 1024)
        throw InvalidArgument("--brick: brick edge must be 2..1024 cells, got " + std::to_string(p.brick_edge));
    if (p.zstd_level < 1 || p.zstd_level > ZSTD_maxCLevel())
        throw InvalidArgument("--level: zstd level must be 1.." + std::to_string(ZSTD_maxCLevel()) + ", got " +
                              std::to_string(p.zstd_level));
    if (p.threads < 1) throw InvalidArgument("--threads: must be at least 1");
    const GridSpec g = src.grid();
    const SampleType type = src.type();
    const std::size_t ss = sample_size(type);
    const std::uint32_t B = p.brick_edge;

    BrickStoreInfo info;
    info.grid = g;
    info.type = type;
    info.brick_edge = B;
    info.ghost = 1;
    info.zstd_level = p.zstd_level;
    info.patient_axes = p.patient_axes;
    info.length_unit = p.length_unit;
    info.value_unit = p.value_unit;
    info.bricks_per_axis = brick_store_bricks_per_axis(g.dims, B);
    for (int a = 0; a < 3; ++a)
        if (info.bricks_per_axis[a] >= (std::int64_t{1} << 21))
            throw InvalidArgument(src.name() + ": too many bricks along an axis; use a larger --brick");
    info.brick_count = static_cast<std::uint64_t>(info.bricks_per_axis[0] * info.bricks_per_axis[1] * info.bricks_per_axis[2]);

    const std::int64_t nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    const std::size_t slice_bytes = static_cast<std::size_t>(nx * ny) * ss;
    const std::int64_t nbx = info.bricks_per_axis[0], nby = info.bricks_per_axis[1], nbz = info.bricks_per_axis[2];

    remove_stale_temporaries(out_path);
    Spool spool(out_path);
    std::vector<BrickEntry> entries;
    entries.reserve(static_cast<std::size_t>(info.brick_count));
    // With more than one thread the next slab is read (or upsampled) while this one is compressed:
    // two slab buffers instead of one. The source is still read by one task at a time, in order.
    const bool prefetch = p.threads > 1 && nbz > 1;
    const std::size_t slab_bytes = static_cast<std::size_t>(std::min<std::int64_t>(B + 1, nz)) * slice_bytes;
    std::vector<std::byte> slab(slab_bytes), next(prefetch ? slab_bytes : 0);
    std::vector<CompressedBrick> out(static_cast<std::size_t>(nbx * nby));
    tbb::task_arena arena(p.threads);
    tbb::enumerable_thread_specific<CCtxPtr> cctx([] { return CCtxPtr(ZSTD_createCCtx()); });
    tbb::enumerable_thread_specific<std::vector<std::byte>> scratch, zbuf;
    double vmin = std::numeric_limits<double>::infinity(), vmax = -vmin;

    // Fills dst with slab bz: the shared ghost slice comes from the previous slab `prev` (its
    // last slice, slab bz-1 having B+1 slices), the rest from the source. dst may be prev.
    auto load = [&](std::int64_t bz, std::byte* dst, const std::byte* prev) {
        const std::int64_t z0 = bz * B, z1 = std::min<std::int64_t>(z0 + B + 1, nz);
        std::int64_t keep = 0;
        if (prev) {
            std::memmove(dst, prev + static_cast<std::size_t>(B) * slice_bytes, slice_bytes);
            keep = 1;
        }
        src.read_slices(z0 + keep, z1 - z0 - keep, dst + static_cast<std::size_t>(keep) * slice_bytes);
    };
    load(0, slab.data(), nullptr);
    for (std::int64_t bz = 0; bz < nbz; ++bz) {
        const std::int64_t z0 = bz * B;
        const bool more = bz + 1 < nbz;
        arena.execute([&] {
            tbb::task_group reader;
            if (prefetch && more) reader.run([&] { load(bz + 1, next.data(), slab.data()); });
            std::exception_ptr failed;
            try {
            tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, nbx * nby, 1), [&](const tbb::blocked_range<std::int64_t>& r) {
                ZSTD_CCtx* cc = cctx.local().get();
                if (!cc) throw std::bad_alloc();
                std::vector<std::byte>& raw = scratch.local();
                for (std::int64_t q = r.begin(); q < r.end(); ++q) {
                    const std::array<std::uint32_t, 3> coord{static_cast<std::uint32_t>(q % nbx), static_cast<std::uint32_t>(q / nbx),
                                                             static_cast<std::uint32_t>(bz)};
                    const BrickBox b = brick_store_box(g.dims, B, coord);
                    raw.resize(static_cast<std::size_t>(b.voxel_count()) * ss);
                    const VolumeView sv{slab.data(), type, g};
                    const auto range = visit_samples(sv, [&](const auto* s) {
                        using T = std::remove_const_t<std::remove_pointer_t<decltype(s)>>;
                        return extract<T>(s, g, z0, b, reinterpret_cast<T*>(raw.data()));
                    });
                    CompressedBrick& cb = out[static_cast<std::size_t>(q)];
                    std::vector<std::byte>& z = zbuf.local();
                    z.resize(ZSTD_compressBound(raw.size()));
                    const std::size_t n = ZSTD_compressCCtx(cc, z.data(), z.size(), raw.data(), raw.size(), p.zstd_level);
                    if (ZSTD_isError(n)) throw IoError(out_path + ": zstd compression failed (" + ZSTD_getErrorName(n) + ")");
                    cb.frame.assign(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(n));  // exact size: a slab's frames stay small
                    BrickEntry& e = cb.entry;
                    e.coord = coord;
                    e.key = morton_encode(coord[0], coord[1], coord[2]);
                    e.stored_bytes = n;
                    e.crc = brick_store_crc32(cb.frame.data(), n);
                    e.vmin = range[0];
                    e.vmax = range[1];
                    e.raw_bytes = raw.size();
                }
            });
            } catch (...) {
                failed = std::current_exception();
            }
            reader.wait();  // rethrows a read failure
            if (failed) std::rethrow_exception(failed);
        });
        for (CompressedBrick& cb : out) {
            cb.entry.offset = spool.append(cb.frame.data(), cb.frame.size());
            if (!std::isnan(cb.entry.vmin)) {
                vmin = std::min(vmin, cb.entry.vmin);
                vmax = std::max(vmax, cb.entry.vmax);
            }
            entries.push_back(cb.entry);
            std::vector<std::byte>().swap(cb.frame);
        }
        if (progress) progress(static_cast<double>(bz + 1) / static_cast<double>(nbz));
        if (more) {
            if (prefetch) slab.swap(next);
            else load(bz + 1, slab.data(), slab.data());
        }
    }
    if (vmin > vmax) vmin = vmax = 0;  // no finite sample: same convention as Volume::value_range
    info.value_min = vmin;
    info.value_max = vmax;

    // Final layout: header, frames in Morton order, index, footer.
    std::sort(entries.begin(), entries.end(), [](const BrickEntry& a, const BrickEntry& b) { return a.key < b.key; });
    AtomicFile file(out_path, Durability::fsync);
    file.write(encode_brick_store_header(info).data(), kBrickStoreHeaderBytes);
    std::uint64_t at = kBrickStoreHeaderBytes;
    std::vector<std::byte> buf;
    std::vector<std::byte> index(entries.size() * kBrickIndexEntryBytes);
    for (std::size_t i = 0; i < entries.size(); ++i) {
        BrickEntry& e = entries[i];
        buf.resize(static_cast<std::size_t>(e.stored_bytes));
        spool.read(e.offset, buf.size(), buf.data());
        file.write(buf.data(), buf.size());
        e.offset = at;
        at += e.stored_bytes;
        encode_brick_index_entry(e, index.data() + i * kBrickIndexEntryBytes);
    }
    file.write(index.data(), index.size());
    const std::uint32_t index_crc = brick_store_crc32(index.data(), index.size());
    file.write(encode_brick_store_footer(at, entries.size(), index_crc).data(), kBrickStoreFooterBytes);
    file.commit();

    ConvertStats st;
    st.input_bytes = static_cast<std::uint64_t>(g.voxel_count()) * ss;
    st.output_bytes = at + index.size() + kBrickStoreFooterBytes;
    st.bricks = entries.size();
    st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return st;
}

}  // namespace meshless
