#include "stream/sample_stream_generation.hpp"

#include "formats/terminal_safe.hpp"
#include "stream/iso_range_warning.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless {

IsoSplatResult generate_sample_stream(VolumeInput& in, double iso, const SamplingParams& sp, std::FILE* out, const std::string& name,
                                      const std::string& producer, bool compress, int threads, std::FILE* warn, bool* warned) {
    StreamSink sink(out, name, RecordKind::sample, volume_meta(in, iso, producer), compress);
    // the records are sample_active_cells' on a volume of uint8/int16/uint16/float32 values, which
    // floats hold exactly: the encoder checks their positions and takes their values from the corners
    sink.index_cells(cell_grid(in.grid()), SampleCellEncoder::Verify::position);
    const IsoSplatResult r = run_isosplat_input(in, iso, Projection::approx, sp, sink, threads, PipelineShape::samples_only);
    // a run that found an active cell has iso inside the range: the volume is not read again to say nothing
    const bool said = r.sampling.active_cells == 0 && warn_if_iso_outside(iso, in.value_range(), in.path, warn);
    if (warned) *warned = said;
    return r;
}

void print_generate_stats(std::FILE* out, const std::string& path, double iso, const IsoSplatResult& r) {
    std::fprintf(out, "generate: %s iso %g: %lld samples (active cells), %lld cells with NaN/Inf skipped, %.3f s\n",
                 terminal_safe(path).c_str(), iso, static_cast<long long>(r.sampling.active_cells),
                 static_cast<long long>(r.sampling.nonfinite_cells), r.seconds);
}

}  // namespace meshless
