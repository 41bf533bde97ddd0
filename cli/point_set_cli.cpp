#include "cli/point_set_cli.hpp"

#include "cli/errors.hpp"

namespace meshless::cli {

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
        .option("lod-level", "", "L", "cluster trees (.mlh): the level-based level of detail at depth L (default: the finest)")
        .option("lod-error", "", "E", "cluster trees (.mlh): the error-based level of detail at error E");
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
    if (a.has("lod-level") && a.has("lod-error")) throw UsageError("--lod-level and --lod-error: give one of them");
    if (auto v = a.get("lod-level")) {
        const long long L = parse_int(*v, "--lod-level");
        if (L < 0 || L > 0xFFFFFFFFll) throw UsageError("--lod-level: expected a depth >= 0");
        o.lod_level = static_cast<std::uint32_t>(L);
    }
    if (auto v = a.get("lod-error")) {
        o.lod_error = parse_finite(*v, "--lod-error");
        if (*o.lod_error < 0) throw UsageError("--lod-error: expected a number >= 0");
    }
    return o;
}

}  // namespace meshless::cli
