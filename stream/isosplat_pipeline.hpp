// Paradigm (C) iso-splatting in one process (dissertation sections 3.3-3.6): CellRowSource ->
// GenerateStage -> ProjectStage -> sink, through the runner. The same stages, joined by pipes
// (meshless generate | meshless project | ...), give the same batches in the same order, hence the
// same output bytes. Throws what the sink throws (IoError, BrokenPipe).
#pragma once
#include "kernels/cell_sampling.hpp"
#include "kernels/project_sample.hpp"
#include "stream/runner.hpp"

namespace meshless {

struct IsoSplatResult {
    SamplingStats sampling;
    ProjectionStats projection;
    double seconds = 0;  ///< wall time of generate + project + sink
};

/// fused = true runs GenerateProjectStage (no SampleRecords stored); false runs GenerateStage and
/// ProjectStage as two stages, exactly as the piped commands do. Both give the same bytes.
IsoSplatResult run_isosplat(const VolumeView& v, double iso, Projection mode, const SamplingParams& sp,
                            Sink& sink, const RunOptions& opt = {}, bool fused = true);

}  // namespace meshless
