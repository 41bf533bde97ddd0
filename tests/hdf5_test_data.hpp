// HDF5 test files written through libhdf5's C API (the tests' writer; the product only reads):
// a dataset of the analytic oracle value(i, j, k) = (i + 5 j + 20 k) mod 113 in any integer or float type of
// either byte order, contiguous or chunked (deflate, shuffle), with geometry attributes, plus the
// defect classes the reader must refuse (external links and raw data, unavailable filters, bad
// attributes, wrong shapes and types). Only for builds with MESHLESS_WITH_HDF5.
#pragma once
#include <hdf5.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace meshless::test {

inline double hdf5_oracle(std::int64_t i, std::int64_t j, std::int64_t k) { return static_cast<double>((i + 5 * j + 20 * k) % 113); }  // fits int8

struct Hdf5WriteOptions {
    hid_t file_type = H5T_STD_U8LE;        ///< the stored type (H5T_IEEE_F64BE, H5T_STD_I16BE, ...)
    std::vector<hsize_t> chunk;            ///< empty: contiguous
    int deflate = 0;                       ///< 1-9: gzip level (chunked only)
    bool shuffle = false;
    std::vector<hsize_t> leading;          ///< leading dimensions (of size 1, or not, for must-fail files)
    std::vector<std::pair<std::string, std::vector<double>>> attributes;  ///< numeric attributes on the dataset
    std::vector<double> values;            ///< x fastest: the samples written instead of the oracle (one volume's worth)
    bool growable = false;                 ///< every dimension unlimited (chunks may then be larger than the data)
};

/// Closes an HDF5 handle at scope end.
struct H5Handle {
    hid_t id;
    herr_t (*close)(hid_t);
    ~H5Handle() {
        if (id >= 0) close(id);
    }
};

/// Writes dataset `path` (groups created as needed) of shape (leading..., nz, ny, nx) into `file`
/// (created, or opened when `append`).
inline void write_hdf5_volume(const std::string& file, const std::string& path, std::int64_t nx, std::int64_t ny, std::int64_t nz,
                              const Hdf5WriteOptions& o = {}, bool append = false) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    H5Handle f{append ? H5Fopen(file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT) : H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
               H5Fclose};
    if (f.id < 0) throw std::runtime_error("cannot create " + file);
    std::vector<hsize_t> dims = o.leading;
    dims.insert(dims.end(), {static_cast<hsize_t>(nz), static_cast<hsize_t>(ny), static_cast<hsize_t>(nx)});
    const std::vector<hsize_t> unlimited(dims.size(), H5S_UNLIMITED);
    H5Handle space{H5Screate_simple(static_cast<int>(dims.size()), dims.data(), o.growable ? unlimited.data() : nullptr), H5Sclose};
    H5Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
    H5Pset_create_intermediate_group(lcpl.id, 1);
    H5Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    if (!o.chunk.empty()) {
        H5Pset_chunk(dcpl.id, static_cast<int>(o.chunk.size()), o.chunk.data());
        if (o.shuffle) H5Pset_shuffle(dcpl.id);
        if (o.deflate) H5Pset_deflate(dcpl.id, static_cast<unsigned>(o.deflate));
    }
    H5Handle d{H5Dcreate2(f.id, path.c_str(), o.file_type, space.id, lcpl.id, dcpl.id, H5P_DEFAULT), H5Dclose};
    if (d.id < 0) throw std::runtime_error("cannot create dataset " + path);
    std::size_t n = 1;
    for (hsize_t v : dims) n *= static_cast<std::size_t>(v);
    std::vector<double> values(n);
    const std::size_t volume = static_cast<std::size_t>(nx * ny * nz);
    for (std::size_t at = 0; at < n; ++at) {
        const std::size_t v = at % volume;
        const auto i = static_cast<std::int64_t>(v % static_cast<std::size_t>(nx));
        const auto j = static_cast<std::int64_t>(v / static_cast<std::size_t>(nx) % static_cast<std::size_t>(ny));
        const auto k = static_cast<std::int64_t>(v / static_cast<std::size_t>(nx * ny));
        values[at] = o.values.empty() ? hdf5_oracle(i, j, k) : o.values[v];
    }
    if (H5Dwrite(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0)
        throw std::runtime_error("cannot write dataset " + path);
    for (const auto& [name, v] : o.attributes) {
        const hsize_t count = v.size();
        H5Handle as{H5Screate_simple(1, &count, nullptr), H5Sclose};
        H5Handle a{H5Acreate2(d.id, name.c_str(), H5T_IEEE_F64LE, as.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
        H5Awrite(a.id, H5T_NATIVE_DOUBLE, v.data());
    }
}

/// A dataset whose raw data are in an external file (H5Pset_external): must be refused.
inline void write_hdf5_external_data(const std::string& file, const std::string& data_file) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    H5Handle f{H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    const hsize_t dims[3] = {2, 2, 2};
    H5Handle space{H5Screate_simple(3, dims, nullptr), H5Sclose};
    H5Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    H5Pset_external(dcpl.id, data_file.c_str(), 0, 8);
    H5Handle d{H5Dcreate2(f.id, "/v", H5T_STD_U8LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT), H5Dclose};
}

/// A link /v to dataset /v of `target` (another file): must be refused.
inline void write_hdf5_external_link(const std::string& file, const std::string& target) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    H5Handle f{H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    H5Lcreate_external(target.c_str(), "/v", f.id, "/v", H5P_DEFAULT, H5P_DEFAULT);
}

/// A chunked dataset whose pipeline names a filter this libhdf5 lacks (Blosc's id 32001, optional).
inline void write_hdf5_unavailable_filter(const std::string& file) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    H5Handle f{H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    const hsize_t dims[3] = {2, 2, 2};
    H5Handle space{H5Screate_simple(3, dims, nullptr), H5Sclose};
    H5Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
    H5Pset_chunk(dcpl.id, 3, dims);
    H5Pset_filter(dcpl.id, 32001, H5Z_FLAG_OPTIONAL, 0, nullptr);
    H5Handle d{H5Dcreate2(f.id, "/v", H5T_STD_U8LE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT), H5Dclose};
}

/// A 2x2x2 dataset of fixed-length strings: must be refused naming the type.
inline void write_hdf5_strings(const std::string& file) {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    H5Handle f{H5Fcreate(file.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    const hsize_t dims[3] = {2, 2, 2};
    H5Handle space{H5Screate_simple(3, dims, nullptr), H5Sclose};
    H5Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
    H5Tset_size(type.id, 4);
    H5Handle d{H5Dcreate2(f.id, "/v", type.id, space.id, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
}

}  // namespace meshless::test
