// Zarr v2 stores written in tests (the layout zarr-python writes: .zarray, one file per chunk, edge
// chunks stored whole), compressed with the libraries the readers link (zlib, zstd, Blosc), so the
// Zarr readers' tests need neither Python nor zarr.
#pragma once
#include <blosc.h>
#include <zlib.h>
#include <zstd.h>

#include <array>
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace meshless::test {

/// The 13 x 11 x 9 volume the Zarr tests store: sample (i, j, k) = i + 5 j + 20 k, x fastest.
inline constexpr std::int64_t kZarrNx = 13, kZarrNy = 11, kZarrNz = 9;
inline std::vector<double> zarr_oracle_values() {
    std::vector<double> v;
    for (std::int64_t k = 0; k < kZarrNz; ++k)
        for (std::int64_t j = 0; j < kZarrNy; ++j)
            for (std::int64_t i = 0; i < kZarrNx; ++i) v.push_back(static_cast<double>(i + 5 * j + 20 * k));
    return v;
}

struct ZarrWriteOptions {
    std::array<std::int64_t, 3> chunks{8, 8, 8};  ///< along z, y, x
    std::string dtype = "|u1";                     ///< |u1 <i2 >i2 <u2 >u2 <f4 >f4 <f8 <i4 ...
    bool fortran = false;                          ///< order "F": shape (nx, ny, nz)
    std::string compressor = "none";               ///< none, zlib, gzip, zstd, blosc
    char separator = '.';
    std::string fill = "0";                        ///< fill_value as JSON text
    double fill_value = 0;                         ///< the same, as a number: chunks all of it are not written
    bool drop_fill_chunks = false;
    std::vector<std::int64_t> leading;             ///< axes of size 1 listed before (C) / after (F) the volume's
    std::string extra;                             ///< more .zarray members, e.g. "\"filters\": [{\"id\": \"delta\"}], "
};

inline void zarr_put(const std::filesystem::path& p, const std::string& bytes) {
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << bytes;
}

inline std::string slurp_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline std::string zarr_compress(const std::string& raw, const std::string& how, std::size_t typesize) {
    if (how == "none") return raw;
    if (how == "zlib" || how == "gzip") {
        z_stream z{};
        if (deflateInit2(&z, 6, Z_DEFLATED, how == "gzip" ? 31 : 15, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("deflate");
        std::string out(deflateBound(&z, raw.size()) + 32, '\0');
        z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(raw.data()));
        z.avail_in = static_cast<uInt>(raw.size());
        z.next_out = reinterpret_cast<Bytef*>(out.data());
        z.avail_out = static_cast<uInt>(out.size());
        if (deflate(&z, Z_FINISH) != Z_STREAM_END) throw std::runtime_error("deflate");
        out.resize(z.total_out);
        deflateEnd(&z);
        return out;
    }
    if (how == "zstd") {
        std::string out(ZSTD_compressBound(raw.size()), '\0');
        out.resize(ZSTD_compress(out.data(), out.size(), raw.data(), raw.size(), 3));
        return out;
    }
    if (how == "blosc") {
        std::string out(raw.size() + BLOSC_MAX_OVERHEAD, '\0');
        const int n = blosc_compress_ctx(5, 1, typesize, raw.size(), raw.data(), out.data(), out.size(), "lz4", 0, 1);
        if (n <= 0) throw std::runtime_error("blosc");
        out.resize(static_cast<std::size_t>(n));
        return out;
    }
    throw std::runtime_error("compressor " + how);
}

inline std::string zarr_compressor_json(const std::string& how) {
    if (how == "none") return "null";
    if (how == "zlib") return R"({"id": "zlib", "level": 6})";
    if (how == "gzip") return R"({"id": "gzip", "level": 6})";
    if (how == "zstd") return R"({"id": "zstd", "level": 3})";
    return R"({"blocksize": 0, "clevel": 5, "cname": "lz4", "id": "blosc", "shuffle": 1})";
}

/// One sample of value v in dtype (host is little endian).
inline std::string zarr_sample(double v, const std::string& dtype) {
    std::string b;
    auto put = [&](auto x) { b.assign(reinterpret_cast<const char*>(&x), sizeof x); };
    const std::string k = dtype.substr(1);
    if (k == "u1") put(static_cast<std::uint8_t>(v));
    else if (k == "i1") put(static_cast<std::int8_t>(v));
    else if (k == "u2") put(static_cast<std::uint16_t>(v));
    else if (k == "i2") put(static_cast<std::int16_t>(v));
    else if (k == "u4") put(static_cast<std::uint32_t>(v));
    else if (k == "i4") put(static_cast<std::int32_t>(v));
    else if (k == "f4") put(static_cast<float>(v));
    else if (k == "f8") put(v);
    else throw std::runtime_error("dtype " + dtype);
    if (dtype[0] == '>') std::reverse(b.begin(), b.end());
    return b;
}

inline std::string zarr_list(const std::vector<std::int64_t>& v) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    return s + "]";
}

/// Writes `values` (nx * ny * nz samples, x fastest) as a Zarr v2 array in folder `dir`.
inline void write_zarr(const std::filesystem::path& dir, const std::vector<double>& values, std::int64_t nx, std::int64_t ny,
                       std::int64_t nz, const ZarrWriteOptions& o = {}) {
    std::filesystem::create_directories(dir);
    const std::int64_t cz = o.chunks[0], cy = o.chunks[1], cx = o.chunks[2];
    std::vector<std::int64_t> shape, chunks;
    if (!o.fortran)
        for (std::int64_t l : o.leading) shape.push_back(l), chunks.push_back(1);
    const std::vector<std::int64_t> s3 = o.fortran ? std::vector<std::int64_t>{nx, ny, nz} : std::vector<std::int64_t>{nz, ny, nx};
    const std::vector<std::int64_t> c3 = o.fortran ? std::vector<std::int64_t>{cx, cy, cz} : std::vector<std::int64_t>{cz, cy, cx};
    shape.insert(shape.end(), s3.begin(), s3.end());
    chunks.insert(chunks.end(), c3.begin(), c3.end());
    if (o.fortran)
        for (std::int64_t l : o.leading) shape.push_back(l), chunks.push_back(1);
    zarr_put(dir / ".zarray", "{\n  \"chunks\": " + zarr_list(chunks) + ",\n  \"compressor\": " + zarr_compressor_json(o.compressor) +
                                  ",\n  \"dtype\": \"" + o.dtype + "\",\n  \"fill_value\": " + o.fill + ",\n  \"filters\": null,\n  " +
                                  o.extra + "\"order\": \"" + (o.fortran ? "F" : "C") + "\",\n  \"shape\": " + zarr_list(shape) +
                                  ",\n  \"dimension_separator\": \"" + o.separator + "\",\n  \"zarr_format\": 2\n}\n");
    const std::size_t ts = zarr_sample(0, o.dtype).size();
    for (std::int64_t iz = 0; iz * cz < nz; ++iz)
        for (std::int64_t iy = 0; iy * cy < ny; ++iy)
            for (std::int64_t ix = 0; ix * cx < nx; ++ix) {
                std::string raw;
                bool all_fill = true;
                for (std::int64_t z = 0; z < cz; ++z)
                    for (std::int64_t y = 0; y < cy; ++y)
                        for (std::int64_t x = 0; x < cx; ++x) {
                            const std::int64_t X = ix * cx + x, Y = iy * cy + y, Z = iz * cz + z;
                            const bool inside = X < nx && Y < ny && Z < nz;
                            const double v = inside ? values[static_cast<std::size_t>((Z * ny + Y) * nx + X)] : 7;  // padding
                            if (inside && v != o.fill_value) all_fill = false;
                            raw += zarr_sample(v, o.dtype);
                        }
                if (o.drop_fill_chunks && all_fill) continue;
                std::vector<std::int64_t> key;
                if (!o.fortran)
                    for (std::size_t l = 0; l < o.leading.size(); ++l) key.push_back(0);
                const std::vector<std::int64_t> k3 = o.fortran ? std::vector<std::int64_t>{ix, iy, iz} : std::vector<std::int64_t>{iz, iy, ix};
                key.insert(key.end(), k3.begin(), k3.end());
                if (o.fortran)
                    for (std::size_t l = 0; l < o.leading.size(); ++l) key.push_back(0);
                std::string name;
                for (std::size_t i = 0; i < key.size(); ++i) name += (i ? std::string(1, o.separator) : "") + std::to_string(key[i]);
                zarr_put(dir / name, zarr_compress(raw, o.compressor, ts));
            }
}

/// An OME-Zarr image folder: .zgroup, .zattrs with one multiscale whose level 0 ("0") has `scale`
/// (z, y, x order; with `translation` when given) and a level 1 that is not read.
inline void write_ome_zarr(const std::filesystem::path& dir, const std::vector<double>& values, std::int64_t nx, std::int64_t ny,
                           std::int64_t nz, const std::array<double, 3>& scale_zyx, const std::array<double, 3>& translation_zyx,
                           ZarrWriteOptions o = {}) {
    std::filesystem::create_directories(dir);
    zarr_put(dir / ".zgroup", "{\"zarr_format\": 2}\n");
    auto num = [](double v) {
        char b[64];
        std::snprintf(b, sizeof b, "%.17g", v);
        return std::string(b);
    };
    std::string lead_scale, lead_axes;
    for (std::size_t l = 0; l < o.leading.size(); ++l) {
        lead_scale += "1.0, ";
        lead_axes += l == 0 && o.leading.size() == 2 ? R"({"name": "t", "type": "time"}, )" : R"({"name": "c", "type": "channel"}, )";
    }
    const std::string s = "[" + lead_scale + num(scale_zyx[0]) + ", " + num(scale_zyx[1]) + ", " + num(scale_zyx[2]) + "]";
    std::string tr = "[";
    for (std::size_t l = 0; l < o.leading.size(); ++l) tr += "0.0, ";
    tr += num(translation_zyx[0]) + ", " + num(translation_zyx[1]) + ", " + num(translation_zyx[2]) + "]";
    zarr_put(dir / ".zattrs",
             "{\"multiscales\": [{\"version\": \"0.4\", \"name\": \"vol\", \"axes\": [" + lead_axes +
                 R"({"name": "z", "type": "space", "unit": "micrometer"}, {"name": "y", "type": "space", "unit": "micrometer"}, )" +
                 R"({"name": "x", "type": "space", "unit": "micrometer"}], "datasets": [)" +
                 R"({"path": "0", "coordinateTransformations": [{"type": "scale", "scale": )" + s +
                 R"(}, {"type": "translation", "translation": )" + tr + R"(}]}, )" +
                 R"({"path": "1", "coordinateTransformations": [{"type": "scale", "scale": [)" + lead_scale + R"(2, 2, 2]}]}]}]})" + "\n");
    write_zarr(dir / "0", values, nx, ny, nz, o);
    // level 1: a different (half-size, constant) array; level 0 must be the one read
    std::vector<double> half(static_cast<std::size_t>(((nx + 1) / 2) * ((ny + 1) / 2) * ((nz + 1) / 2)), 3);
    write_zarr(dir / "1", half, (nx + 1) / 2, (ny + 1) / 2, (nz + 1) / 2, o);
}

}  // namespace meshless::test
