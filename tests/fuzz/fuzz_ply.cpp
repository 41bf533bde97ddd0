// libFuzzer target for the PLY codec (formats/ply.hpp): the header parser and the body reader.
//
// Built only with Clang and -DMESHLESS_BUILD_FUZZ=ON (GCC, the default compiler, never sees it):
//   cmake -S . -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DMESHLESS_BUILD_FUZZ=ON \
//         -DMESHLESS_BUILD_TESTS=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
//   cmake --build build-fuzz --target fuzz_ply
//   mkdir -p corpus && build-fuzz/tests/fuzz/fuzz_ply corpus -max_total_time=60
// (the libraries are instrumented with -fsanitize=fuzzer-no-link,address,undefined; seed the corpus
// with a few .ply files, e.g. `meshless demo -o corpus` and `meshless mc ... -o corpus/m.ply`).
// Each input is read as a whole PLY in memory: every element by values (fixed records, in odd-sized
// pieces), by raw copies (binary) or by records (lists), then the trailing-bytes check. The only
// acceptable failure is FormatError; anything else (a crash, a sanitizer report, another
// exception, a hang) is a defect. Oracle: a header that parses formats back to text that parses to
// the same model.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string_view>
#include <vector>

#include "formats/ply.hpp"
#include "kernels/errors.hpp"

using namespace meshless;

namespace {

bool same(const PlyHeader& a, const PlyHeader& b) {
    if (a.encoding != b.encoding || a.comments != b.comments || a.obj_info != b.obj_info ||
        a.elements.size() != b.elements.size())
        return false;
    for (std::size_t e = 0; e < a.elements.size(); ++e) {
        const PlyElement &x = a.elements[e], &y = b.elements[e];
        if (x.name != y.name || x.count != y.count || x.props.size() != y.props.size()) return false;
        for (std::size_t p = 0; p < x.props.size(); ++p)
            if (x.props[p].name != y.props[p].name || x.props[p].type != y.props[p].type ||
                x.props[p].is_list != y.props[p].is_list || (x.props[p].is_list && x.props[p].count_type != y.props[p].count_type))
                return false;
    }
    return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const PlyHeader h = parse_ply_header(text, "fuzz");
        const std::string again = format_ply_header(h, false);
        if (!same(h, parse_ply_header(again, "again"))) std::abort();
    } catch (const FormatError&) {
    }
    try {
        PlyReader r("fuzz", std::span(reinterpret_cast<const std::byte*>(data), size));
        std::vector<double> vals;
        std::vector<std::byte> raw;
        PlyRecord rec;
        bool use_raw = false;
        while (r.element() < r.header().elements.size()) {
            const PlyElement& e = r.header().elements[r.element()];
            if (e.has_lists()) {
                r.read_record(rec);
            } else if (use_raw && r.header().encoding != PlyEncoding::ascii) {
                raw.resize(5 * e.min_record_bytes());
                r.read_raw(raw.data(), 5);
            } else {
                r.read_values(vals, 7);
            }
            use_raw = !use_raw;
        }
        r.finish(size % 2 == 0);
    } catch (const FormatError&) {
    }
    return 0;
}
