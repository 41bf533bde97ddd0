#include "stream/volume_input.hpp"

#include "kernels/volume_crop.hpp"
#include "ooc/brick_slice_source.hpp"
#include "ooc/cropped_slice_source.hpp"

#include <stdexcept>

#include "formats/byte_size_text.hpp"
#include "formats/payload.hpp"
#include "formats/stored_type.hpp"
#include "formats/stored_type.hpp"
#include "formats/terminal_safe.hpp"
#include "ooc/brick_slice_source.hpp"
#include "stream/available_memory.hpp"
#include "stream/volume_block_minmax.hpp"

namespace meshless {

namespace {

constexpr int kFramingBlockEdge = 32;  // the default brick edge of meshless convert
constexpr const char* kBrickStoreFormat = "brick store (.mlb)";  // RawOptions::array refused: one array

void warn_if_raw_options_ignored(const std::string& path, const VolumeOpenOptions& o) {
    if (!o.raw_given || !o.warn) return;
    const VolumeInfo vi = probe_volume(path, o.raw);
    if (vi.format == "zarr" || vi.format == "ome-zarr") {  // .zarray gives the shape and dtype; OME-Zarr its scale
        if (o.raw.dims || o.raw.type || o.raw.big_endian)
            o.warn("warning: " + terminal_safe(path) + " is a Zarr store, whose .zarray gives its shape and dtype: --dims, " +
                   "--type and --endian are ignored");
        if (o.raw.spacing && vi.grid.spacing != *o.raw.spacing)
            o.warn("warning: " + terminal_safe(path) + " is an OME-Zarr image whose coordinateTransformations give its scale: " +
                   "--spacing is ignored");
        return;
    }
    if (vi.format == "hdf5") {  // the dataset gives its shape and type; its attributes, where present, the geometry
        if (o.raw.dims || o.raw.type || o.raw.big_endian)
            o.warn("warning: " + terminal_safe(path) + " is an HDF5 dataset, which gives its shape and type: --dims, --type " +
                   "and --endian are ignored");
        if (o.raw.spacing && vi.grid.spacing != *o.raw.spacing)
            o.warn("warning: " + terminal_safe(path) + " is an HDF5 dataset whose attributes give its spacing: --spacing is ignored");
        return;
    }
    if (vi.format == "npy") {  // the header gives the shape and dtype, --spacing the geometry it lacks
        if (o.raw.dims || o.raw.type || o.raw.big_endian)
            o.warn("warning: " + terminal_safe(path) + " is a .npy file, whose header gives its shape and dtype: --dims, " +
                   "--type and --endian are ignored");
        return;
    }
    if (vi.format != "raw")
        o.warn("warning: " + terminal_safe(path) + " is a " + vi.format +
               " file, which describes itself: --dims, --type, --endian and --spacing are ignored");
}

/// Formats whose payload open_slice_source streams from disk (raw or gzip samples, Zarr chunk rows).
bool streamable(const std::string& path, const RawOptions& raw) {
    const VolumeInfo vi = probe_volume(path, raw);
    if (vi.format == "zarr" || vi.format == "ome-zarr" || vi.format == "hdf5") return true;
    return (vi.format == "raw" || vi.format == "npy" || vi.format == "nrrd" || vi.format == "metaimage" || vi.format == "voreen-dat") &&
           (vi.encoding == "raw" || vi.encoding == "gzip");
}

// The slices of a spooled standard input, read as they are needed (long after open_volume_input):
// their errors name "- (stdin)", not the spool's /proc/self/fd path.
class StdinSliceSource final : public SliceSource {
public:
    StdinSliceSource(std::shared_ptr<const StdinSpool> spool, std::unique_ptr<SliceSource> src)
        : spool_(std::move(spool)), src_(std::move(src)) {}
    const GridSpec& grid() const override { return src_->grid(); }
    SampleType type() const override { return src_->type(); }
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        spool_->readable_errors([&] { src_->read_slices(k, count, out); });
    }
    std::string name() const override { return "- (stdin)"; }

private:
    std::shared_ptr<const StdinSpool> spool_;
    std::unique_ptr<SliceSource> src_;
};

/// The patient's axes and the length unit of a volume already read, into `in` (the header once
/// more; a header whose probe finds nothing to add leaves the camera generic and the unit unknown).
void set_probed_labels(VolumeInput& in, const std::string& path, const RawOptions& raw) {
    try {
        const VolumeInfo vi = probe_volume(path, raw);
        in.frame = vi.frame;
        in.length_unit = vi.length_unit;
        in.value_unit = vi.value_unit;
    } catch (const std::exception&) {
    }
}

}  // namespace

const GridSpec& VolumeInput::grid() const {
    return store ? store->info().grid : slices ? slices->grid() : volume->grid;
}
SampleType VolumeInput::type() const { return store ? store->info().type : slices ? slices->type() : volume->type; }

const BlockMinMax& VolumeInput::blocks() const {
    if (store) throw std::logic_error("VolumeInput::blocks: a brick store has its brick index");
    if (blocks_) return *blocks_;
    if (threads > 1 && (!slices || reopen))
        blocks_ = parallel_block_minmax(grid(), type(), kFramingBlockEdge, threads, reopen,
                                        slices ? nullptr : static_cast<const std::byte*>(volume->view().data));
    else
        blocks_ = slices ? streamed_block_minmax(*slices, kFramingBlockEdge) : block_minmax(volume->view(), kFramingBlockEdge);
    return *blocks_;
}

std::array<double, 2> VolumeInput::value_range() const {
    if (store) return {store->info().value_min, store->info().value_max};
    return blocks().range();
}

void check_volume_fits(const std::string& name, const VolumeInfo& vi, bool map, std::optional<std::uint64_t> memory) {
    if (map && vi.maps) return;  // the samples stay in the file (page cache), not in this process's memory
    const std::uint64_t need = decoded_bytes(vi, name);
    const std::uint64_t budget = memory ? *memory : available_memory();
    if (need <= budget) return;
    throw IoError(name + ": the volume takes " + byte_size_text(need) + " (" + dims_string(vi.grid) + " " +
                  to_string(vi.type) + ") in memory, more than " +
                  (memory ? "--memory " + byte_size_text(budget)
                          : "the " + byte_size_text(budget) + " this process may use (physical memory, cgroup limit; --memory sets it)") +
                  "; a brick store streams it: meshless convert " + name + " -o vol.mlb");
}

namespace {

/// open_volume_input with VolumeOpenOptions::crop: the whole input opened as usual (a brick store
/// as slices of the bricks the crop touches), then cropped (kernels/volume_crop.hpp).
VolumeInput open_cropped(const std::string& path, const VolumeOpenOptions& o) {
    VolumeOpenOptions whole = o;
    whole.crop.reset();
    const bool mlb_name = path.size() > 4 && path.compare(path.size() - 4, 4, ".mlb") == 0;
    if (path != "-" && (is_brick_store(path) || mlb_name)) {
        refuse_array_choice(o.raw.array, path, kBrickStoreFormat);
        VolumeInput in;
        in.path = path;
        in.threads = o.threads;
        const auto store = BrickStore::open(path);
        in.frame = store_frame(store->info());
        in.length_unit = store->info().length_unit;
        in.value_unit = store->info().value_unit;
        auto slices = open_brick_store_slices(path);
        const VoxelBox box = crop_voxels(slices->grid(), *o.crop, path);
        in.slices = make_cropped_source(std::move(slices), box);
        in.reopen = [path, box] { return make_cropped_source(open_brick_store_slices(path), box); };
        if (!o.stream) {  // the crop read whole, through the bricks it touches
            VolumeInfo vi;
            vi.grid = in.slices->grid();
            vi.type = in.slices->type();
            check_volume_fits(path, vi, false, o.memory);
            Volume v(vi.grid, vi.type);
            in.slices->read_slices(0, vi.grid.dims[2], v.bytes.data());
            in.volume = std::move(v);
            in.slices.reset();
            in.reopen = nullptr;
        }
        return in;
    }
    VolumeInput in = open_volume_input(path, whole);
    const VoxelBox box = crop_voxels(in.grid(), *o.crop, path == "-" ? "- (stdin)" : path);
    if (in.volume) in.volume = crop_volume(*in.volume, box);
    if (in.slices) in.slices = make_cropped_source(std::move(in.slices), box);
    if (in.reopen) in.reopen = [reopen = in.reopen, box] { return make_cropped_source(reopen(), box); };
    return in;
}

}  // namespace

Volume load_volume(const std::string& path, const VolumeOpenOptions& o, bool map) {
    if (o.crop) {  // the crop, read whole
        VolumeOpenOptions whole = o;
        whole.stream = false;
        VolumeInput in = open_cropped(path, whole);
        return std::move(*in.volume);
    }
    if (path == "-") {  // a mapping outlives the spool's descriptor; a read copies
        const StdinSpool spool;
        return spool.readable_errors([&] {
            check_volume_fits("- (stdin)", probe_volume(spool.path(), o.raw), map, o.memory);
            return map ? map_volume(spool.path(), o.raw) : read_volume(spool.path(), o.raw);
        });
    }
    if (is_brick_store(path)) {  // commands that need the volume whole
        refuse_array_choice(o.raw.array, path, kBrickStoreFormat);
        const auto store = BrickStore::open(path);
        VolumeInfo vi;
        vi.grid = store->info().grid;
        vi.type = store->info().type;
        check_volume_fits(path, vi, false, o.memory);
        return read_brick_store_volume(path);
    }
    warn_if_raw_options_ignored(path, o);
    check_volume_fits(path, probe_volume(path, o.raw), map, o.memory);
    return map ? map_volume(path, o.raw) : read_volume(path, o.raw);
}

VolumeInput open_volume_input(const std::string& path, const VolumeOpenOptions& o) {
    if (o.crop) return open_cropped(path, o);
    VolumeInput in;
    in.path = path;
    const RawOptions& raw = o.raw;
    if (in.path == "-") {  // standard input: spooled, then read as a file (no brick store: it needs its path)
        in.spool = std::make_shared<const StdinSpool>();
        in.threads = o.threads;
        in.spool->readable_errors([&] {
            if (o.stream && streamable(in.spool->path(), raw)) {
                in.slices = std::make_unique<StdinSliceSource>(in.spool, open_slice_source(in.spool->path(), raw));
                if (probe_volume(in.spool->path(), raw).encoding == "raw")
                    in.reopen = [spool = in.spool, raw]() -> std::unique_ptr<SliceSource> {
                        return std::make_unique<StdinSliceSource>(spool, open_slice_source(spool->path(), raw));
                    };
            } else {
                check_volume_fits("- (stdin)", probe_volume(in.spool->path(), raw), true, o.memory);
                in.volume = map_volume(in.spool->path(), raw);
            }
            set_probed_labels(in, in.spool->path(), raw);
        });
        return in;
    }
    const bool mlb_name = in.path.size() > 4 && in.path.compare(in.path.size() - 4, 4, ".mlb") == 0;
    if (is_brick_store(in.path) || mlb_name) {  // a damaged .mlb gets the brick store's own diagnosis
        refuse_array_choice(raw.array, in.path, kBrickStoreFormat);
        in.store = BrickStore::open(in.path);
        in.cache = std::make_unique<BrickCache>(*in.store, o.memory.value_or(kDefaultBrickCacheBytes));
        in.index = std::make_unique<BrickIndex>(*in.store);
        // the axes its volume's header gave, recorded by convert (older stores have none)
        in.frame = store_frame(in.store->info());
        in.length_unit = in.store->info().length_unit;
        in.value_unit = in.store->info().value_unit;
    } else {
        in.threads = o.threads;
        if (o.stream && streamable(in.path, raw)) {
            if (o.memory && o.warn)
                o.warn("warning: --memory bounds brick stores (.mlb) and volumes read whole; " + terminal_safe(in.path) +
                       " is streamed slab by slab");
            warn_if_raw_options_ignored(in.path, o);
            in.slices = open_slice_source(in.path, raw);
            if (const VolumeInfo vi = probe_volume(in.path, raw);  // any k, any reader: parallel passes
                vi.encoding == "raw" || vi.format == "zarr" || vi.format == "ome-zarr")
                in.reopen = [path = in.path, raw] { return open_slice_source(path, raw); };
        } else {
            in.volume = load_volume(in.path, o, /*map=*/true);
        }
        set_probed_labels(in, in.path, raw);
    }
    return in;
}

IsoSplatResult run_isosplat_input(VolumeInput& in, double iso, Projection mode, const SamplingParams& sp,
                                  Sink& sink, int threads, PipelineShape shape, const IsoSplatStages& extra) {
    if (in.store)
        return run_isosplat_bricks(*in.store, *in.cache, in.index->active(iso), iso, mode, sp, sink, {threads}, shape,
                                   extra);
    if (in.slices) return run_isosplat_slabs(*in.slices, iso, mode, sp, sink, {threads}, shape, extra);
    return run_isosplat(in.volume->view(), iso, mode, sp, sink, {threads}, shape, extra);
}

double isosurface_work(const VolumeInput& in, double iso) {
    if (!in.store) return static_cast<double>(cell_row_count(in.grid()));
    double rows = 0;
    for (const std::size_t b : in.index->active(iso)) rows += static_cast<double>(cell_row_count(in.store->brick_grid(b)));
    return rows;
}

std::optional<std::array<Vec3, 2>> surface_bounds(const VolumeInput& in, double iso) {
    if (in.store) return store_surface_bounds(*in.store, *in.index, iso);
    const auto box = active_block_box(in.blocks(), in.grid(), iso);
    if (!box) return std::nullopt;
    return world_bounds(in.grid(), *box);
}

StreamMeta volume_meta(const VolumeInput& in, double iso, const std::string& producer) {
    if (in.store) {
        StreamMeta m = volume_meta(in.path, in.grid(), in.type(), in.value_range(), iso, producer);
        set_surface_bounds(m, store_surface_bounds(*in.store, *in.index, iso));
        set_patient_axes(m, in.frame);
        set_length_unit(m, in.length_unit);
    if (!in.value_unit.empty()) m.set("value_unit", in.value_unit);
        return m;
    }
    // one pass gives the value range and the active blocks
    const BlockMinMax& b = in.blocks();
    StreamMeta m = volume_meta(in.path, in.grid(), in.type(), b.range(), iso, producer);
    const auto box = active_block_box(b, in.grid(), iso);
    set_surface_bounds(m, box ? std::optional(world_bounds(in.grid(), *box)) : std::nullopt);
    set_patient_axes(m, in.frame);
    set_length_unit(m, in.length_unit);
    if (!in.value_unit.empty()) m.set("value_unit", in.value_unit);
    return m;
}

}  // namespace meshless
