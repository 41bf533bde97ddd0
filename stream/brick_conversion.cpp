#include "stream/brick_conversion.hpp"

#include <cstdio>
#include <exception>
#include <utility>

#include "formats/anatomical_frame.hpp"
#include "formats/volume_reader.hpp"
#include "ooc/brick_store.hpp"
#include "stream/text_format.hpp"

namespace meshless {

VolumeLabels volume_labels_of(const std::string& path, const RawOptions& raw) {
    try {
        if (is_brick_store(path)) {
            const auto store = BrickStore::open(path);  // (held: info() lives in it)
            const BrickStoreInfo& i = store->info();
            return {i.patient_axes, i.length_unit, i.value_unit};
        }
        const VolumeInfo vi = probe_volume(path, raw);
        VolumeLabels l;
        if (vi.frame) l.patient_axes = frame_axes(*vi.frame);
        l.length_unit = vi.length_unit;
        l.value_unit = vi.value_unit;
        return l;
    } catch (const std::exception&) {
        return {};
    }
}

ConversionInput open_conversion_input(const std::string& path, const VolumeOpenOptions& o) {
    ConversionInput c;
    if (path == "-") {  // standard input, spooled (formats/stdin_spool.hpp): streamed when it can be
        VolumeInput in = open_volume_input(path, o);
        if (in.spool) c.labels = volume_labels_of(in.spool->path(), o.raw);
        c.slices = in.slices ? std::move(in.slices) : make_volume_source(std::move(*in.volume), "- (stdin)");
        return c;
    }
    if (o.crop) {  // the crop's slices (a brick store's: only the bricks the crop touches)
        VolumeInput in = open_volume_input(path, o);
        c.slices = in.slices ? std::move(in.slices) : make_volume_source(std::move(*in.volume), path);
    } else {
        c.slices = open_slice_source(path, o.raw);
    }
    c.labels = volume_labels_of(path, o.raw);
    return c;
}

ConversionInput open_upsampled_input(const std::string& path, const VolumeOpenOptions& o, int factor, Upsampling mode) {
    ConversionInput c;
    c.volume = std::make_unique<const Volume>(load_volume(path, o));
    if (path != "-") c.labels = volume_labels_of(path, o.raw);
    c.slices = make_upsampling_source(*c.volume, factor, mode, path);
    return c;
}

std::string brick_conversion_report(const std::string& command, const SliceSource& src, const std::string& out,
                                    const ConvertParams& p, const ConvertStats& st) {
    const GridSpec& g = src.grid();
    return format_text("%s: %lldx%lldx%lld %s -> %s: %llu bricks of %u cells, level %d, %.1f MB in %.3f s (%.1f MB/s), "
                       "%.1f MB stored, ratio %.2f",
                       command.c_str(), static_cast<long long>(g.dims[0]), static_cast<long long>(g.dims[1]),
                       static_cast<long long>(g.dims[2]), to_string(src.type()), out.c_str(),
                       static_cast<unsigned long long>(st.bricks), p.brick_edge, p.zstd_level, st.input_bytes / 1e6, st.seconds,
                       st.seconds > 0 ? st.input_bytes / 1e6 / st.seconds : 0.0, st.output_bytes / 1e6,
                       st.output_bytes ? static_cast<double>(st.input_bytes) / static_cast<double>(st.output_bytes) : 0.0);
}

}  // namespace meshless
