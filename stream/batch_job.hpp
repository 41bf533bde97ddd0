// The batch job, the recipe of `meshless batch` (the nightly archive job) and of any other front
// end: converts every volume of an archive to a brick store OUT_DIR/NAME.mlb and iso-splats it
// into point sets (NAME_iso<V>.ply and/or NAME_iso<V>.mlp, one per isovalue), skipping outputs whose
// sidecar says they are up to date (stream/batch_sidecar.hpp), going on past bad inputs, and
// returning one result per volume.
//
// Archive: a directory or a manifest (stream/batch_archive.hpp). Outputs mirror the volumes' names
// (NAME: batch_archive's output name); a name claimed by two volumes fails the second.
// Crash safety: every output and sidecar is written to a temporary name and renamed, the sidecar
// after its output, and a stale sidecar is removed before its output is redone; so a run killed at
// any point leaves complete outputs (with or without sidecar) and temporaries, which the next run
// removes (quietly, formats/temporary_files.hpp) before finishing only what is left. Outputs are
// deterministic, so the result is byte-identical to a clean run. The folder is locked for the run
// (stream/batch_lock.hpp).
// Failures: a volume that fails (bad data, I/O, out of memory) is a result with its message, the
// run goes on; one that is, or whose header names, a file outside its archive folder is `refused`
// (nothing of it read or written); a full disk stops the run, the rest `not attempted`.
// Throws, before any volume is made: IoError (no such archive, the output folder cannot be made or
// is locked, the archive cannot be listed), InvalidArgument (the archive is a single volume);
// BrokenPipe passes through. Units: seconds of wall time; progress fractions 0..1.
// Not thread-safe: one run at a time per output folder; the callbacks run on the calling thread.
// docs/architecture.md: stream/ holds the recipes the front ends call.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "kernels/cell_sampling.hpp"
#include "kernels/project_sample.hpp"
#include "ooc/brick_converter.hpp"
#include "stream/batch_archive.hpp"

namespace meshless {

/// What a run makes, and how (the CLI fills it from its options).
struct BatchSettings {
    std::string out_dir;       ///< created when missing
    std::vector<double> isos;  ///< one point set (or two) per isovalue; names batch_iso_name, distinct
    bool ply = true, stream = false;  ///< point set formats: PLY, point stream
    bool rehash = false;       ///< hash every input, even when its size and time are those recorded
    bool recursive = false;    ///< archive directory: walk subfolders too
    ConvertParams convert;     ///< brick edge, zstd level, threads of the conversion
    Projection mode = Projection::approx;
    SamplingParams sampling;
    std::uint64_t memory = 256ull << 20;  ///< brick cache budget, bytes (as --memory 256M)
    int threads = 1;
    /// --shard K/N: this run converts the volumes dealt to shard `shard` (0-based) of `shards`
    /// (stream/batch_shard.hpp); shards of one archive may run at once into the same OUT_DIR.
    std::uint32_t shard = 0, shards = 1;
    /// A dynamic deal (mpirun, stream/batch_ranks.hpp): when set, the run converts the volumes this
    /// returns — positions in size_order of the archive (stream/batch_shard.hpp), largest first —
    /// until it returns nullopt, called first after the sweep of temporaries (`shard` 0 sweeps the
    /// whole archive's, the others none); `shard`/`shards` then name only the lock.
    std::function<std::optional<std::size_t>()> deal;
    /// With a deal: the share of the archive's bytes dealt so far, for the progress line (the batch
    /// fraction is then the run's, not this rank's alone).
    std::function<double()> dealt_share;
};

/// An isovalue as output names carry it ("%.9g": "_iso100.5").
std::string batch_iso_name(double iso);

enum class BatchStatus { done, up_to_date, failed, refused };

/// One volume of a run.
struct BatchItemResult {
    std::string name;  ///< output name (stream/batch_archive.hpp)
    BatchStatus status = BatchStatus::failed;
    int written = 0, current = 0;  ///< outputs written, outputs found up to date (also when failed)
    int empty = 0;                 ///< isovalues whose point sets hold no point (the isovalue crosses no brick)
    double seconds = 0;
    std::string message;    ///< why it failed or was refused ("not attempted: ..." after a full disk)
    std::string stops_run;  ///< non-empty: why the run stops after this volume ("out of disk space in OUT")
};

struct BatchRun {
    std::vector<BatchItemResult> items;  ///< in archive order (a shard's: its own)
    std::size_t archive_count = 0;       ///< the volumes of the whole archive (a shard converts some of them)
    std::uint32_t shard = 0, shards = 1; ///< as BatchSettings
    double seconds = 0;                  ///< the volumes' loop, from after the sweep of temporaries
    /// Some volume failed or was refused.
    bool any_failed() const;
    /// Some isovalue of some volume gave an empty point set (`meshless batch --fail-empty`).
    bool any_empty() const;
};

/// A step of the running volume, for a progress line.
struct BatchProgress {
    std::size_t index = 0, count = 0;  ///< the volume (0-based) of count
    std::string name;                  ///< its output name
    std::string what;                  ///< "converting", "hashing input", "iso 100.5"
    double fraction = -1;              ///< of the step (converting), -1: none
    double batch = 0;                  ///< of the run: volumes weighed by input bytes, the running one by its conversion
    double seconds = 0;                ///< since the volumes' loop began (BatchRun::seconds)
};

/// What the run tells its caller as it goes (each may be empty).
struct BatchCallbacks {
    RawOptionsParser parse_raw;                            ///< a manifest line's raw options
    std::function<void(const BatchProgress&)> progress;    ///< each step
    /// Before each isovalue's pass over a store: the store's value range (NaN: no finite sample), the
    /// input's path (the CLI warns when iso lies outside; the outputs are then empty but valid).
    std::function<void(double iso, const std::array<double, 2>& range, const std::string& input)> iso_range;
    /// After each volume attempted (not those after a full disk).
    std::function<void(const BatchItemResult&)> item_done;
};

/// Runs the batch job over `archive` (a directory or a manifest), see above.
BatchRun run_batch(const std::string& archive, const BatchSettings& s, const BatchCallbacks& cb);

}  // namespace meshless
