// A volume as the chapter-3 graphs take it (dissertation sections 3.5-3.6): a volume in memory
// (mapped from the file when it holds raw samples), a file streamed slab by slab, or a brick store
// (.mlb) read brick by brick through a byte-budgeted cache with its brick interval tree; and
// standard input ("-") spooled to an unlinked temporary and read as a file. The one place a
// volume input is opened, for every front end (the CLI, the Python module).
// Memory: a volume read whole takes its decoded samples (refused beforehand when they exceed the
// budget: check_volume_fits); a streamed file or a store takes about one slab or the brick cache.
// RawOptions::array given for a brick store is an InvalidArgument (it holds one array), as for the
// formats of one unnamed array (formats/volume_reader.hpp).
// Throws FormatError for bad data, IoError for files that cannot be read and for a volume that does
// not fit the budget (naming the file, the size and the budget), both naming the file ("- (stdin)"
// for standard input). Thread-safety: a VolumeInput is used by one thread at a time; blocks() runs
// its own parallel pass (stream/volume_block_minmax.hpp).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "formats/anatomical_frame.hpp"
#include "formats/stdin_spool.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/block_minmax.hpp"
#include "kernels/cell_sampling.hpp"
#include "kernels/grid.hpp"
#include "kernels/project_sample.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/slice_source.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/stream_metadata.hpp"

namespace meshless {

/// How a volume input is opened.
struct VolumeOpenOptions {
    RawOptions raw;         ///< a raw file's shape, type, byte order and spacing
    bool raw_given = false; ///< the caller gave raw options: a warning when the file describes itself
    /// true (graphs that make one pass in cell-row order: isosurface, generate): raw, NRRD, MetaImage
    /// and Voreen files with raw or gzip payloads are streamed slab by slab, other formats read
    /// whole; false: read whole (mapped when raw samples).
    bool stream = false;
    /// The memory budget the caller gave, bytes: a brick store's cache and the most a volume read
    /// whole may take. Without it: a 256 MiB cache, and whole volumes up to available_memory()
    /// (physical memory capped by the cgroup limit, stream/available_memory.hpp).
    std::optional<std::uint64_t> memory;
    int threads = 1;  ///< threads of VolumeInput::blocks() (its result does not depend on them)
    /// A box in world units {x0, y0, z0, x1, y1, z1}: only the samples inside it, as a volume of
    /// their own (kernels/volume_crop.hpp; InvalidArgument when it keeps fewer than 2 samples along
    /// an axis). A brick store is then read as slices of the bricks the crop touches (no brick
    /// index: the cropped volume's min/max pass frames the stream, as for a file).
    std::optional<std::array<double, 6>> crop;
    /// Receives one-line warnings (already escaped for a terminal; the caller adds who speaks), e.g.
    /// "warning: f.nrrd is a nrrd file, which describes itself: ...". Empty: no warnings.
    std::function<void(const std::string&)> warn;
};

/// The brick cache of a store opened without a budget (bytes).
inline constexpr std::uint64_t kDefaultBrickCacheBytes = std::uint64_t{256} << 20;

struct VolumeInput {
    std::string path;
    std::optional<Volume> volume;
    std::unique_ptr<SliceSource> slices;  ///< slab-streamed file (VolumeOpenOptions::stream)
    /// Opens another reader of `slices` (raw payloads, read at any k), for passes split across
    /// threads; empty when the payload must be read in order (gzip).
    std::function<std::unique_ptr<SliceSource>()> reopen;
    int threads = 1;  ///< threads for blocks(); its result does not depend on them
    std::unique_ptr<BrickStore> store;
    std::unique_ptr<BrickCache> cache;
    std::unique_ptr<BrickIndex> index;
    std::shared_ptr<const StdinSpool> spool;  ///< path "-": standard input spooled (formats/stdin_spool.hpp)
    /// The patient's axes, where the header says them (a brick store records its volume's): the
    /// default camera of its pictures, carried in volume_meta as `patient_axes`.
    std::optional<AnatomicalFrame> frame;
    /// The length unit of its world coordinates where the file says it (formats/length_unit.hpp; a
    /// brick store records its volume's), else "": carried in volume_meta as `length_unit`.
    std::string length_unit;
    /// The values' unit where the file says it (VolumeInfo::value_unit; a store records it), else "":
    /// carried in volume_meta as `value_unit`, the colour bar's title.
    std::string value_unit;
    const GridSpec& grid() const;
    SampleType type() const;
    /// The value range (computed once, on first use: the store's header, or blocks().range()).
    std::array<double, 2> value_range() const;
    /// Not for a brick store (its index has the bricks' intervals; std::logic_error): the min/max of
    /// 32-cell blocks aligned as a store's bricks (kernels/block_minmax.hpp), computed once, on first
    /// use, in one pass over the volume in memory or over the slab-streamed file (a layer of blocks at
    /// a time; layers split across `threads` when the volume is in memory or `reopen` is set).
    const BlockMinMax& blocks() const;

private:
    mutable std::optional<BlockMinMax> blocks_;
};

/// Opens `path` ("-": standard input) as the options say. Brick stores (.mlb, by content or name;
/// a damaged .mlb gets the brick store's own diagnosis) are always opened as stores.
VolumeInput open_volume_input(const std::string& path, const VolumeOpenOptions& o);

/// Reads the volume at `path` ("-": standard input) whole, a brick store included (commands that
/// need every sample at once); map = true maps raw samples from the file instead of reading them.
/// Refused beforehand by check_volume_fits when the samples exceed the budget.
Volume load_volume(const std::string& path, const VolumeOpenOptions& o, bool map = false);

/// Refuses, before anything is read, a volume whose decoded samples exceed `memory` (when given,
/// else available_memory()). A volume that `map` lets map_volume map costs no memory of its own and
/// always fits. IoError naming `name`, the size and the budget, suggesting `meshless convert` to a
/// brick store (which streams).
void check_volume_fits(const std::string& name, const VolumeInfo& vi, bool map, std::optional<std::uint64_t> memory);

/// Runs paradigm (C), the chapter-3 graph of stream/isosplat_pipeline.hpp, on any kind of input:
/// the active bricks of a store, a slab-streamed file or a volume in memory; extra.first sees
/// isosurface_work(in, iso) cell rows in all.
IsoSplatResult run_isosplat_input(VolumeInput& in, double iso, Projection mode, const SamplingParams& sp,
                                  Sink& sink, int threads, PipelineShape shape, const IsoSplatStages& extra = {});
/// The cell rows run_isosplat_input hands out (for progress lines): the volume's (in memory or
/// slab-streamed), or those of the active bricks of a store.
double isosurface_work(const VolumeInput& in, double iso);

/// The bounds of the isosurface known before extraction (dissertation section 3.6 framing): a brick
/// store: the union of the active bricks' voxel boxes (BrickIndex::active); a volume in memory: the
/// union of the active 32-cell blocks (aligned as the bricks of a store with the default edge, so
/// both frame alike). nullopt when nothing is active.
std::optional<std::array<Vec3, 2>> surface_bounds(const VolumeInput& in, double iso);

/// The stream metadata of an isosurface of `in` (stream/stream_metadata.hpp volume_meta), framed:
/// bounds_lo/hi are the surface bounds for iso (surface_bounds; the volume's when nothing is active)
/// and the volume's are kept as volume_bounds_lo/hi; the patient's axes when known. For a volume in
/// memory or streamed, the value range and the surface bounds come from one pass (blocks()).
StreamMeta volume_meta(const VolumeInput& in, double iso, const std::string& producer);

}  // namespace meshless
