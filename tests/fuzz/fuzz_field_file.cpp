// libFuzzer target for the fitted-field file codec (formats/field_file.hpp, ".mlf"): the header,
// the sections (zstd payloads, byte shuffling), the metadata and the validation of every field's
// state (kernels/field_state.hpp).
//
// Built only with Clang and -DMESHLESS_BUILD_FUZZ=ON (see fuzz_ply.cpp for the commands):
//   cmake --build build-fuzz --target fuzz_field_file
//   mkdir -p corpus-mlf && for k in rbf-grid mpu global-rbf; do for l in 0 1; do
//     build/cli/meshless fit POINTS.csv --field $k --zstd-level $l -o corpus-mlf/$k-$l.mlf; done; done
//   build-fuzz/tests/fuzz/fuzz_field_file corpus-mlf -max_total_time=60
// (seed with small point sets: a few hundred points give files of a few KB to a few hundred KB).
// The target is compiled with FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION, which makes the codec
// accept wrong checksums so that mutations reach the decoders and validators behind them.
// The only acceptable failure is FormatError; anything else (a crash, a sanitizer report, another
// exception, a hang, an allocation beyond -rss_limit_mb) is a defect. Oracle: a file that parses
// gives a field that evaluates anywhere (inside, outside, far away) without a sanitizer report.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "formats/field_file.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const FieldFile f = parse_field_file_bytes(std::span<const unsigned char>(data, size), "fuzz");
        const auto [lo, hi] = f.field->bounds();
        std::vector<Vec3> q;
        for (int i = 0; i <= 4; ++i)
            for (int j = 0; j <= 4; ++j) q.push_back(lo + Vec3{(hi.x - lo.x) * i / 4.0, (hi.y - lo.y) * j / 4.0, (hi.z - lo.z) * 0.5});
        q.push_back(lo - (hi - lo) - Vec3{1, 1, 1});
        q.push_back(Vec3{1e300, -1e300, 0});
        std::vector<double> v(q.size());
        std::vector<Vec3> g(q.size());
        f.field->evaluate(q, v, g);
        f.field->evaluate(q, v, {});
    } catch (const FormatError&) {
    }
    return 0;
}
