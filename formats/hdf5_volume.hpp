// HDF5 datasets as regular volumes: `FILE.h5:/path/to/dataset` (or `FILE.h5` with `--array
// /path/to/dataset`, or `FILE.h5` alone when the file holds one 3-D numeric dataset).
//
// Layout: a dataset of shape (nz, ny, nx), C order, x fastest, as h5py and NumPy write a volume
// (`f.create_dataset("ct", data=vol)` with vol.shape == (nz, ny, nx)); leading dimensions of size
// 1 are dropped ((1, 1, nz, ny, nx) of one time point and one channel is a volume). Types: every
// integer of 1, 2, 4 or 8 bytes and IEEE float32/float64, of either byte order, converted by libhdf5
// into the Volume types (formats/stored_type.hpp volume_type_for: u8, i8 -> i16, u16, i16, f32).
// Storage: contiguous, compact or chunked; filtered chunks (deflate, shuffle, fletcher32: what h5py
// writes) are read as stored and decoded here, in parallel (TBB, in the caller's arena), each checked
// to decode to exactly its size (libhdf5 1.10 reads past its buffer when a chunk inflates short);
// other filters are refused. Chunks never written read as the dataset's fill value.
// Geometry: the dataset's attributes `spacing` and `origin` (three numbers each, x, y, z order, as
// the tool's --spacing), else `element_size_um` (ImageJ's and ilastik's, z, y, x order) for the
// spacing; RawOptions::spacing where the file gives none; origin 0 otherwise. Checked by
// validate_grid (finite world positions for every sample).
// Memory: Hdf5Slices reads one z-row of chunks (the chunk depth, or slabs of at most 16 MiB of a
// contiguous dataset) at a time, so the slab streamer (ooc/slice_source.hpp) holds one row.
// Hostile files: no reference leaves the file (formats/hdf5_dataset.hpp); the file itself is
// checked against RawOptions::references; sizes are checked before libhdf5 or this reader allocates
// from them (each dimension < 2^31, the voxel count by kernels/checked_size.hpp, a chunk at most
// 2 GiB decoded, the dataset's stored bytes at most the file's size, a contiguous dataset within
// the file). A deflate chunk decodes in libhdf5, whose buffer grows to what the chunk inflates to
// (at most 1032 times its stored size) before the size is checked. Throws FormatError naming "FILE:/DATASET" and what is wrong; IoError when the file
// cannot be read; InvalidArgument when the path and --array name different datasets.
// Thread-safety: reentrant; an Hdf5Slices is used by one thread at a time.
// Dissertation: chapter 3 input volumes (section 3.6: volumes bigger than RAM).
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "formats/hdf5_dataset.hpp"
#include "formats/volume_reader.hpp"

namespace meshless {

/// A path split into its HDF5 file and the dataset named after it ("" when none).
struct Hdf5Path {
    std::string file, dataset;
};

/// `path` as "FILE" or "FILE:/DATASET" when FILE is an existing regular file with the HDF5
/// signature (at byte 0, 512, 1024 or 2048) or an extension .h5, .hdf5, .he5 or .hdf; nullopt
/// otherwise. Reads at most 2,056 bytes; never throws.
std::optional<Hdf5Path> hdf5_path(const std::string& path);

/// hdf5_path(path) has a value: what the volume dispatch (formats/volume_reader.hpp) reads as HDF5.
bool is_hdf5_input(const std::string& path);

/// A dataset opened as a volume, one z-row at a time.
class Hdf5Slices {
public:
    Hdf5Slices(const std::string& path, const RawOptions& raw);
    ~Hdf5Slices();
    Hdf5Slices(Hdf5Slices&&) noexcept;
    const GridSpec& grid() const { return grid_; }
    SampleType type() const { return type_; }
    /// "FILE:/DATASET" (escaped), as messages name it.
    const std::string& name() const { return name_; }
    const Hdf5DatasetHeader& header() const { return dataset_.header(); }
    /// Slices per row: the chunk depth of a chunked dataset, else a 16 MiB slab.
    std::int64_t row_depth() const { return row_depth_; }
    /// Slices [k, k + count) into out (nx * ny * count samples, x fastest): whole rows are read in
    /// place, parts of a row through the row read last.
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out);

private:
    /// Slices [z0, z1) of one row into out (volume type): libhdf5's read of a dataset stored as it
    /// is; filtered chunks read as stored and decoded here (deflate, shuffle, fletcher32), each
    /// checked to decode to exactly its size.
    void read_row(std::int64_t z0, std::int64_t z1, std::byte* out);
    std::string file_, name_;  // set while dataset_ is constructed: declared before it
    Hdf5Dataset dataset_;
    GridSpec grid_;
    SampleType type_ = SampleType::u8;
    std::int64_t row_depth_ = 1;
    std::vector<std::byte> row_;  ///< the row read last
    std::int64_t row_index_ = -1;
};

Volume read_hdf5(const std::string& path, const RawOptions& raw = {});
/// The dataset's header and the file's 3-D datasets (VolumeInfo::arrays, by path; at most 64).
VolumeInfo probe_hdf5(const std::string& path, const RawOptions& raw = {});
/// probe_hdf5, then every row read and dropped (what `meshless info` runs).
VolumeInfo prove_hdf5(const std::string& path, const RawOptions& raw = {});

}  // namespace meshless
