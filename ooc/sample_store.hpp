// The sample store ("vol.mls" by convention; magic "\x89MLA"): paradigm (A) of the
// dissertation, "partial evaluation" (section 3.5, Table 3.1): point generation runs once, in
// preprocessing, for every isovalue; extraction of an isovalue only collects the samples of its
// active cells, reading them from disk through a span-space index (Livnat, Shen & Johnson; the
// out-of-core active-cell lookups cited in section 3.5), so a new isovalue costs time proportional to
// its active cells, not to the volume.
//
// Stored per sample (36 bytes, kernels/cell_interval_sampling.hpp): cell-centre position, trilinear
// value and gradient there, the cell's corner interval [vmin, vmax]; what the approximate projection
// (Eq. 3.5) needs. Radius and cell size come from the header's grid spacing. Corners are NOT stored,
// so the exact projection (Eq. 3.3) cannot run on these samples: query() emits SampleRecords with
// corner[] = NaN (see below).
//
// Span-space index: the value range [value_lo, value_hi] is cut into L levels, level(v) =
// clamp(floor((v - value_lo) * scale), 0, L-1), monotone in v. Integer volumes whose range has at
// most `levels` distinct values get exact levels (scale 1, L = range + 1: one level per grey value),
// otherwise scale = L / (value_hi - value_lo). Bucket (a, b), a <= b, holds the samples with
// level(vmin) = a, level(vmax) = b, in generation order: bricks in Morton order, cells row-major
// inside a brick (so a store built from a VolumeView with brick edge B and one built from a brick
// store with edge B are the same bytes). Buckets are stored a-major then b: for an isovalue at level
// l the candidate buckets {a <= l <= b} are, for each a, one contiguous run of the file.
// Query(iso): thr = active_threshold(type, iso); a cell is active when vmin < thr <= vmax (exactly
// the cell set of paradigm (C), kernels/cell_sampling.hpp). Each candidate bucket is tested with its
// exact bounds: skipped when min vmin >= thr or max vmax < thr, emitted whole when max vmin < thr <=
// min vmax (interior buckets), filtered sample by sample otherwise (boundary buckets; never needed
// with exact levels).
//
// File layout, version 1, all little endian:
//   header (256 bytes): magic "\x89MLA\r\n\x1a\n" | u32 version | u32 header bytes (256) |
//       i64 dims[3] | f64 origin[3] | f64 spacing[3] | u32 source sample type | u32 sample bytes (36) |
//       f64 value_lo | f64 value_hi | u32 levels L | u32 flags (bit 0: exact integer levels) |
//       u64 sample count | u64 bucket count (non-empty buckets) | u64 constant cells |
//       u64 non-finite cells | u32 brick edge | char source[96] (NUL padded) | u32 CRC-32 of [0,252)
//   samples: sample count x 36 bytes, bucket by bucket in table order
//   bucket table (non-empty buckets, sorted by (a, b)), 40 bytes each: u16 a | u16 b |
//       u32 CRC-32 of the bucket's sample bytes | u64 first sample | u64 count |
//       f32 min vmin | f32 max vmin | f32 min vmax | f32 max vmax
//   footer (32 bytes): u64 table offset | u64 bucket count | u32 CRC-32 of the table | u32 version |
//       magic "MLAEND\0\0"
// Opening checks magic, version, header CRC, exact file size (truncation), footer and table CRC and
// the table's consistency; a bucket's CRC is checked when a query (or verify()) has read all of it,
// so a damaged bucket throws FormatError (naming the file and bucket) before the query returns; a
// caller must treat the batches already delivered by a query that throws as void.
//
// Writers hold O(buckets + one brick + a write buffer) memory, never all samples: a first pass
// counts the samples per bucket, a second recomputes them and writes each at its bucket's offset
// (positional writes into an AtomicFile: temporary name, then rename).
// Threading: a SampleStore is immutable after open(); query/verify may run concurrently (positional
// reads); the read statistics are atomic. Errors: FormatError (bad file, naming it), IoError
// (cannot open/read/write), UsageError (NaN isovalue, output "-", bad parameters).
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/cell_interval_sampling.hpp"
#include "kernels/cell_sampling.hpp"
#include "kernels/grid.hpp"
#include "kernels/records.hpp"

namespace meshless {

class BrickStore;
class BrickCache;

inline constexpr std::uint32_t kSampleStoreVersion = 1;
inline constexpr std::size_t kSampleStoreHeaderBytes = 256;
inline constexpr std::size_t kSampleStoreBucketBytes = 40;
inline constexpr std::size_t kSampleStoreFooterBytes = 32;

struct SampleStoreInfo {
    GridSpec grid;
    SampleType type = SampleType::u8;   ///< sample type of the source volume
    double value_lo = 0, value_hi = 0;  ///< level range (finite range of the volume)
    std::uint32_t levels = 1;
    bool exact_levels = false;
    std::uint64_t sample_count = 0;
    std::uint64_t bucket_count = 0;
    std::uint64_t constant_cells = 0, nonfinite_cells = 0;
    std::uint32_t brick_edge = 0;
    std::string source;                 ///< file name of the source volume (<= 95 bytes kept)
};

/// One non-empty span-space bucket.
struct SampleBucket {
    std::uint16_t a = 0, b = 0;  ///< level(vmin), level(vmax)
    std::uint32_t crc = 0;
    std::uint64_t first = 0, count = 0;  ///< sample range
    float min_vmin = 0, max_vmin = 0, min_vmax = 0, max_vmax = 0;
};

/// Cumulative read counters of one SampleStore (all queries and verify()).
struct SampleStoreStats {
    std::uint64_t queries = 0;
    std::uint64_t buckets_read = 0;   ///< candidate buckets read from disk
    std::uint64_t samples_read = 0;   ///< stored samples read
    std::uint64_t bytes_read = 0;     ///< sample bytes read (header/table excluded: read once at open)
    std::uint64_t samples_emitted = 0;
};

class SampleQuery;

class SampleStore {
public:
    /// Opens and validates the file (header, size, footer, table); FormatError/IoError naming it.
    static std::unique_ptr<SampleStore> open(const std::string& path);
    ~SampleStore();
    SampleStore(const SampleStore&) = delete;
    SampleStore& operator=(const SampleStore&) = delete;

    const std::string& path() const { return path_; }
    const SampleStoreInfo& info() const { return info_; }
    const std::vector<SampleBucket>& buckets() const { return buckets_; }
    /// The span-space level of a value (monotone; see above).
    std::uint32_t level(double v) const;

    /// Emits the active samples of iso as SampleRecords in batches of at most max_batch records
    /// (<= 65536; the default keeps a batch in cache; cell_lo/cell_size from the header, radius = params.radius_scale * half the cell diagonal,
    /// corner[] = NaN). Returns the number emitted. UsageError for a NaN iso.
    std::uint64_t query(double iso, const std::function<void(std::span<const SampleRecord>)>& emit,
                        const SamplingParams& params = {}, std::size_t max_batch = 4096) const;
    /// Number of active samples of iso from the bucket table alone when no boundary bucket is hit
    /// (exact levels); otherwise an upper bound. Reads nothing.
    std::uint64_t count_upper_bound(double iso) const;
    /// Reads every bucket and checks its CRC; FormatError naming the first bad bucket.
    void verify() const;

    SampleStoreStats stats() const;
    void reset_stats() const;

private:
    friend class SampleQuery;
    SampleStore() = default;
    void read_samples(std::uint64_t first, std::uint64_t count, CellIntervalSample* dst) const;

    std::string path_;
    int fd_ = -1;
    SampleStoreInfo info_;
    double scale_ = 1.0;
    std::vector<SampleBucket> buckets_;
    std::vector<std::uint32_t> row_begin_;  ///< row_begin_[a] = first bucket with that a; size L+1
    mutable std::atomic<std::uint64_t> queries_{0}, buckets_read_{0}, samples_read_{0}, bytes_read_{0},
        samples_emitted_{0};
};

/// A pull-style cursor over the active samples of one isovalue (what query() and the stream source
/// use). Not thread-safe; the store must outlive it.
class SampleQuery {
public:
    SampleQuery(const SampleStore& store, double iso, const SamplingParams& params = {});
    /// Replaces `out` with the next up to max records (possibly fewer, possibly none while buckets
    /// remain); returns false when the query is exhausted (out is then empty).
    bool next(std::vector<SampleRecord>& out, std::size_t max = 65536);
    /// Active samples emitted so far.
    std::uint64_t emitted() const { return emitted_; }

private:
    struct Item {
        std::uint32_t bucket;
        bool filter;
    };
    const SampleStore& store_;
    double thr_;
    SampleRecord proto_{};
    std::array<double, 3> origin_{}, spacing_{}, inv_spacing_{};
    std::vector<Item> plan_;
    std::size_t item_ = 0;       ///< current plan item
    std::uint64_t offset_ = 0;   ///< samples of the current bucket already read
    std::uint32_t crc_ = 0;      ///< running CRC of the current bucket
    std::uint64_t emitted_ = 0;
    std::vector<CellIntervalSample> buf_;
};

/// Options of the writers.
struct SampleStoreParams {
    std::uint32_t levels = 256;               ///< span-space levels L (1..1024)
    std::uint32_t brick_edge = 32;            ///< virtual brick edge for VolumeView input (cells)
    std::size_t buffer_samples = 1u << 19;    ///< samples gathered before one sorted write (memory)
};

struct SampleStoreBuildStats {
    std::uint64_t samples = 0, buckets = 0, constant_cells = 0, nonfinite_cells = 0;
    std::uint64_t file_bytes = 0;
    std::uint32_t levels = 0;
    bool exact_levels = false;
};

/// Paradigm (A) preprocessing of an in-memory volume: cut into virtual bricks of params.brick_edge
/// cells visited in Morton order. `source_name` is recorded (file name of the volume).
SampleStoreBuildStats write_sample_store_from_volume(const VolumeView& v, const std::string& path,
                                                     const std::string& source_name,
                                                     const SampleStoreParams& params = {});
/// The same from a brick store, brick by brick in Morton order through `cache` (its budget bounds
/// the memory); params.brick_edge is ignored (the store's edge is recorded).
SampleStoreBuildStats write_sample_store_from_brick_store(const BrickStore& store, BrickCache& cache,
                                                          const std::string& path, const std::string& source_name,
                                                          const SampleStoreParams& params = {});

/// True when the file starts with the sample store magic.
bool is_sample_store(const std::string& path);

}  // namespace meshless
