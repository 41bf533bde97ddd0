// meshless extract vol.mls --iso V [-o FILE|-]: extraction of paradigm (A), "partial evaluation"
// (dissertation section 3.5, Table 3.1). Reads only the samples of a sample store
// (ooc/sample_store.hpp, made once by `meshless generate VOLUME --all -o vol.mls`) whose cell is
// active for V, and writes them as the same binary sample stream as `meshless generate`, so
// `meshless extract vol.mls --iso V | meshless project | meshless splat` works like paradigm (C).
// The stored samples carry no cell corners (corner[] = NaN; META sample_corners=none): project them
// with the approximate projection (the default).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.hpp"
#include "cli/common.hpp"
#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"
#include "ooc/sample_store.hpp"
#include "stream/runner.hpp"
#include "stream/sample_store_source.hpp"
#include "stream/stream_endpoints.hpp"

namespace meshless::cli {

namespace {

std::string triple3(double a, double b, double c) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g", a, b, c);  // as volume_meta (cli/common.cpp)
    return buf;
}

/// The META of an extracted stream: the keys of volume_meta, from the store's header.
StreamMeta store_meta(const SampleStoreInfo& info, double iso, const std::string& producer) {
    StreamMeta m;
    const GridSpec& g = info.grid;
    m.set("source", info.source);
    m.set("iso", iso);
    m.set("grid_dims", std::to_string(g.dims[0]) + "," + std::to_string(g.dims[1]) + "," + std::to_string(g.dims[2]));
    m.set("grid_origin", triple3(g.origin[0], g.origin[1], g.origin[2]));
    m.set("grid_spacing", triple3(g.spacing[0], g.spacing[1], g.spacing[2]));
    m.set("bounds_lo", triple3(g.origin[0], g.origin[1], g.origin[2]));
    m.set("bounds_hi", triple3(g.origin[0] + static_cast<double>(g.dims[0] - 1) * g.spacing[0],
                               g.origin[1] + static_cast<double>(g.dims[1] - 1) * g.spacing[1],
                               g.origin[2] + static_cast<double>(g.dims[2] - 1) * g.spacing[2]));
    m.set("value_min", info.value_lo);
    m.set("value_max", info.value_hi);
    m.set("sample_type", to_string(info.type));
    m.set("paradigm", "A");
    m.set("sample_corners", "none");
    m.set("producer", producer);
    return m;
}

}  // namespace

int cmd_extract(int argc, char** argv) {
    Args a("extract", "STORE.mls --iso V [-o FILE|-]",
           "Paradigm (A) extraction (section 3.5, Table 3.1): reads from a sample store (made once by\n"
           "`meshless generate VOLUME --all -o vol.mls`) only the samples whose cell's value interval\n"
           "contains V (span-space index), and writes them as a sample stream for `meshless project`.\n"
           "The samples carry no cell corners: use the approximate projection (the default).");
    a.option("iso", "", "V", "isovalue (required)")
        .option("output", "o", "FILE", "stream output, '-' = stdout", "-")
        .flag("compress", "zstd-compress the stream's DATA frames")
        .flag("stats", "print samples and bytes read to stderr");
    add_sampling_options(a);
    a.positionals(1, 1);
    a.epilog("example: meshless extract vol.mls --iso 100.5 | meshless project | meshless splat -o img.png\n");
    if (!a.parse(argc, argv, 2)) return 0;
    const double iso = parse_finite(a.require("iso"), "--iso");
    const SamplingParams sp = sampling_params(a);
    const std::string path = a.positional()[0];
    const auto store = SampleStore::open(path);
    const SampleStoreInfo& info = store->info();
    warn_if_iso_outside(iso, {info.value_lo, info.value_hi}, path);

    auto file = std::make_unique<AtomicFile>(a.get_or("output", "-"));
    if (file->is_stdout() && ::isatty(1))
        throw UsageError("refusing to write a binary stream to a terminal (pipe it or use -o FILE)");
    StreamSink sink(file->handle(), file->path(), RecordKind::sample, store_meta(info, iso, a.command_line()),
                    a.has("compress"));
    SampleStoreSource source(*store, iso, sp);
    run_pipeline(source, {}, sink, {1});
    file->commit();
    if (a.has("stats")) {
        const SampleStoreStats s = store->stats();
        std::fprintf(stderr, "extract: %llu of %llu stored samples active; read %llu samples (%llu bytes) from %llu buckets\n",
                     static_cast<unsigned long long>(s.samples_emitted), static_cast<unsigned long long>(info.sample_count),
                     static_cast<unsigned long long>(s.samples_read), static_cast<unsigned long long>(s.bytes_read),
                     static_cast<unsigned long long>(s.buckets_read));
    }
    return 0;
}

}  // namespace meshless::cli
