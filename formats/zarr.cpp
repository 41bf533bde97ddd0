#include "formats/zarr.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <zstd.h>
#include <zstd_errors.h>
#if MESHLESS_HAVE_BLOSC
#include <blosc.h>
#endif

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <new>

#include "formats/binary_file.hpp"
#include "formats/gzip.hpp"
#include "formats/length_unit.hpp"
#include "formats/json.hpp"
#include "formats/reference_policy.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace fs = std::filesystem;

namespace {

/// The largest decoded chunk read (numcodecs' Blosc and zarr-python limit chunks to 2 GiB too).
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 31;
/// The most chunk files a store may name (a folder of more is not a store anyone wrote).
constexpr std::uint64_t kMaxChunkFiles = std::uint64_t{1} << 31;
/// .zarray and .zattrs documents larger than this are not metadata.
constexpr std::uint64_t kMaxMetadataBytes = std::uint64_t{16} << 20;

[[noreturn]] void fail(const std::string& file, const std::string& what) { throw FormatError(file + ": " + what); }

std::string list_text(const std::vector<std::int64_t>& v) {
    std::string s = "(";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    return s + (v.size() == 1 ? ",)" : ")");
}

// A JSON value as short, escaped text for messages.
std::string json_text(const Json& j) {
    switch (j.kind) {
        case Json::Kind::null: return "null";
        case Json::Kind::boolean: return j.b ? "true" : "false";
        case Json::Kind::number: return number_text(j.num);
        case Json::Kind::string: return "\"" + escape_field(j.str) + "\"";
        case Json::Kind::array: return "an array";
        case Json::Kind::object: return "an object";
    }
    return "?";
}

// An integer JSON number in [lo, hi], else FormatError naming the field.
std::int64_t integer_field(const Json& j, const std::string& file, const std::string& field, std::int64_t lo, std::int64_t hi) {
    if (!j.is_number() || !(j.num == std::floor(j.num)) || j.num < static_cast<double>(lo) || j.num > static_cast<double>(hi))
        fail(file, field + " " + json_text(j) + " is not an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
    return static_cast<std::int64_t>(j.num);
}

std::vector<std::int64_t> integer_list(const Json* j, const std::string& file, const char* field, std::int64_t lo) {
    if (!j) fail(file, std::string("missing \"") + field + "\"");
    if (!j->is_array()) fail(file, std::string("\"") + field + "\" is " + json_text(*j) + ", expected a list of integers");
    if (j->arr.size() > 32) fail(file, std::string("\"") + field + "\" lists " + std::to_string(j->arr.size()) + " axes (at most 32)");
    std::vector<std::int64_t> out;
    for (std::size_t i = 0; i < j->arr.size(); ++i)
        out.push_back(integer_field(j->arr[i], file, std::string("\"") + field + "\"[" + std::to_string(i) + "]", lo,
                                    static_cast<std::int64_t>(kMaxPayloadBytes)));
    return out;
}

// numpy dtype strings: byte order, kind, size.
StoredType parse_dtype(const Json* j, const std::string& file, bool& big_endian) {
    if (!j) fail(file, "missing \"dtype\"");
    if (!j->is_string())
        fail(file, "dtype " + json_text(*j) + " is not read (structured dtypes are not volumes; |u1 <i2 <u2 <f4 ... are)");
    const std::string& d = j->str;
    const std::string why = "dtype \"" + escape_field(d) +
                            "\" is not read (|u1 |i1 <u2 <i2 <u4 <i4 <u8 <i8 <f4 <f8 and their big-endian '>' forms are)";
    if (d.size() != 3) fail(file, why);
    const std::string kind = d.substr(1);
    StoredType t;
    if (kind == "u1") t = StoredType::u8;
    else if (kind == "i1") t = StoredType::i8;
    else if (kind == "u2") t = StoredType::u16;
    else if (kind == "i2") t = StoredType::i16;
    else if (kind == "u4") t = StoredType::u32;
    else if (kind == "i4") t = StoredType::i32;
    else if (kind == "u8") t = StoredType::u64;
    else if (kind == "i8") t = StoredType::i64;
    else if (kind == "f4") t = StoredType::f32;
    else if (kind == "f8") t = StoredType::f64;
    else fail(file, why);
    const char order = d[0];
    if (order == '|' && stored_size(t) != 1) fail(file, "dtype \"" + escape_field(d) + "\" gives no byte order ('<' or '>')");
    if (order != '|' && order != '<' && order != '>') fail(file, why);
    big_endian = order == '>';
    return t;
}

bool integer_type(StoredType t) { return t != StoredType::f32 && t != StoredType::f64; }

// The stored type's range as doubles (integers), for fill_value.
std::array<double, 2> type_range(StoredType t) {
    switch (t) {
        case StoredType::u8: return {0, 255};
        case StoredType::i8: return {-128, 127};
        case StoredType::u16: return {0, 65535};
        case StoredType::i16: return {-32768, 32767};
        case StoredType::u32: return {0, 4294967295.0};
        case StoredType::i32: return {-2147483648.0, 2147483647.0};
        case StoredType::u64: return {0, 18446744073709551615.0};
        case StoredType::i64: return {-9223372036854775808.0, 9223372036854775807.0};
        default: return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    }
}

double parse_fill(const Json* j, StoredType t, const std::string& file) {
    if (!j || j->is_null()) return 0;  // no fill value: missing chunks read as 0
    if (j->is_string() && !integer_type(t)) {
        if (j->str == "NaN") return std::numeric_limits<double>::quiet_NaN();
        if (j->str == "Infinity") return std::numeric_limits<double>::infinity();
        if (j->str == "-Infinity") return -std::numeric_limits<double>::infinity();
    }
    if (!j->is_number()) fail(file, "fill_value " + json_text(*j) + " is not a number of dtype " + to_string(t));
    const auto r = type_range(t);
    if (integer_type(t) && (j->num != std::floor(j->num) || j->num < r[0] || j->num > r[1]))
        fail(file, "fill_value " + json_text(*j) + " is not a " + to_string(t) + " value");
    if (t == StoredType::f32 && std::fabs(j->num) > std::numeric_limits<float>::max())
        fail(file, "fill_value " + json_text(*j) + " is out of float32's range");
    return j->num;
}

// One stored sample of value v in host order.
std::vector<std::byte> stored_sample(double v, StoredType t) {
    std::vector<std::byte> b(stored_size(t));
    auto put = [&](auto x) { std::memcpy(b.data(), &x, sizeof x); };
    switch (t) {
        case StoredType::u8: put(static_cast<std::uint8_t>(v)); break;
        case StoredType::i8: put(static_cast<std::int8_t>(v)); break;
        case StoredType::u16: put(static_cast<std::uint16_t>(v)); break;
        case StoredType::i16: put(static_cast<std::int16_t>(v)); break;
        case StoredType::u32: put(static_cast<std::uint32_t>(v)); break;
        case StoredType::i32: put(static_cast<std::int32_t>(v)); break;
        case StoredType::u64: put(v >= 18446744073709551615.0 ? ~std::uint64_t{0} : static_cast<std::uint64_t>(v)); break;
        case StoredType::i64: put(v >= 9223372036854775807.0 ? std::numeric_limits<std::int64_t>::max() : static_cast<std::int64_t>(v)); break;
        case StoredType::f32: put(static_cast<float>(v)); break;
        case StoredType::f64: put(v); break;
    }
    return b;
}

void parse_compressor(const Json* j, ZarrArray& a) {
    const std::string& file = a.zarray;
    if (!j || j->is_null()) {
        a.compressor = ZarrCompressor::none;
        a.compressor_text = "none";
        return;
    }
    if (!j->is_object()) fail(file, "compressor " + json_text(*j) + " is not an object or null");
    const Json* id = j->find("id");
    if (!id || !id->is_string()) fail(file, "compressor has no \"id\" string");
    auto level = [&](const char* key) {
        const Json* l = j->find(key);
        return l && l->is_number() ? " level " + number_text(l->num) : std::string();
    };
    if (id->str == "zlib") {
        a.compressor = ZarrCompressor::zlib;
        a.compressor_text = "zlib" + level("level");
    } else if (id->str == "gzip") {
        a.compressor = ZarrCompressor::gzip;
        a.compressor_text = "gzip" + level("level");
    } else if (id->str == "zstd") {
        a.compressor = ZarrCompressor::zstd;
        a.compressor_text = "zstd" + level("level");
    } else if (id->str == "blosc") {
        a.compressor = ZarrCompressor::blosc;
        const Json* c = j->find("cname");
        const Json* s = j->find("shuffle");
        a.compressor_text = "blosc";
        if (c && c->is_string()) a.compressor_text += " " + escape_field(c->str);
        a.compressor_text += level("clevel");
        if (s && s->is_number()) a.compressor_text += s->num == 1 ? " shuffle" : s->num == 2 ? " bitshuffle" : s->num == 0 ? " noshuffle" : "";
    } else {
        fail(file, "compressor \"" + escape_field(id->str) + "\" is not read (none, zlib, gzip, zstd and blosc are)");
    }
}

// A relative path of plain components (an OME-Zarr dataset path): no `..`, no absolute path.
bool plain_relative_path(const std::string& p) {
    if (p.empty() || p.size() > 255 || p.front() == '/') return false;
    std::size_t start = 0;
    while (start <= p.size()) {
        const std::size_t end = std::min(p.find('/', start), p.size());
        const std::string part = p.substr(start, end - start);
        if (part.empty() || part == "." || part == "..") return false;
        for (const char c : part)
            if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) return false;
        start = end + 1;
    }
    return true;
}

std::string read_metadata(const std::string& path) {
    const std::uint64_t size = regular_file_size(path);
    if (size > kMaxMetadataBytes)
        fail(path, std::to_string(size) + " bytes is too large for Zarr metadata (at most " + std::to_string(kMaxMetadataBytes) + ")");
    const std::vector<std::byte> b = read_file_bytes(path);
    return std::string(reinterpret_cast<const char*>(b.data()), b.size());
}

// The unit OME-Zarr axes (multiscales[0].axes: {"name", "type", "unit"}) give the spatial axes at the
// shape positions `axis` (x, y, z), when all three name the same known unit; "" otherwise (the
// axes only label the picture's scale bar: odd ones are not an error).
std::string ome_length_unit(const Json* axes, const std::array<int, 3>& axis) {
    if (!axes || !axes->is_array()) return {};
    std::string unit;
    for (int ax = 0; ax < 3; ++ax) {
        const std::size_t q = static_cast<std::size_t>(axis[ax]);
        if (q >= axes->arr.size()) return {};
        const Json* u = axes->arr[q].find("unit");
        if (!u || !u->is_string()) return {};
        const std::string one = length_unit_from_name(u->str);
        if (one.empty() || (ax > 0 && one != unit)) return {};
        unit = one;
    }
    return unit;
}

// scale and translation of a coordinateTransformations list (absent ones leave the arguments).
void transformations(const Json* list, const std::string& file, std::size_t ndim, std::vector<double>& scale,
                     std::vector<double>& translation) {
    if (!list) return;
    if (!list->is_array()) fail(file, "coordinateTransformations is " + json_text(*list) + ", expected a list");
    for (const Json& t : list->arr) {
        const Json* type = t.find("type");
        if (!type || !type->is_string()) fail(file, "a coordinateTransformation has no \"type\"");
        const bool is_scale = type->str == "scale";
        if (!is_scale && type->str != "translation") {
            if (type->str == "identity") continue;
            fail(file, "coordinateTransformation \"" + escape_field(type->str) + "\" is not read (scale and translation are)");
        }
        const Json* v = t.find(is_scale ? "scale" : "translation");
        if (!v) fail(file, std::string("a ") + (is_scale ? "scale" : "translation") + " transformation without its list (a \"path\" is not read)");
        if (!v->is_array() || v->arr.size() != ndim)
            fail(file, std::string(is_scale ? "scale" : "translation") + " does not list " + std::to_string(ndim) + " numbers, one per axis");
        std::vector<double>& dst = is_scale ? scale : translation;
        for (std::size_t i = 0; i < ndim; ++i) {
            if (!v->arr[i].is_number() || !std::isfinite(v->arr[i].num))
                fail(file, std::string(is_scale ? "scale" : "translation") + "[" + std::to_string(i) + "] " + json_text(v->arr[i]) + " is not a number");
            if (is_scale) dst[i] *= v->arr[i].num;
            else dst[i] += v->arr[i].num;
        }
    }
}

// The fill sample as a volume sample (host order).
std::vector<std::byte> fill_sample(const ZarrArray& a) {
    GridSpec one;
    one.dims = {1, 1, 1};
    const Volume v = make_volume(stored_sample(a.fill, a.type), a.type, !host_is_little_endian(), one, a.zarray);
    return std::vector<std::byte>(v.bytes.begin(), v.bytes.end());
}

bool native(StoredType t) { return t == StoredType::u8 || t == StoredType::u16 || t == StoredType::i16 || t == StoredType::f32; }

}  // namespace

ZarrArray parse_zarray(std::string_view text, const std::string& zarray) {
    const std::string& file = zarray;
    const Json doc = parse_json(text, file);
    if (!doc.is_object()) fail(file, "is not a JSON object");
    ZarrArray a;
    a.zarray = zarray;
    a.folder = parent_dir(zarray);
    const Json* fmt = doc.find("zarr_format");
    if (!fmt) fail(file, "missing \"zarr_format\"");
    if (!fmt->is_number() || fmt->num != 2) fail(file, "zarr_format " + json_text(*fmt) + " is not read (Zarr v2 stores are)");
    a.shape = integer_list(doc.find("shape"), file, "shape", 0);
    a.chunks = integer_list(doc.find("chunks"), file, "chunks", 1);
    a.type = parse_dtype(doc.find("dtype"), file, a.big_endian);
    a.dtype = escape_field(doc.find("dtype")->str);
    const std::size_t n = a.shape.size();
    if (a.chunks.size() != n)
        fail(file, "chunks " + list_text(a.chunks) + " do not have one entry per axis of shape " + list_text(a.shape));
    const Json* order = doc.find("order");
    if (!order || !order->is_string() || (order->str != "C" && order->str != "F"))
        fail(file, "order " + (order ? json_text(*order) : std::string("missing")) + " is not \"C\" or \"F\"");
    a.fortran = order->str == "F";
    // C: (..., nz, ny, nx); F: (nx, ny, nz, ...); the other axes must be of size 1
    if (n < 3) fail(file, "shape " + list_text(a.shape) + " is not a volume (a 3-D array, shape (nz, ny, nx), is)");
    for (std::size_t i = 0; i < n; ++i) {
        if (a.shape[i] == 0) fail(file, "shape " + list_text(a.shape) + " has an empty axis");
        const bool spatial = a.fortran ? i < 3 : i >= n - 3;
        if (!spatial && a.shape[i] != 1)
            fail(file, "shape " + list_text(a.shape) + " is not a volume (a 3-D array is; other axes must be of size 1)");
    }
    for (int ax = 0; ax < 3; ++ax) a.axis[ax] = a.fortran ? ax : static_cast<int>(n) - 1 - ax;
    const std::string shape_ctx = file + ": shape " + list_text(a.shape);
    std::uint64_t samples = 1, chunk_samples = 1, chunk_files = 1;
    for (std::size_t i = 0; i < n; ++i) {
        samples = checked_mul(samples, static_cast<std::uint64_t>(a.shape[i]), shape_ctx);
        chunk_samples = checked_mul(chunk_samples, static_cast<std::uint64_t>(a.chunks[i]), file + ": chunks " + list_text(a.chunks));
        chunk_files = checked_mul(chunk_files, static_cast<std::uint64_t>((a.shape[i] + a.chunks[i] - 1) / a.chunks[i]),
                                  file + ": chunk count");
    }
    (void)checked_mul(samples, stored_size(a.type), shape_ctx);
    if (chunk_files > kMaxChunkFiles)
        fail(file, "shape " + list_text(a.shape) + " in chunks " + list_text(a.chunks) + " makes " + std::to_string(chunk_files) +
                       " chunks, more than a store holds (at most 2^31)");
    a.chunk_bytes = checked_mul(chunk_samples, stored_size(a.type), file + ": chunks " + list_text(a.chunks));
    if (a.chunk_bytes > kMaxChunkBytes)
        fail(file, "chunks " + list_text(a.chunks) + " of " + std::string(to_string(a.type)) + " hold " + std::to_string(a.chunk_bytes) +
                       " bytes, more than the 2 GiB a chunk may hold");
    for (int ax = 0; ax < 3; ++ax) {
        const std::size_t p = static_cast<std::size_t>(a.axis[ax]);
        a.grid.dims[ax] = a.shape[p];
        a.chunk[ax] = a.chunks[p];
        a.count[ax] = (a.shape[p] + a.chunks[p] - 1) / a.chunks[p];
    }
    const Json* sep = doc.find("dimension_separator");
    if (sep && !sep->is_null()) {
        if (!sep->is_string() || (sep->str != "." && sep->str != "/"))
            fail(file, "dimension_separator " + json_text(*sep) + " is not \".\" or \"/\"");
        a.separator = sep->str[0];
        a.separator_given = true;
    }
    const Json* filters = doc.find("filters");
    if (filters && !filters->is_null() && !(filters->is_array() && filters->arr.empty())) {
        std::string ids;
        if (filters->is_array())
            for (const Json& f : filters->arr) {
                const Json* id = f.find("id");
                ids += (ids.empty() ? "" : ", ") + (id && id->is_string() ? "\"" + escape_field(id->str) + "\"" : json_text(f));
            }
        fail(file, "filters " + (ids.empty() ? json_text(*filters) : "[" + ids + "]") + " are not supported (only filters null is read)");
    }
    parse_compressor(doc.find("compressor"), a);
    a.fill = parse_fill(doc.find("fill_value"), a.type, file);
    validate_grid(a.grid, file);
    return a;
}

bool looks_like_zarr(const std::string& path) {
    std::error_code ec;
    const fs::path p(path);
    if (fs::is_regular_file(p, ec)) return p.filename() == ".zarray";
    if (!fs::is_directory(p, ec)) return false;
    if (fs::is_regular_file(p / ".zarray", ec) || fs::is_regular_file(p / "zarr.json", ec)) return true;
    if (!fs::is_regular_file(p / ".zattrs", ec)) return false;
    try {
        return read_file_prefix((p / ".zattrs").string(), 1 << 16).find("\"multiscales\"") != std::string::npos;
    } catch (const std::exception&) {
        return false;
    }
}

bool is_zarr_input(const std::string& path) {
    if (looks_like_zarr(path)) return true;
    std::error_code ec;
    std::string name = fs::path(path).filename().string();
    if (name.empty()) name = fs::path(path).parent_path().filename().string();  // "store.zarr/"
    return fs::is_directory(path, ec) && to_lower(name).size() > 5 && to_lower(name).ends_with(".zarr");
}

ZarrArray open_zarr(const std::string& path, const RawOptions& raw) {
    std::error_code ec;
    fs::path folder(path);
    if (fs::is_regular_file(folder, ec) && folder.filename() == ".zarray") folder = folder.parent_path();
    if (folder.empty()) folder = ".";
    const std::string f = folder.string();
    check_reference(raw.references, path, f);
    if (fs::is_regular_file(folder / "zarr.json", ec) && !fs::is_regular_file(folder / ".zarray", ec))
        fail((folder / "zarr.json").string(), "a Zarr v3 store is not read (Zarr v2 stores, with .zarray, are)");
    if (raw.spacing)
        for (int ax = 0; ax < 3; ++ax)
            if (!((*raw.spacing)[ax] > 0)) throw InvalidArgument(path + ": spacing must be > 0");
    std::vector<double> scale, translation;
    std::string level;
    fs::path array_folder = folder;
    const std::string zattrs = (folder / ".zattrs").string();
    if (!fs::is_regular_file(folder / ".zarray", ec)) {
        if (!fs::is_regular_file(zattrs, ec))
            throw IoError(f + ": not a Zarr store (no .zarray for an array, no .zattrs with multiscales for an OME-Zarr image)");
        check_reference(raw.references, f, zattrs);
        const Json attrs = parse_json(read_metadata(zattrs), zattrs);
        const Json* ms = attrs.find("multiscales");
        if (!ms) throw IoError(f + ": not a Zarr store (its .zattrs has no \"multiscales\" and there is no .zarray)");
        if (!ms->is_array() || ms->arr.empty()) fail(zattrs, "multiscales is " + json_text(*ms) + ", expected a non-empty list");
        const Json& m = ms->arr[0];
        const Json* ds = m.find("datasets");
        if (!ds || !ds->is_array() || ds->arr.empty()) fail(zattrs, "multiscales[0] has no datasets");
        const std::size_t L = static_cast<std::size_t>(raw.resolution_level);
        if (L >= ds->arr.size())
            throw InvalidArgument(f + ": resolution level " + std::to_string(L) + " asked, the image has " + std::to_string(ds->arr.size()) +
                                  " (0.." + std::to_string(ds->arr.size() - 1) + ", 0 the full resolution)");
        const Json& dataset = ds->arr[L];
        const std::string dname = "multiscales[0].datasets[" + std::to_string(L) + "]";
        const Json* p = dataset.find("path");
        if (!p || !p->is_string()) fail(zattrs, dname + " has no \"path\" string");
        if (!plain_relative_path(p->str))
            fail(zattrs, "dataset path \"" + escape_field(p->str) + "\" is not a relative path of plain names (no \"..\", no \"/\" first)");
        level = p->str;
        array_folder = folder / level;
        const std::string za = (array_folder / ".zarray").string();
        check_reference(raw.references, zattrs, za);
        if (!fs::is_regular_file(za, ec))
            throw IoError(zattrs + ": level " + std::to_string(L) + " \"" + escape_field(level) + "\" has no .zarray (" + za + ")");
        // the transformations of the level, then the multiscale's own (applied after)
        ZarrArray a = parse_zarray(read_metadata(za), za);
        const std::size_t n = a.shape.size();
        scale.assign(n, 1.0);
        translation.assign(n, 0.0);
        transformations(dataset.find("coordinateTransformations"), zattrs, n, scale, translation);
        std::vector<double> s2(n, 1.0), t2(n, 0.0);
        transformations(m.find("coordinateTransformations"), zattrs, n, s2, t2);
        const bool scaled = dataset.find("coordinateTransformations") || m.find("coordinateTransformations");
        for (std::size_t i = 0; i < n; ++i) {
            translation[i] = translation[i] * s2[i] + t2[i];
            scale[i] *= s2[i];
        }
        a.format = "ome-zarr";
        a.length_unit = ome_length_unit(m.find("axes"), a.axis);
        a.level = escape_field(level);
        a.level_index = static_cast<int>(L);
        a.level_count = static_cast<int>(ds->arr.size());
        a.zattrs = zattrs;
        a.references = raw.references;
        for (int ax = 0; ax < 3; ++ax) {
            const std::size_t q = static_cast<std::size_t>(a.axis[ax]);
            if (scaled) {
                a.grid.spacing[ax] = scale[q];
                a.grid.origin[ax] = translation[q];
            } else if (raw.spacing) {
                a.grid.spacing[ax] = (*raw.spacing)[ax];
            }
        }
        if (scaled) {
            for (int ax = 0; ax < 3; ++ax)
                if (!(a.grid.spacing[ax] > 0))
                    fail(zattrs, "scale gives axis " + std::to_string(a.axis[ax]) + " a spacing of " + number_text(a.grid.spacing[ax]) +
                                     " (must be > 0)");
        }
        if (raw.spacing && !scaled) validate_given_spacing(a.grid, zattrs);
        else validate_grid(a.grid, zattrs);
        return a;
    }
    if (raw.resolution_level != 0)
        throw InvalidArgument(f + ": a Zarr array has one resolution: --resolution-level applies to OME-Zarr images (multiscales)");
    const std::string za = (folder / ".zarray").string();
    check_reference(raw.references, f, za);
    ZarrArray a = parse_zarray(read_metadata(za), za);
    a.references = raw.references;
    if (raw.spacing) {
        a.grid.spacing = *raw.spacing;
        validate_given_spacing(a.grid, za);  // a spacing given, not read: the caller's fault
    }
    return a;
}

std::string zarr_chunk_path(const ZarrArray& a, std::int64_t ix, std::int64_t iy, std::int64_t iz) {
    std::string key;
    const std::int64_t idx[3] = {ix, iy, iz};
    for (std::size_t p = 0; p < a.shape.size(); ++p) {
        std::int64_t i = 0;
        for (int ax = 0; ax < 3; ++ax)
            if (static_cast<std::size_t>(a.axis[ax]) == p) i = idx[ax];
        if (p) key += a.separator;
        key += std::to_string(i);
    }
    return (fs::path(a.folder) / key).string();
}

void decode_zarr_chunk(const ZarrArray& a, const std::byte* data, std::size_t n, std::byte* out, const std::string& file) {
    const std::size_t want = static_cast<std::size_t>(a.chunk_bytes);
    switch (a.compressor) {
        case ZarrCompressor::none:
            if (n != want)
                fail(file, "uncompressed chunk of " + std::to_string(n) + " bytes, expected " + std::to_string(want) + " (chunks " +
                               list_text(a.chunks) + " of " + to_string(a.type) + ")");
            if (n) std::memcpy(out, data, n);
            return;
        case ZarrCompressor::zlib:
        case ZarrCompressor::gzip:
            if (want > static_cast<std::uint64_t>(n) * kMaxDeflateRatio)
                fail(file, "a " + std::to_string(n) + "-byte " + (a.compressor == ZarrCompressor::zlib ? "zlib" : "gzip") +
                               " chunk cannot hold " + std::to_string(want) + " bytes (deflate expands at most 1032:1): truncated");
            inflate_into(data, n, out, want, file);
            return;
        case ZarrCompressor::zstd: {
            const unsigned long long declared = ZSTD_getFrameContentSize(data, n);
            if (declared == ZSTD_CONTENTSIZE_ERROR) fail(file, "not a zstd frame (corrupt or truncated chunk)");
            if (declared != ZSTD_CONTENTSIZE_UNKNOWN && declared != want)
                fail(file, "zstd frame declares " + std::to_string(declared) + " bytes, a chunk holds " + std::to_string(want));
            thread_local std::unique_ptr<ZSTD_DCtx, decltype(&ZSTD_freeDCtx)> dctx(ZSTD_createDCtx(), &ZSTD_freeDCtx);
            if (!dctx) throw std::bad_alloc();
            const std::size_t r = ZSTD_decompressDCtx(dctx.get(), out, want, data, n);
            if (ZSTD_isError(r)) {
                if (ZSTD_getErrorCode(r) == ZSTD_error_dstSize_tooSmall)
                    fail(file, "zstd chunk decompresses to more than " + std::to_string(want) + " bytes");
                fail(file, std::string("corrupt or truncated zstd chunk (") + ZSTD_getErrorName(r) + ")");
            }
            if (r != want) fail(file, "zstd chunk decompresses to " + std::to_string(r) + " bytes, expected " + std::to_string(want));
            return;
        }
        case ZarrCompressor::blosc: {
#if !MESHLESS_HAVE_BLOSC
            fail(file, "a Blosc chunk, and this build has no Blosc decoder (rebuild with libblosc-dev installed)");
#else
            std::size_t declared = 0;
            if (n < BLOSC_MIN_HEADER_LENGTH || blosc_cbuffer_validate(data, n, &declared) != 0)
                fail(file, "not a valid blosc chunk (" + std::to_string(n) + " bytes: corrupt or truncated)");
            if (declared != want)
                fail(file, "blosc chunk declares " + std::to_string(declared) + " bytes, a chunk holds " + std::to_string(want));
            const int r = want ? blosc_decompress_ctx(data, out, want, 1) : 0;
            if (r < 0) fail(file, "corrupt blosc chunk (blosc error " + std::to_string(r) + ")");
            if (static_cast<std::size_t>(r) != want)
                fail(file, "blosc chunk decompresses to " + std::to_string(r) + " bytes, expected " + std::to_string(want));
            return;
#endif
        }
    }
}

// One thread's buffers: a chunk file's bytes, the decoded chunk, the chunk as volume samples.
struct ZarrChunkRows::Scratch {
    struct Buffers {
        std::vector<std::byte> packed, chunk, converted;
    };
    tbb::enumerable_thread_specific<Buffers> local;
};

ZarrChunkRows::ZarrChunkRows(ZarrArray a) : a_(std::move(a)), scratch_(std::make_unique<Scratch>()) {
    type_ = volume_type_for(a_.type);
    fill_ = fill_sample(a_);
}
ZarrChunkRows::~ZarrChunkRows() = default;
ZarrChunkRows::ZarrChunkRows(ZarrChunkRows&&) noexcept = default;

void ZarrChunkRows::read_chunk(std::int64_t ix, std::int64_t iy, std::int64_t r, std::byte* out, bool out_zeroed) {
    const std::int64_t nx = a_.grid.dims[0], ny = a_.grid.dims[1], nz = a_.grid.dims[2];
    const std::int64_t cx = a_.chunk[0], cy = a_.chunk[1], cz = a_.chunk[2];
    const std::size_t vs = sample_size(type_);
    const std::int64_t z0 = r * cz, zc = std::min(cz, nz - z0);
    const std::size_t want = static_cast<std::size_t>(a_.chunk_bytes);
    // the most a chunk file may hold: its chunk compressed by any coding we read, with overhead
    const std::uint64_t plausible = a_.chunk_bytes + a_.chunk_bytes / 128 + 1024;
    const std::int64_t x0 = ix * cx, y0 = iy * cy;
    const std::int64_t xc = std::min(cx, nx - x0), yc = std::min(cy, ny - y0);
    std::string file = zarr_chunk_path(a_, ix, iy, r);
    std::error_code ec;
    fs::file_status st = fs::status(file, ec);
    if (st.type() == fs::file_type::not_found && !a_.separator_given) {  // nested keys, the separator unnamed
        ZarrArray nested = a_;
        nested.separator = '/';
        const std::string other = zarr_chunk_path(nested, ix, iy, r);
        if (fs::status(other, ec).type() != fs::file_type::not_found) {
            file = other;
            st = fs::status(file, ec);
        }
    }
    const std::byte* samples = nullptr;  // volume samples, x fastest, chunk-sized; none: fill_value
    if (st.type() != fs::file_type::not_found) {
        Scratch::Buffers& b = scratch_->local.local();
        check_reference(a_.references, a_.zarray, file);
        const std::uint64_t size = regular_file_size(file);
        if (size > plausible)
            fail(file, "chunk file of " + std::to_string(size) + " bytes is larger than a chunk of " + std::to_string(want) +
                           " bytes compresses to (" + a_.compressor_text + ")");
        if (b.chunk.size() != want) b.chunk.resize(want);
        if (a_.compressor == ZarrCompressor::none) {
            if (size != want)
                fail(file, "uncompressed chunk of " + std::to_string(size) + " bytes, expected " + std::to_string(want) + " (chunks " +
                               list_text(a_.chunks) + " of " + to_string(a_.type) + ")");
            read_file_range_into(file, 0, size, b.chunk.data());
        } else {
            b.packed.resize(static_cast<std::size_t>(size));
            read_file_range_into(file, 0, size, b.packed.data());
            decode_zarr_chunk(a_, b.packed.data(), b.packed.size(), b.chunk.data(), file);
        }
        if (native(a_.type)) {
            if (a_.big_endian == host_is_little_endian()) byte_swap_in_place(b.chunk.data(), want, stored_size(a_.type));
            samples = b.chunk.data();
        } else {
            GridSpec g;
            g.dims = {static_cast<std::int64_t>(want / stored_size(a_.type)), 1, 1};
            const Volume v = make_volume(std::vector<std::byte>(b.chunk), a_.type, a_.big_endian, g, file);
            b.converted.assign(v.bytes.begin(), v.bytes.end());
            samples = b.converted.data();
        }
    }
    const bool zero_fill = std::all_of(fill_.begin(), fill_.end(), [](std::byte v) { return v == std::byte{0}; });
    if (!out || (!samples && out_zeroed && zero_fill)) return;
    for (std::int64_t z = 0; z < zc; ++z)
        for (std::int64_t y = 0; y < yc; ++y) {
            std::byte* dst = out + static_cast<std::size_t>(((z * ny) + y0 + y) * nx + x0) * vs;
            if (samples) {
                std::memcpy(dst, samples + static_cast<std::size_t>((z * cy + y) * cx) * vs, static_cast<std::size_t>(xc) * vs);
            } else {
                for (std::int64_t x = 0; x < xc; ++x) std::memcpy(dst + static_cast<std::size_t>(x) * vs, fill_.data(), vs);
            }
        }
}

void ZarrChunkRows::read_row(std::int64_t r, std::byte* out, bool out_zeroed) {
    if (r < 0 || r >= a_.count[2]) throw InvalidArgument(a_.folder + ": chunk row " + std::to_string(r) + " outside the array");
    const std::int64_t n = a_.count[0] * a_.count[1];
    // the chunks of the row decoded in parallel (the caller's TBB arena: --threads), each writing its
    // own part of the row; the first failing chunk in key order is reported, whatever the schedule
    std::vector<std::exception_ptr> failed(static_cast<std::size_t>(n));
    auto one = [&](std::int64_t c) {
        try {
            read_chunk(c % a_.count[0], c / a_.count[0], r, out, out_zeroed);
        } catch (...) {
            failed[static_cast<std::size_t>(c)] = std::current_exception();
        }
    };
    if (n == 1) {
        one(0);
    } else {
        tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, n, 1), [&](const tbb::blocked_range<std::int64_t>& q) {
            for (std::int64_t c = q.begin(); c < q.end(); ++c) one(c);
        });
    }
    for (const std::exception_ptr& e : failed)
        if (e) std::rethrow_exception(e);
}

Volume read_zarr(const std::string& path, const RawOptions& raw) {
    ZarrChunkRows rows(open_zarr(path, raw));
    const GridSpec& g = rows.array().grid;
    Volume v;
    v.grid = g;
    v.type = rows.type();
    // fresh zero pages: the chunks present become resident, missing chunks of fill value 0 cost nothing
    v.bytes = SampleBytes::lazy_zeroed(static_cast<std::size_t>(
        checked_mul(static_cast<std::uint64_t>(g.voxel_count()), sample_size(rows.type()), path + ": decoded size")));
    const std::size_t slice = static_cast<std::size_t>(g.dims[0] * g.dims[1]) * sample_size(rows.type());
    for (std::int64_t r = 0; r < rows.array().count[2]; ++r)
        rows.read_row(r, v.bytes.data() + static_cast<std::size_t>(r * rows.array().chunk[2]) * slice, true);
    return v;
}

VolumeInfo probe_zarr(const std::string& path, const RawOptions& raw) {
    const ZarrArray a = open_zarr(path, raw);
    VolumeInfo i;
    i.format = a.format;
    i.grid = a.grid;
    i.type = volume_type_for(a.type);
    std::string chunks = "(";
    for (std::size_t k = 0; k < a.chunks.size(); ++k) chunks += (k ? ", " : "") + std::to_string(a.chunks[k]);
    i.encoding = "Zarr v2" +
                 (a.level.empty() ? std::string()
                                  : ", level " + std::to_string(a.level_index) + " \"" + a.level + "\" of " + std::to_string(a.level_count)) +
                 ", shape " + list_text(a.shape) +
                 " order " + (a.fortran ? "F" : "C") + ", dtype " + a.dtype + ", chunks " + list_text(a.chunks) + " (" +
                 std::to_string(a.count[0] * a.count[1] * a.count[2]) + " chunk files, separator '" + a.separator +
                 "'), compressor " + a.compressor_text + ", fill_value " + number_text(a.fill);
    i.length_unit = a.length_unit;
    i.data_files = {a.zarray};
    if (!a.zattrs.empty()) i.data_files.insert(i.data_files.begin(), a.zattrs);
    return i;
}

VolumeInfo prove_zarr(const std::string& path, const RawOptions& raw) {
    ZarrChunkRows rows(open_zarr(path, raw));
    for (std::int64_t r = 0; r < rows.array().count[2]; ++r) rows.read_row(r, nullptr);
    return probe_zarr(path, raw);
}

}  // namespace meshless
