#include "formats/vtkjs_image.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "kernels/significant_text.hpp"
#include "formats/binary_file.hpp"
#include "formats/gzip.hpp"
#include "formats/json.hpp"
#include "formats/text_header.hpp"
#include "formats/reference_policy.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"
#include "kernels/flip_axes.hpp"

namespace meshless {

namespace fs = std::filesystem;

std::string vtkjs_index_path(const std::string& path) {
    std::error_code ec;
    if (fs::is_directory(path, ec)) return (fs::path(path) / "index.json").string();
    return path;
}

namespace {
// A JSON number for a message (no cast: the number may be anything).
std::string num_text(double v) { return significant_text(v, 17); }
std::vector<double> numbers(const Json* v, std::size_t n, const std::string& path, const char* what) {
    if (!v || !v->is_array() || v->arr.size() != n)
        throw FormatError(path + ": '" + what + "' must be an array of " + std::to_string(n) + " numbers");
    std::vector<double> out;
    for (const auto& e : v->arr) {
        if (!e.is_number()) throw FormatError(path + ": '" + what + "' must be an array of numbers");
        out.push_back(e.num);
    }
    return out;
}
const std::string& str(const Json* v, const std::string& path, const char* what) {
    if (!v || !v->is_string()) throw FormatError(path + ": missing string '" + what + "'");
    return v->str;
}
}  // namespace

PayloadPlan plan_vtkjs_image(const std::string& in_path, const ReferencePolicy& refs, const std::string& array) {
    const std::string path = vtkjs_index_path(in_path);
    const std::uint64_t size = regular_file_size(path);
    if (size > (64u << 20)) throw FormatError(path + ": index.json larger than 64 MiB");
    const auto bytes = read_file_bytes(path);
    const Json root = parse_json(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
    if (!root.is_object()) throw FormatError(path + ": index.json is not a JSON object");
    if (!root.find("vtkClass")) {  // another JSON document (a KVS object, a vtk.js scene, ...)
        const bool kvs = root.find("values") && (root.find("resolution") || root.find("size") || root.find("dims"));
        throw FormatError(path + ": a JSON document meshless does not read" +
                          (kvs ? std::string(" (a KVS volume object?)") : std::string()) +
                          ": the JSON volumes it reads are vtk.js images (index.json with 'vtkClass' vtkImageData);"
                          " convert it to NRRD or raw first");
    }
    const std::string& cls = str(root.find("vtkClass"), path, "vtkClass");
    if (cls != "vtkImageData") throw FormatError(path + ": unsupported vtkClass '" + escape_field(cls) + "' (vtkImageData supported)");
    PayloadPlan plan;
    plan.format = "vtkjs";
    const auto ext = numbers(root.find("extent"), 6, path, "extent");
    const Json* sp_j = root.find("spacing");
    const Json* or_j = root.find("origin");
    const auto sp = sp_j ? numbers(sp_j, 3, path, "spacing") : std::vector<double>{1, 1, 1};
    const auto org = or_j ? numbers(or_j, 3, path, "origin") : std::vector<double>{0, 0, 0};
    for (int a = 0; a < 3; ++a) {
        const double d = ext[2 * a + 1] - ext[2 * a] + 1;
        if (!(d >= 1) || d != std::floor(d) || d > static_cast<double>(kMaxPayloadBytes))
            throw FormatError(path + ": bad extent (" + std::to_string(ext[2 * a]) + ".." + std::to_string(ext[2 * a + 1]) +
                              " along axis " + std::to_string(a) + ")");
        plan.grid.dims[a] = static_cast<std::int64_t>(d);
        if (sp[a] == 0 || !std::isfinite(sp[a])) throw FormatError(path + ": bad spacing: zero or non-finite spacing");
        plan.grid.origin[a] = org[a] + ext[2 * a] * sp[a];
        honour_signed_spacing(plan.grid, plan.flip, a, sp[a]);  // negative: a flipped axis
    }
    validate_grid(plan.grid, path);
    const Json* pd = root.find("pointData");
    const Json* arrays = pd ? pd->find("arrays") : nullptr;
    if (!arrays || !arrays->is_array() || arrays->arr.empty()) throw FormatError(path + ": no pointData arrays");
    struct M { const char* n; StoredType t; };
    static constexpr M table[] = {
        {"Int8Array", StoredType::i8},    {"Uint8Array", StoredType::u8},   {"Uint8ClampedArray", StoredType::u8},
        {"Int16Array", StoredType::i16},  {"Uint16Array", StoredType::u16}, {"Int32Array", StoredType::i32},
        {"Uint32Array", StoredType::u32}, {"Float32Array", StoredType::f32}, {"Float64Array", StoredType::f64},
        {"BigInt64Array", StoredType::i64}, {"BigUint64Array", StoredType::u64}};
    // every array with 'data' listed; the default: the one registered with "setScalars", else the first
    std::vector<const Json*> datas;
    bool registered = false;
    for (const auto& a : arrays->arr) {
        const Json* d = a.find("data");
        if (!d) continue;
        const Json* ref = d->find("ref");
        const Json* reg = ref ? ref->find("registration") : nullptr;
        if (!registered && reg && reg->is_string() && reg->str == "setScalars") {
            plan.default_array = datas.size();
            registered = true;
        }
        datas.push_back(d);
        VolumeArray va;
        const Json* name = d->find("name");
        va.name = name && name->is_string() ? name->str : "";
        const Json* t = d->find("dataType");
        va.type = t && t->is_string() ? escape_field(t->str) : "?";
        for (const auto& m : table)  // the type as the other formats name it
            if (t && t->is_string() && t->str == m.n) va.type = to_string(m.t);
        const Json* n = d->find("numberOfComponents");
        va.components = !n ? 1 : n->is_number() && n->num >= 1 && n->num <= 1e9 && n->num == std::floor(n->num)
                                    ? static_cast<std::int64_t>(n->num) : 0;
        plan.arrays.push_back(std::move(va));
    }
    if (datas.empty()) throw FormatError(path + ": no pointData array with 'data'");
    plan.read_array = choose_volume_array(plan.arrays, plan.default_array, array, path);
    const Json* chosen = datas[plan.read_array];
    const Json* nc = chosen->find("numberOfComponents");
    if (nc && (!nc->is_number() || nc->num != 1))
        throw FormatError(path + ": unsupported array with " + (nc->is_number() ? num_text(nc->num) : std::string("?")) +
                          " components");
    const std::string& dt = str(chosen->find("dataType"), path, "dataType");
    bool found = false;
    for (const auto& m : table)
        if (dt == m.n) plan.type = m.t, found = true;
    if (!found) throw FormatError(path + ": unsupported dataType '" + escape_field(dt) + "'");
    if (const Json* sz = chosen->find("size"); sz && sz->is_number() && sz->num != static_cast<double>(plan.grid.voxel_count()))
        throw FormatError(path + ": array size " + num_text(sz->num) + " does not match extent " +
                          dims_string(plan.grid));
    const Json* ref = chosen->find("ref");
    if (!ref) throw FormatError(path + ": array without 'ref' (inline values are not supported)");
    const std::string& id = str(ref->find("id"), path, "ref.id");
    const Json* bp = ref->find("basepath");
    const std::string base = bp && bp->is_string() ? bp->str : "";
    if (const Json* enc = ref->find("encode"); enc && enc->is_string()) {
        if (enc->str == "BigEndian")
            plan.big_endian = true;
        else if (enc->str != "LittleEndian")
            throw FormatError(path + ": bad encode '" + escape_field(enc->str) + "'");
    }
    const fs::path dir = fs::path(path).parent_path();
    const fs::path file = dir / base / id;
    check_reference(refs, path, file.string() + ".gz");  // both candidates, before either is looked at
    check_reference(refs, path, file.string());
    std::error_code ec;
    if (fs::is_regular_file(fs::path(file.string() + ".gz"), ec)) {
        plan.files = {file.string() + ".gz"};
        plan.encoding = PayloadEncoding::gzip;
    } else if (fs::is_regular_file(file, ec)) {
        plan.files = {file.string()};
        const std::string head = read_file_prefix(file.string(), 2);
        plan.encoding = is_gzip_magic(head.data(), head.size()) ? PayloadEncoding::gzip : PayloadEncoding::raw;
        plan.exact_size = true;
    } else {
        throw IoError(path + ": cannot open the array file " + escape_field(file.string(), 256) + "(.gz)");
    }
    return plan;
}

VolumeInfo probe_vtkjs_image(const std::string& path, const ReferencePolicy& refs, const std::string& array) {
    return info_from_plan(plan_vtkjs_image(path, refs, array));
}
Volume read_vtkjs_image(const std::string& path, const ReferencePolicy& refs, const std::string& array) {
    return read_payload(plan_vtkjs_image(path, refs, array));
}

}  // namespace meshless
