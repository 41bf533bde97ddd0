// The sample stream of paradigm (C)'s first stage as its own process (dissertation section 3.4;
// `meshless generate VOLUME --iso V | meshless project | ...`): one sample per active cell of any
// volume input (stream/volume_input.hpp), written as the binary stream of formats/point_stream.hpp
// with the volume's metadata, cell-indexed (the records' positions checked against their cells),
// one DATA frame per batch, so the bytes reaching the last stage equal the in-process
// `meshless isosurface` run's. Throws what the volume input, the graph and the stream sink throw.
#pragma once
#include <vector>
#include <cstdio>
#include <string>

#include "stream/isosplat_pipeline.hpp"
#include "stream/volume_input.hpp"

namespace meshless {

/// Writes the sample stream of `in` at the isovalues `isos` (one or more, in order) to `out` (named
/// `name`; compress: zstd DATA frames; producer: the command line in the metadata) on `threads`
/// threads. Several isovalues make one segment each (formats/point_stream.hpp "Segments"), the
/// metadata listing them as isosurface's does (`isovalues`, the union of the surfaces' bounds).
/// The warning of an isovalue outside the volume's values goes to `warn` (and *warned, when given,
/// is set to whether one was written). Returns each isovalue's result.
std::vector<IsoSplatResult> generate_sample_stream(VolumeInput& in, const std::vector<double>& isos, const SamplingParams& sp,
                                                   std::FILE* out, const std::string& name, const std::string& producer,
                                                   bool compress, int threads, std::FILE* warn = stderr, bool* warned = nullptr);

/// The statistics line of generate_sample_stream (prefixed `generate: `) to `out`, one per isovalue.
void print_generate_stats(std::FILE* out, const std::string& path, const std::vector<double>& isos,
                          const std::vector<IsoSplatResult>& r);

}  // namespace meshless
