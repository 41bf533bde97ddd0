#include "stream/sample_stream_generation.hpp"

#include "formats/terminal_safe.hpp"
#include "stream/continued_sink.hpp"
#include "stream/iso_range_warning.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless {

std::vector<IsoSplatResult> generate_sample_stream(VolumeInput& in, const std::vector<double>& isos, const SamplingParams& sp,
                                                   std::FILE* out, const std::string& name, const std::string& producer,
                                                   bool compress, int threads, std::FILE* warn, bool* warned) {
    const bool segments = isos.size() > 1;
    StreamMeta meta = volume_meta(in, isos[0], producer);
    set_isovalues(meta, isos, [&](double v) { return surface_bounds(in, v); });
    StreamSink sink(out, name, RecordKind::sample, meta, compress);
    // the records are sample_active_cells' on a volume of uint8/int16/uint16/float32 values, which
    // floats hold exactly: the encoder checks their positions and takes their values from the corners
    sink.index_cells(cell_grid(in.grid()), SampleCellEncoder::Verify::position);
    std::vector<IsoSplatResult> r;
    std::vector<std::size_t> counts;
    run_each_isovalue(isos.size(), sink, r, counts, [&](std::size_t i, Sink& one) {
        if (segments) sink.begin_segment(i, isos[i]);
        return run_isosplat_input(in, isos[i], Projection::approx, sp, one, threads, PipelineShape::samples_only);
    });
    bool said = false;
    // a run that found an active cell has iso inside the range: the volume is not read again to say nothing
    for (std::size_t i = 0; i < isos.size(); ++i)
        said = (r[i].sampling.active_cells == 0 && warn_if_iso_outside(isos[i], in.value_range(), in.path, warn, segments)) || said;
    if (warned) *warned = said;
    return r;
}

void print_generate_stats(std::FILE* out, const std::string& path, const std::vector<double>& isos,
                          const std::vector<IsoSplatResult>& r) {
    for (std::size_t i = 0; i < isos.size(); ++i)
        std::fprintf(out, "generate: %s iso %g: %lld samples (active cells), %lld cells with NaN/Inf skipped, %.3f s\n",
                     terminal_safe(path).c_str(), isos[i], static_cast<long long>(r[i].sampling.active_cells),
                     static_cast<long long>(r[i].sampling.nonfinite_cells), r[i].seconds);
}

}  // namespace meshless
