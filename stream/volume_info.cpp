#include "stream/volume_info.hpp"

#include "formats/anatomical_frame.hpp"
#include "formats/dicom_series.hpp"
#include "formats/reference_policy.hpp"
#include "formats/terminal_safe.hpp"
#include "formats/text_header.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/sample_store.hpp"
#include "stream/volume_input.hpp"

namespace meshless {

namespace {

void print_dims(const GridSpec& g, std::FILE* out) {
    std::fprintf(out, "  dims: %lld x %lld x %lld (%lld voxels, %lld cells)\n", static_cast<long long>(g.dims[0]),
                 static_cast<long long>(g.dims[1]), static_cast<long long>(g.dims[2]), static_cast<long long>(g.voxel_count()),
                 static_cast<long long>(g.cell_count()));
}

}  // namespace

void describe_brick_store(const std::string& path, std::FILE* out) {
    const auto store = BrickStore::open(path);
    const BrickStoreInfo& i = store->info();
    const GridSpec& g = i.grid;
    std::uint64_t stored = 0, raw = 0, constant = 0;
    for (const auto& e : store->bricks()) {
        stored += e.stored_bytes;
        raw += e.raw_bytes;
        if (e.vmin == e.vmax) ++constant;
    }
    const std::uint64_t volume_bytes = static_cast<std::uint64_t>(g.voxel_count()) * sample_size(i.type);
    const std::uint64_t file_bytes = stored + kBrickStoreHeaderBytes + kBrickStoreFooterBytes +
                                     store->bricks().size() * kBrickIndexEntryBytes;
    std::fprintf(out, "%s: meshless brick store, version %u\n", terminal_safe(path).c_str(), kBrickStoreVersion);
    print_dims(g, out);
    std::fprintf(out, "  type: %s\n  spacing: %g %g %g\n  origin: %g %g %g\n  value range: %g .. %g\n", to_string(i.type),
                 g.spacing[0], g.spacing[1], g.spacing[2], g.origin[0], g.origin[1], g.origin[2], i.value_min, i.value_max);
    if (i.patient_axes)  // recorded by convert from the volume's header
        std::fprintf(out, "  patient axes: %s (from the converted volume's header)\n",
                     describe_frame(frame_of_axes(*i.patient_axes, "brick store header")).c_str());
    if (!i.length_unit.empty()) std::fprintf(out, "  length unit: %s (from the converted volume's header)\n", i.length_unit.c_str());
    if (!i.value_unit.empty()) std::fprintf(out, "  value unit: %s (from the converted volume's header)\n", i.value_unit.c_str());
    std::fprintf(out, "  bricks: %llu (%lld x %lld x %lld) of %u cells + %u ghost, Morton order, zstd level %d; %llu constant\n",
                 static_cast<unsigned long long>(i.brick_count), static_cast<long long>(i.bricks_per_axis[0]),
                 static_cast<long long>(i.bricks_per_axis[1]), static_cast<long long>(i.bricks_per_axis[2]), i.brick_edge,
                 i.ghost, i.zstd_level, static_cast<unsigned long long>(constant));
    std::fprintf(out, "  largest brick: %llu bytes decompressed (minimum --memory)\n",
                 static_cast<unsigned long long>(store->max_brick_bytes()));
    std::fprintf(out, "  size: %llu bytes; volume %llu bytes (bricks with ghost layers %llu): compression ratio %.2f\n",
                 static_cast<unsigned long long>(file_bytes), static_cast<unsigned long long>(volume_bytes),
                 static_cast<unsigned long long>(raw), file_bytes ? static_cast<double>(volume_bytes) / file_bytes : 0.0);
}

void describe_volume(const std::string& path, const RawOptions& raw, bool value_range, std::FILE* out) {
    // a DICOM folder of several series: listed (each reading command refuses it, naming them the same way)
    if (raw.series.empty() && is_dicom_input(path, raw)) {
        const std::vector<DicomSeriesSummary> all = list_dicom_series(path, raw.references);
        if (all.size() > 1) {
            std::fprintf(out, "%s: DICOM, %zu series (read one with --series N or --series UID)\n", terminal_safe(path).c_str(), all.size());
            for (std::size_t i = 0; i < all.size(); ++i)
                std::fprintf(out, "  %zu) %s\n", i + 1, terminal_safe(describe_dicom_series(all[i])).c_str());
            return;
        }
    }
    // the payload proven as the readers would before allocating it, and decoded through a small
    // buffer: a bomb, a truncated or a corrupt payload fails here as it fails every reading command
    const VolumeInfo vi = prove_volume(path, raw);
    const GridSpec& g = vi.grid;
    std::fprintf(out, "%s: %s volume\n", terminal_safe(path).c_str(), vi.format.c_str());
    print_dims(g, out);
    std::fprintf(out, "  type: %s\n  spacing: %g %g %g\n  origin: %g %g %g\n", to_string(vi.type), g.spacing[0], g.spacing[1],
                 g.spacing[2], g.origin[0], g.origin[1], g.origin[2]);
    if (!vi.series.empty()) std::fprintf(out, "  series: %s\n", terminal_safe(vi.series).c_str());
    if (vi.arrays.size() > 1) {  // a multi-array file: which one is read, and the others
        std::fprintf(out, "  point arrays: %zu (read one with --array NAME)\n", vi.arrays.size());
        for (std::size_t k = 0; k < vi.arrays.size(); ++k) {
            const VolumeArray& v = vi.arrays[k];
            std::string note;
            if (k == vi.read_array) note = k == vi.default_array ? "read, the default" : "read (--array)";
            else if (k == vi.default_array) note = "the default";
            std::fprintf(out, "    %s: %s, %s%s%s%s\n", escape_field(v.name, 256).c_str(), v.type.c_str(),
                         v.components > 0 ? std::to_string(v.components).c_str() : "?", v.components == 1 ? " component" : " components",
                         note.empty() ? "" : "; ", note.c_str());
        }
    }
    if (!vi.encoding.empty()) std::fprintf(out, "  encoding: %s\n", vi.encoding.c_str());
    // every file the header makes the readers open, as named and resolved (`..`, symbolic links)
    if (!vi.data_files.empty()) {
        std::fprintf(out, "  data files: %zu\n", vi.data_files.size());
        for (const auto& f : vi.data_files)
            std::fprintf(out, "    %s -> %s\n", terminal_safe(f).c_str(), terminal_safe(resolved_path(f)).c_str());
    }
    if (vi.frame)
        std::fprintf(out, "  patient axes: %s (%s)\n", describe_frame(*vi.frame).c_str(), terminal_safe(vi.frame->source).c_str());
    if (!vi.length_unit.empty()) std::fprintf(out, "  length unit: %s\n", vi.length_unit.c_str());
    if (!vi.value_unit.empty()) std::fprintf(out, "  value unit: %s\n", vi.value_unit.c_str());
    std::fprintf(out, "  payload: checked, %llu bytes decoded%s\n", static_cast<unsigned long long>(decoded_bytes(vi, path)),
                 vi.maps ? " (mapped from the file when read)" : "");
    if (value_range) {
        check_volume_fits(path, probe_volume(path, raw), /*map=*/false, std::nullopt);  // read whole
        const Volume v = read_volume(path, raw);
        const auto r = v.value_range();
        std::fprintf(out, "  value range: %g .. %g\n", r[0], r[1]);
    }
}

void describe_sample_store(const std::string& path, std::FILE* out) {
    const auto store = SampleStore::open(path);
    const SampleStoreInfo& i = store->info();
    const GridSpec& g = i.grid;
    std::fprintf(out, "%s: meshless paradigm (A) sample store, version %u (span-space index of cell rows)\n",
                 terminal_safe(path).c_str(), kSampleStoreVersion);
    std::fprintf(out, "  brick store: %s -> %s (recomputed from; identity checked), %lld x %lld x %lld %s, spacing %g %g %g\n",
                 terminal_safe(store->brick_store().path()).c_str(), terminal_safe(resolved_path(store->brick_store().path())).c_str(),
                 static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]), static_cast<long long>(g.dims[2]),
                 to_string(i.type), g.spacing[0], g.spacing[1], g.spacing[2]);
    std::fprintf(out, "  cells: %llu indexed (non-constant; %llu constant, %llu NaN/Inf cells skipped) as %llu cell-row keys, "
                 "%llu key bytes\n",
                 static_cast<unsigned long long>(i.cells), static_cast<unsigned long long>(i.constant_cells),
                 static_cast<unsigned long long>(i.nonfinite_cells), static_cast<unsigned long long>(i.key_count),
                 static_cast<unsigned long long>(i.key_bytes));
    std::fprintf(out, "  index: %llu buckets over %u %s levels of [%g, %g]\n", static_cast<unsigned long long>(i.bucket_count),
                 i.levels, i.exact_levels ? "exact" : "quantised", i.value_lo, i.value_hi);
}

}  // namespace meshless
