// One numeric dataset of an HDF5 file, through libhdf5 (Debian libhdf5-dev, the serial thread-safe
// build): the boundary the HDF5 volume reader (formats/hdf5_volume.hpp) stands on. Only
// formats/hdf5_library.cpp includes hdf5.h; a build without libhdf5 (MESHLESS_WITH_HDF5=OFF)
// compiles formats/hdf5_unavailable.cpp instead, whose functions refuse every HDF5 input in one line.
//
// Shapes: `shape` is the dataset's dimensions as stored, slowest first (C order: a volume written by
// NumPy/h5py as (nz, ny, nx) has x fastest). Reads are hyperslabs of whole z-slices, converted by
// libhdf5 from the file's type and byte order into the host's native type asked for.
// Hostile files: every file's structure is first parsed by libhdf5 in a child process, and a file
// that makes libhdf5 crash there is refused (libhdf5 1.10 can dereference a failed allocation on a
// corrupt file); no path is followed outside the file (external links, external raw-data files and
// virtual datasets are refused before anything is read); filters libhdf5 cannot decode (Blosc, LZ4,
// ... plugins) are refused naming the filter; libhdf5's own error stack is not printed, its
// innermost message is quoted (escaped) in ours.
// Throws FormatError "FILE: WHAT" for a file libhdf5 cannot open or a dataset it cannot read;
// IoError when the file cannot be opened for reading at all.
// Thread-safety: libhdf5 serialises its calls (thread-safe build); an Hdf5Dataset is used by one
// thread at a time.
// Dissertation: none (I/O support for chapter 3 input volumes).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "formats/stored_type.hpp"
#include "kernels/grid.hpp"

namespace meshless {

/// What a dataset's header says.
struct Hdf5DatasetHeader {
    std::vector<std::int64_t> shape;                 ///< slowest first, as stored
    std::vector<std::int64_t> max_shape;             ///< the dimensions it may grow to; -1: unlimited
    std::optional<StoredType> type;                  ///< nullopt: not a type the tool reads (type_text says which)
    std::string type_text;                           ///< "uint16 little-endian", "float16", "string", ...
    std::vector<std::int64_t> chunk;                 ///< chunk dimensions, slowest first; empty unless chunked
    std::string layout;                              ///< "contiguous", "compact", "chunked"
    std::string filters;                             ///< "deflate 4, shuffle", ... ; "none"
    std::uint64_t storage_bytes = 0;                 ///< bytes the dataset takes in the file (H5Dget_storage_size)
    std::optional<std::uint64_t> data_offset;        ///< contiguous: where its bytes start in the file (nullopt: never written)
    bool big_endian = false;                         ///< the stored type's byte order
    /// The filter pipeline in writing order (H5Z ids: 1 deflate, 2 shuffle, 3 fletcher32, ...) and
    /// each filter's first parameter (deflate: the level).
    std::vector<int> filters_ids;
    /// The fill value in the stored type's bytes (what a chunk never written holds), stored_size bytes.
    std::vector<std::byte> fill;
    /// Numeric attributes of three values on the dataset, by name, as stored (no reordering).
    std::optional<std::array<double, 3>> spacing, origin, element_size_um;
};

/// True when this build reads HDF5 (libhdf5 linked).
bool hdf5_reader_available();

/// A dataset found in a file: its path ("/group/name") and its type ("uint16 little-endian").
struct Hdf5Listing {
    std::string path, type;
};

/// The numeric datasets of `file` that have three dimensions after
/// dropping leading dimensions of size 1, in the file's order, at most `limit` of them (`more` set
/// when there were more). Datasets behind external links are not visited.
std::vector<Hdf5Listing> hdf5_volume_datasets(const std::string& file, std::size_t limit, bool& more);

/// An open dataset of an open file.
class Hdf5Dataset {
public:
    /// Opens `dataset` ("/a/b") of `file`; every link on its path must be a hard or soft link of
    /// the file (an external link is refused), and its raw data must be in the file.
    Hdf5Dataset(const std::string& file, const std::string& dataset);
    /// Where the file's structure is parsed first: in a child process (the default, see
    /// hdf5_library.cpp preflight), or here only (the child itself).
    enum class Parsed { in_a_child_first, here };
    Hdf5Dataset(const std::string& file, const std::string& dataset, Parsed parsed);
    ~Hdf5Dataset();
    Hdf5Dataset(Hdf5Dataset&&) noexcept;
    Hdf5Dataset& operator=(Hdf5Dataset&&) noexcept;
    const Hdf5DatasetHeader& header() const { return header_; }
    /// The stored (filtered) bytes of the chunk whose first sample is (z, y, x) of the last three
    /// dimensions (leading ones at 0) into raw, and the mask of the filters skipped for it (bit i:
    /// filter i of the pipeline); false when the chunk was never written. FormatError when its
    /// stored size exceeds `max_bytes` (checked before it is read).
    bool read_chunk(std::int64_t z, std::int64_t y, std::int64_t x, std::uint64_t max_bytes, std::vector<std::byte>& raw,
                    unsigned& mask);
    /// Reads slices [z0, z0 + count) of the dataset's last three dimensions (the leading ones of
    /// size 1 at index 0) into out, x fastest, converted into `as` in host byte order
    /// (u8, i16, u16 or f32: the Volume types).
    void read_slices(std::int64_t z0, std::int64_t count, SampleType as, std::byte* out);

private:
    struct Handles;
    std::unique_ptr<Handles> h_;
    Hdf5DatasetHeader header_;
};

}  // namespace meshless
