// libFuzzer target for the cluster-tree file codec (formats/cluster_tree_file.hpp, ".mlh"): the
// header, the meta section, the node section and the tree validation (kernels/cluster_tree.hpp).
//
// Built only with Clang and -DMESHLESS_BUILD_FUZZ=ON (see fuzz_ply.cpp for the commands):
//   cmake --build build-fuzz --target fuzz_cluster_tree_file
//   mkdir -p corpus-mlh && for m in 0 3 40 400; do
//     build/cli/meshless hierarchy SMALL_VOLUME.raw --max-splits $m -o corpus-mlh/t$m.mlh; done
//   build-fuzz/tests/fuzz/fuzz_cluster_tree_file corpus-mlh -max_total_time=60
// Compiled with FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION, which makes the codec accept wrong
// checksums so that mutations reach the structural checks behind them. The only acceptable failure
// is FormatError. Oracle: a file that parses is a valid tree whose LODs (every level, several
// errors) can be extracted without a sanitizer report, and it re-encodes to the same bytes.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "formats/cluster_tree_file.hpp"
#include "kernels/cluster_lod.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const ClusterTree t = parse_cluster_tree_bytes(std::span<const unsigned char>(data, size), "fuzz");
        if (!validate_cluster_tree(t.nodes, t.stats.samples).empty()) __builtin_trap();
        for (std::uint32_t L = 0; L <= t.stats.depth + 1 && L < 64; ++L) (void)lod_nodes(t.nodes, LodMode::level, L);
        for (double e : {0.0, 1.0, t.nodes[0].error}) (void)lod_size_at_error(t.nodes, e);
        (void)lod_sizes_per_level(t.nodes);
        (void)cluster_tree_bytes(t);
    } catch (const FormatError&) {
    }
    return 0;
}
