#include "formats/points_raw.hpp"

#include "kernels/checked_size.hpp"

#include <cmath>
#include <cstring>

#include "formats/binary_file.hpp"
#include "formats/npy_header.hpp"
#include "formats/stored_type.hpp"
#include "formats/text_header.hpp"

namespace meshless {

namespace {

float load_f32(const std::byte* p, bool swap) {
    std::uint32_t u;
    std::memcpy(&u, p, 4);
    if (swap) u = __builtin_bswap32(u);
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

double load_f64(const std::byte* p, bool swap) {
    std::uint64_t u;
    std::memcpy(&u, p, 8);
    if (swap) u = __builtin_bswap64(u);
    double f;
    std::memcpy(&f, &u, 8);
    return f;
}

// Byte-swapped floats get a random exponent: few land in [1e-12, 1e12], real data almost always does.
bool plausible(double v) {
    const double a = std::fabs(v);
    return std::isfinite(v) && (a == 0 || (a > 1e-12 && a < 1e12));
}

}  // namespace

PointSet read_points_raw(const std::string& path, const PointSetOptions& o, std::vector<std::string>* notes) {
    const auto bytes = read_file_bytes(path);
    if (bytes.empty()) throw FormatError(path + ": empty file (no points)");
    std::size_t fields = 4;
    if (!o.columns.empty()) {
        const std::string c = to_lower(o.columns);
        if (c == "x,y,z") fields = 3;
        else if (c != "x,y,z,value" && c != "x,y,z,v") throw FormatError(path + ": raw records are x,y,z or x,y,z,value float32 (--columns '" + o.columns + "')");
    }
    const std::size_t rec = 4 * fields;
    const std::size_t n = bytes.size() / rec;
    const std::size_t extra = bytes.size() - n * rec;
    if (extra && !o.allow_trailing)
        throw FormatError(path + ": " + std::to_string(bytes.size()) + " bytes is not a whole number of " + std::to_string(rec) +
                          "-byte float32 records (" + std::to_string(extra) + " trailing bytes; --allow-trailing ignores them)");
    if (extra && notes) notes->push_back(std::to_string(extra) + " trailing bytes ignored");
    const std::size_t nf = n * fields;
    std::size_t good[2] = {0, 0};  // [little, big]: plausible values
    std::size_t coords[2] = {0, 0}, coords_good[2] = {0, 0};  // non-zero, non-NaN x, y, z; plausible ones
    for (int order = 0; order < 2; ++order) {
        const bool swap = (order == 1) == host_is_little_endian();
        for (std::size_t i = 0; i < nf; ++i) {
            const double v = load_f32(bytes.data() + 4 * i, swap);
            const bool p = plausible(v);
            good[order] += p;
            if (i % fields < 3 && v != 0 && !std::isnan(v)) ++coords[order], coords_good[order] += p;
        }
    }
    bool big = false;
    if (o.byte_order == ByteOrder::detect) {
        big = good[1] > good[0];
        // Records, or a raw volume read without --dims? A volume's bytes read as float32 give
        // coordinates of random magnitude (uint8 CT: 11-69 % of the non-zero ones plausible in
        // either order, real records ~100 %).
        // the order with the larger plausible share of its coordinates
        const int best = static_cast<double>(coords_good[1]) * static_cast<double>(coords[0]) >
                                 static_cast<double>(coords_good[0]) * static_cast<double>(coords[1])
                             ? 1
                             : 0;
        const std::size_t nonzero = coords[best], fine = coords_good[best];
        if (nonzero >= 16 && fine < 0.9 * static_cast<double>(nonzero))
            throw FormatError(path + ": not float32 x,y,z" + (fields == 4 ? ",value" : "") + " records: " +
                              std::to_string(nonzero - fine) + " of " + std::to_string(nonzero) +
                              " non-zero coordinates are infinite, tiny (< 1e-12) or huge (> 1e12) in either byte order "
                              "(a raw volume? give --dims X,Y,Z and --type; --endian little|big reads the records as they are)");
    } else {
        big = o.byte_order == ByteOrder::big;
        const int other = big ? 0 : 1;
        if (nf && good[other] == nf && good[1 - other] * 2 < nf)
            throw FormatError(path + ": the float32 values are implausible as " + (big ? "big" : "little") +
                              "-endian; the file looks " + (big ? "little" : "big") + "-endian");
    }
    if (notes) notes->push_back(std::string("byte order: ") + (big ? "big" : "little") + " endian" +
                                (o.byte_order == ByteOrder::detect ? " (detected)" : ""));
    const bool swap = big == host_is_little_endian();
    PointSetBuilder b(path, o);
    b.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::byte* r = bytes.data() + i * rec;
        b.add(load_f32(r, swap), load_f32(r + 4, swap), load_f32(r + 8, swap), fields == 4 ? load_f32(r + 12, swap) : 0.0,
              "record", i);
    }
    return b.finish(fields == 4 ? "value" : "", fields == 4);
}

PointSet read_points_npy(const std::string& path, const PointSetOptions& o, std::vector<std::string>* notes) {
    const auto bytes = read_file_bytes(path);
    const NpyHeader hd = parse_npy_header(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), path);
    if (hd.type != StoredType::f32 && hd.type != StoredType::f64)
        throw FormatError(path + ": unsupported .npy dtype '" + escape_field(hd.descr) + "' for points (float32/float64 supported)");
    const std::size_t es = stored_size(hd.type);
    const bool big = hd.big_endian;
    const std::vector<std::int64_t>& dims = hd.shape;
    if (dims.size() != 2 || dims[1] < 3)
        throw FormatError(path + ": .npy shape " + npy_shape_text(dims) +
                          ", expected (N, 3) positions or (N, k>=4) x,y,z,value... (a 3-D array is read as a volume)");
    const auto N = static_cast<std::uint64_t>(dims[0]), K = static_cast<std::uint64_t>(dims[1]);
    const std::size_t data = static_cast<std::size_t>(hd.data_offset);
    const std::uint64_t need = checked_mul(checked_mul(N, K, path + ": .npy shape"), es, path + ": .npy shape");
    if (bytes.size() - data < need)
        throw FormatError(path + ": truncated .npy data: " + std::to_string(bytes.size() - data) + " of " + std::to_string(need) + " bytes");
    if (bytes.size() - data > need) {
        if (!o.allow_trailing)
            throw FormatError(path + ": " + std::to_string(bytes.size() - data - need) + " trailing bytes after the .npy array");
        if (notes) notes->push_back(std::to_string(bytes.size() - data - need) + " trailing bytes ignored");
    }
    const bool forder = hd.fortran_order;
    const bool has_v = K >= 4;
    std::uint64_t vc = 3;
    if (o.value_index) {
        if (*o.value_index < 0 || static_cast<std::uint64_t>(*o.value_index) >= K)
            throw FormatError(path + ": missing column " + std::to_string(*o.value_index) + " (the array has " + std::to_string(K) + ")");
        vc = static_cast<std::uint64_t>(*o.value_index);
    }
    const bool swap = big == host_is_little_endian();
    auto at = [&](std::uint64_t i, std::uint64_t c) {
        const std::uint64_t k = forder ? c * N + i : i * K + c;
        const std::byte* p = bytes.data() + data + k * es;
        return es == 4 ? static_cast<double>(load_f32(p, swap)) : load_f64(p, swap);
    };
    PointSetBuilder b(path, o);
    b.reserve(N);
    for (std::uint64_t i = 0; i < N; ++i) b.add(at(i, 0), at(i, 1), at(i, 2), has_v ? at(i, vc) : 0.0, "row", i);
    return b.finish(has_v ? "column " + std::to_string(vc) : "", has_v);
}

}  // namespace meshless
