// The sample store reader: paradigm (A) extraction (dissertation section 3.5, Table 3.1). A store
// (layout: ooc/sample_store_format.hpp, writer: ooc/sample_store_writer.hpp) lists, per span-space
// bucket, the cell rows of the non-constant cells; a query for an isovalue reads only the candidate
// buckets (ooc/span_space_levels.hpp), merges their rows into ascending key order (bricks in Morton
// order, rows in order), and recomputes the samples of those rows from the referenced brick store
// with paradigm (C)'s own kernel (kernels/cell_sampling.hpp sample_active_cells). So a query emits
// exactly paradigm (C)'s active cells, with the same bytes (corners included: both projections
// apply) and in the same order as `meshless generate vol.mlb`, while touching only the bricks that
// hold active cells and, inside them, only the candidate rows.
//
// Opening validates the .mls (see the format header) and then its brick store: the recorded path
// (relative to the .mls's folder unless absolute) must exist and have the recorded identity
// (size, header and index CRCs) and the same grid, type and brick edge; otherwise FormatError/
// IoError naming the .mls and the .mlb ("vol.mls: its brick store vol.mlb is missing", "... has
// changed since the sample store was made"). Bucket damage (CRC, malformed keys) is detected when
// a query or verify() reads the bucket, before anything of that query is emitted.
// Memory of a query: one bit per possible row (ooc/row_set.hpp) + one decompressed brick + one
// batch. Threading: a SampleStore is immutable after open(); queries may run concurrently; the
// read statistics are atomic. A SampleQuery is not thread-safe.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/cell_sampling.hpp"
#include "kernels/records.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/row_set.hpp"
#include "ooc/sample_store_format.hpp"
#include "ooc/span_space_levels.hpp"

namespace meshless {

/// Cumulative read counters of one SampleStore (all queries and verify()).
struct SampleStoreStats {
    std::uint64_t queries = 0;
    std::uint64_t buckets_read = 0;   ///< candidate buckets read
    std::uint64_t key_bytes_read = 0; ///< key bytes read (header/table excluded: read once at open)
    std::uint64_t rows_read = 0;      ///< distinct candidate cell rows recomputed
    std::uint64_t bricks_read = 0;    ///< bricks decompressed from the .mlb
    std::uint64_t samples_emitted = 0;
};

class SampleQuery;

class SampleStore {
public:
    /// Opens and validates the .mls and its brick store (see above).
    static std::unique_ptr<SampleStore> open(const std::string& path);
    ~SampleStore();
    SampleStore(const SampleStore&) = delete;
    SampleStore& operator=(const SampleStore&) = delete;

    const std::string& path() const { return path_; }
    const SampleStoreInfo& info() const { return layout_.info; }
    const std::vector<SampleBucket>& buckets() const { return layout_.buckets; }
    const SpanSpaceLevels& levels() const { return levels_; }
    /// The brick store the samples are recomputed from.
    const BrickStore& brick_store() const { return *mlb_; }

    /// Emits the active samples of iso as SampleRecords (paradigm C's, see above) in batches of at
    /// most max_batch records (1..65536). Returns the number emitted. InvalidArgument for a NaN iso.
    std::uint64_t query(double iso, const std::function<void(std::span<const SampleRecord>)>& emit,
                        const SamplingParams& params = {}, std::size_t max_batch = 4096) const;
    /// Reads and decodes every bucket; FormatError naming the first bad one.
    void verify() const;

    SampleStoreStats stats() const;
    void reset_stats() const;

private:
    friend class SampleQuery;
    SampleStore() = default;
    void read_bytes(void* dst, std::size_t n, std::uint64_t offset) const;

    std::string path_;
    int fd_ = -1;
    SampleStoreLayout layout_;
    SpanSpaceLevels levels_;
    std::unique_ptr<BrickStore> mlb_;
    mutable std::atomic<std::uint64_t> queries_{0}, buckets_read_{0}, key_bytes_read_{0}, rows_read_{0},
        bricks_read_{0}, samples_emitted_{0};
};

/// A pull-style cursor over the active samples of one isovalue (what query() and the stream source
/// use). The constructor reads and decodes the candidate buckets (FormatError on damage); next()
/// recomputes brick by brick. Not thread-safe; the store must outlive it.
class SampleQuery {
public:
    SampleQuery(const SampleStore& store, double iso, const SamplingParams& params = {});
    /// Replaces `out` with the next records (at most max, at least one unless exhausted, never
    /// from two bricks); returns false when the query is exhausted (out is then empty).
    bool next(std::vector<SampleRecord>& out, std::size_t max = 65536);
    /// Active samples emitted so far.
    std::uint64_t emitted() const { return emitted_; }
    /// Distinct candidate rows of the query.
    std::uint64_t candidate_rows() const { return rows_.size(); }

private:
    const SampleStore& store_;
    double iso_;
    SamplingParams params_;
    RowSet rows_;                      ///< candidate rows
    std::uint64_t at_ = 0;             ///< next key to look at
    std::int64_t brick_ = -1;          ///< brick held in buf_
    std::vector<std::byte> buf_;
    std::vector<SampleRecord> out_;      ///< the batch being built
    std::vector<SampleRecord> pending_;  ///< records of a row run beyond the last batch's cap
    std::size_t pend_at_ = 0;
    std::uint64_t emitted_ = 0;
};

/// True when the file starts with the sample store magic.
bool is_sample_store(const std::string& path);

}  // namespace meshless
