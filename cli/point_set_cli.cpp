#include "cli/point_set_cli.hpp"

#include "cli/errors.hpp"

namespace meshless::cli {

std::uint64_t lod_count_arg(const std::string& v, const std::string& option) {
    const long long n = parse_int(v, option);
    if (n < 1) throw UsageError(option + ": expected a count >= 1");
    return static_cast<std::uint64_t>(n);
}

void add_point_set_options(Args& a, bool with_endian) {
    a.option("columns", "", "X,Y,Z[,V]", "point sets (text, raw): columns by header name or 0-based index")
        .option("value", "", "NAME|INDEX", "point sets: the scalar (column, PLY property, VTK array, PLOT3D q name or function variable)")
        .option("q", "", "FILE", "PLOT3D: q file (default: the xyz file's sibling, e.g. combxyz.bin -> combq.bin)")
        .option("q-component", "", "N", "PLOT3D: q component 0..4 (rho, rho u, rho v, rho w, rho E) or 5 = speed", "0")
        .validate([](const std::string& v) {
            const long long qc = parse_int(v, "--q-component");
            if (qc < 0 || qc > 5) throw UsageError("--q-component: expected 0..5, got " + v);
        })
        .option("function", "", "FILE", "PLOT3D: function file (.f) giving the values")
        .flag("allow-trailing", "point sets: ignore bytes after the data the header describes (noted)")
        .flag("strict", "point sets: refuse NaN/Inf samples (with the line) instead of dropping them")
        .flag("merge-blocks", "point sets: one block instead of one per grid/piece/file")
        .option("lod-level", "", "L", "cluster trees (.mlh): the level-based level of detail at depth L >= 0 (default: the finest)")
        .option("lod-error", "", "E", "cluster trees (.mlh): the error-based level of detail at error E >= 0")
        .option("lod-count", "", "N", "cluster trees (.mlh): the level of detail of N >= 1 points (the refinement's first N - 1 splits)")
        .option("lod-fraction", "", "F", "cluster trees (.mlh): the level of detail of F x the samples, 0 < F <= 1")
        .validate(in_range("--lod-fraction", 0, false, 1));
    if (with_endian) a.option("endian", "", "little|big", "binary point sets: byte order (default: detected)");
}

PointSetOptions point_set_options(const Args& a) {
    PointSetOptions o;
    o.columns = a.get_or("columns", "");
    if (auto v = a.get("value")) {
        bool digits = !v->empty();
        for (char c : *v) digits = digits && c >= '0' && c <= '9';
        if (digits) o.value_index = static_cast<int>(parse_int(*v, "--value"));
        else o.value_name = *v;
    }
    o.q_file = a.get_or("q", "");
    o.function_file = a.get_or("function", "");
    const long long qc = a.get_int_or("q-component", 0);
    if (qc < 0 || qc > 5) throw UsageError("--q-component: expected 0..5, got " + std::to_string(qc));
    o.q_component = static_cast<int>(qc);
    if (auto e = a.get("endian")) {
        if (*e == "little") o.byte_order = ByteOrder::little;
        else if (*e == "big") o.byte_order = ByteOrder::big;
        else throw UsageError("--endian: expected little or big, got '" + *e + "'");
    }
    o.allow_trailing = a.has("allow-trailing");
    o.strict = a.has("strict");
    o.merge_blocks = a.has("merge-blocks");
    if (int(a.has("lod-level")) + int(a.has("lod-error")) + int(a.has("lod-count")) + int(a.has("lod-fraction")) > 1)
        throw UsageError("--lod-level, --lod-error, --lod-count, --lod-fraction: give one of them");
    if (auto v = a.get("lod-level")) {
        const long long L = parse_int(*v, "--lod-level");
        if (L < 0 || L > 0xFFFFFFFFll) throw UsageError("--lod-level: expected a depth >= 0");
        o.lod_level = static_cast<std::uint32_t>(L);
    }
    if (auto v = a.get("lod-error")) {
        o.lod_error = parse_finite(*v, "--lod-error");
        if (*o.lod_error < 0) throw UsageError("--lod-error: expected a number >= 0");
    }
    if (auto v = a.get("lod-count")) o.lod_count = lod_count_arg(*v, "--lod-count");
    if (auto v = a.get("lod-fraction")) o.lod_fraction = parse_finite(*v, "--lod-fraction");
    return o;
}

}  // namespace meshless::cli
