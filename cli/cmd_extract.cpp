// meshless extract vol.mls --iso V [-o FILE|-]: extraction of paradigm (A), "partial evaluation"
// (dissertation section 3.5, Table 3.1). Reads from a sample store (ooc/sample_store.hpp, made
// once by `meshless generate vol.mlb --all -o vol.mls`) the cell rows that can be active for V,
// recomputes their samples from the store's .mlb, and writes them as the same binary sample stream
// as `meshless generate vol.mlb --iso V` (same records in the same order, same META), so
// `meshless extract vol.mls --iso V | meshless project | meshless write -o out.ply` writes the
// same bytes as the paradigm (C) pipeline.
#include <unistd.h>

#include <cstdio>
#include <memory>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "cli/errors.hpp"
#include "formats/binary_stream_output.hpp"
#include "formats/atomic_file.hpp"
#include "ooc/sample_store.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/sample_store_source.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless::cli {

int cmd_extract(int argc, char** argv) {
    Args a("extract", "STORE.mls --iso V [-o FILE|-]",
           "Paradigm (A) extraction (section 3.5, Table 3.1): reads from a sample store (made once by\n"
           "`meshless generate vol.mlb --all -o vol.mls`) only the cell rows whose value interval can\n"
           "contain V (span-space index), recomputes their samples from the .mlb it refers to, and writes\n"
           "them as a sample stream for `meshless project` (the same stream as `meshless generate vol.mlb`).");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "stream output, '-' = stdout", "-")
        .flag("compress", "zstd-compress the stream's DATA frames")
        .flag("stats", "print rows, bricks and bytes read to stderr");
    add_sampling_options(a);
    a.positionals(1, 1);
    a.epilog("example: meshless extract vol.mls --iso 100.5 | meshless project | meshless write -o out.ply\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = single_iso(a, "sample streams (extract)");
    const SamplingParams sp = sampling_params(a);
    const std::string path = a.positional()[0];
    const auto store = SampleStore::open(path);
    const SampleStoreInfo& info = store->info();
    warn_if_iso_outside(iso, {info.value_lo, info.value_hi}, path);

    SampleStoreSource source(*store, iso, sp);  // reads the candidate buckets: damage shows before any output
    BinaryStreamOutput out(a.get_or("output", "-"), "a sample stream");
    StreamSink sink(out.f, out.name, RecordKind::sample, sample_store_meta(*store, iso, a.command_line()),
                    a.has("compress"));
    // the records are sample_active_cells' on the .mlb's bricks, as generate's: cell-indexed alike
    sink.index_cells(cell_grid(store->brick_store().info().grid), SampleCellEncoder::Verify::position);
    run_isosplat_sample_store(source, iso, Projection::none, sink, {1}, PipelineShape::samples_only);
    out.commit();
    if (a.has("stats")) {
        const SampleStoreStats s = store->stats();
        std::fprintf(stderr,
                     "extract: %llu active samples of %llu indexed cells; read %llu key bytes from %llu buckets, "
                     "recomputed %llu cell rows from %llu bricks\n",
                     static_cast<unsigned long long>(s.samples_emitted), static_cast<unsigned long long>(info.cells),
                     static_cast<unsigned long long>(s.key_bytes_read), static_cast<unsigned long long>(s.buckets_read),
                     static_cast<unsigned long long>(s.rows_read), static_cast<unsigned long long>(s.bricks_read));
    }
    return 0;
}

}  // namespace meshless::cli
