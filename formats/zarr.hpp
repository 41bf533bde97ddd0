// Zarr v2 directory stores holding a 3-D array, read as regular volumes; OME-Zarr images (a folder
// whose .zattrs has `multiscales`) read at the dataset RawOptions::resolution_level names (0, the
// default: the full resolution; InvalidArgument beyond the image's levels, or for a plain array).
//
// Layout: a folder with `.zarray` (JSON: zarr_format 2, shape, chunks, dtype, order, fill_value,
// compressor, filters, dimension_separator) and one file per chunk, named by its chunk indices
// joined by "." ("2.0.1") or, with dimension_separator "/", nested folders ("2/0/1"; tried too for a
// chunk missing as "2.0.1" when .zarray names no separator, as NestedDirectoryStore wrote). Order "C":
// shape (nz, ny, nx), x fastest, as NumPy and Zarr store a volume; order "F": shape (nx, ny, nz),
// x fastest too (as formats/npy_volume.hpp reads Fortran .npy). Axes of size 1 before a C array's
// last three (after an F array's first three) are dropped: OME-Zarr's (t, c, z, y, x) of one time
// point and one channel is a volume. Edge chunks are stored whole (padded); a missing chunk file
// reads as fill_value (null: 0; "NaN", "Infinity", "-Infinity" for floats).
// dtypes: |u1 |i1 <u2 <i2 <u4 <i4 <u8 <i8 <f4 <f8 and their big-endian ('>') forms, converted as
// formats/stored_type.hpp says (u1, i2, u2, f4 kept). Others (float16, complex, bool, strings,
// structured) are refused, naming the dtype. Compressors: none, zlib, gzip, zstd, blosc (any of
// its internal codecs and shuffles); others, and any `filters`, are refused.
// Geometry: OME-Zarr: spacing from the dataset's `scale` coordinateTransformation times the
// multiscale's own (when present), origin from their `translation`s; otherwise RawOptions::spacing
// (default 1,1,1), origin 0.
// Memory: ZarrChunkRows decodes one z-row of chunks at a time (chunk depth cz slices), so the slab
// streamer (ooc/slice_source.hpp) holds one row, and one chunk and its compressed bytes per thread
// decoding the row's chunks (TBB, in the caller's arena).
// Hostile stores: every size is checked before anything is allocated from it (shape and chunk
// products overflow-checked; a chunk at most 2 GiB, at most 2^31 chunks; a chunk file larger
// than its chunk compresses to is refused before it is read; a deflate chunk must hold at least
// 1/1032 of its decoded size; a zstd frame's or blosc header's declared size must equal the
// chunk's; decoding never writes beyond one chunk, so a bomb stops at the chunk's size). Chunk paths are computed from chunk
// indices, never taken from the JSON; an OME-Zarr dataset `path` must be relative, without `..`
// or odd characters. RawOptions::references confines the store, its level and each chunk file.
// Throws FormatError naming the .zarray (a field and what is wrong with it, bytes from the file
// escaped by escape_field) or the chunk file (truncated, corrupt, wrong size); IoError for a
// folder that is not a Zarr store or a chunk that cannot be read. Thread-safety: reentrant; a
// ZarrChunkRows is used by one thread at a time (it runs its own parallel decode).
// Dissertation: chapter 3 input volumes (section 3.6: volumes bigger than RAM).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "formats/stored_type.hpp"
#include "formats/volume_reader.hpp"

namespace meshless {

enum class ZarrCompressor { none, zlib, gzip, zstd, blosc };

/// A Zarr v2 array as a volume: its .zarray parsed and checked.
struct ZarrArray {
    std::string folder;                  ///< the array's folder (chunk keys are relative to it)
    std::string zarray;                  ///< its .zarray (messages name it)
    std::string format = "zarr";         ///< "zarr" or "ome-zarr"
    std::string level;                   ///< OME-Zarr: the dataset path read (escaped), else empty
    int level_index = 0;                 ///< OME-Zarr: the level read (RawOptions::resolution_level; 0: full resolution)
    int level_count = 1;                 ///< OME-Zarr: the levels of its first multiscale
    std::string zattrs;                  ///< OME-Zarr: the image's .zattrs, else empty
    std::vector<std::int64_t> shape;     ///< as listed
    std::vector<std::int64_t> chunks;    ///< as listed
    std::string dtype;                   ///< as written (escaped for messages)
    StoredType type = StoredType::u8;
    bool big_endian = false;
    bool fortran = false;
    char separator = '.';
    bool separator_given = false;        ///< .zarray names dimension_separator (else "." and, for a missing chunk, "/" tried)
    ZarrCompressor compressor = ZarrCompressor::none;
    std::string compressor_text;         ///< "zstd level 3", "blosc lz4 shuffle", ...
    double fill = 0;                     ///< fill_value (null: 0)
    std::array<int, 3> axis{0, 0, 0};    ///< the shape position of x, y, z
    std::array<std::int64_t, 3> chunk{1, 1, 1};   ///< chunk samples along x, y, z
    std::array<std::int64_t, 3> count{1, 1, 1};   ///< chunks along x, y, z
    std::uint64_t chunk_bytes = 0;       ///< stored bytes of one decoded chunk (every listed axis)
    GridSpec grid;                       ///< dims x, y, z; spacing; origin
    std::string length_unit;             ///< OME-Zarr: the unit its axes give x, y and z alike (formats/length_unit.hpp), else ""
    ReferencePolicy references;
};

/// Parses and checks a .zarray document (no file is read); `zarray` names it in messages.
/// The grid's spacing is 1, origin 0.
ZarrArray parse_zarray(std::string_view text, const std::string& zarray);

/// The store at `path` (an array folder, its .zarray, or an OME-Zarr image folder: the level
/// raw.resolution_level) with its geometry (OME-Zarr scale of that level, else raw.spacing).
ZarrArray open_zarr(const std::string& path, const RawOptions& raw = {});

/// A folder holding .zarray or zarr.json, or .zattrs with "multiscales"; a file named .zarray.
/// Reads no more than .zattrs's first 64 KiB; never throws.
bool looks_like_zarr(const std::string& path);

/// looks_like_zarr, or a folder named *.zarr (read as a store, so that one without metadata is
/// named as such): what the volume dispatch (formats/volume_reader.hpp) reads as Zarr. Never throws.
bool is_zarr_input(const std::string& path);

/// The file of chunk (ix, iy, iz): indices joined by the separator, computed, never read from JSON.
std::string zarr_chunk_path(const ZarrArray& a, std::int64_t ix, std::int64_t iy, std::int64_t iz);

/// Decodes one chunk's stored bytes `data` (n bytes, from `file`) into out (a.chunk_bytes bytes,
/// the file's byte order): the compressor's checks above; FormatError naming `file`.
void decode_zarr_chunk(const ZarrArray& a, const std::byte* data, std::size_t n, std::byte* out, const std::string& file);

/// The array's chunks one z-row at a time, as volume samples (host order, x fastest).
class ZarrChunkRows {
public:
    explicit ZarrChunkRows(ZarrArray a);
    ~ZarrChunkRows();
    ZarrChunkRows(ZarrChunkRows&&) noexcept;
    const ZarrArray& array() const { return a_; }
    SampleType type() const { return type_; }
    /// Slices [r * chunk z, min(nz, (r + 1) * chunk z)) into out (nx * ny * their count samples);
    /// out == nullptr decodes and checks every chunk of the row without keeping it. `out_zeroed`:
    /// out holds zeros already, so a missing chunk whose fill_value is stored as zeros is skipped
    /// (a sparse store read into lazily committed pages costs only its chunks). The row's chunks
    /// are decoded in parallel (TBB, in the caller's arena); the first bad chunk in key order throws.
    void read_row(std::int64_t r, std::byte* out, bool out_zeroed = false);

private:
    struct Scratch;  ///< each thread's chunk buffers (TBB, kept out of this header)
    void read_chunk(std::int64_t ix, std::int64_t iy, std::int64_t r, std::byte* out, bool out_zeroed);
    ZarrArray a_;
    SampleType type_ = SampleType::u8;
    std::vector<std::byte> fill_;        ///< one volume sample of fill_value
    std::unique_ptr<Scratch> scratch_;
};

Volume read_zarr(const std::string& path, const RawOptions& raw = {});
VolumeInfo probe_zarr(const std::string& path, const RawOptions& raw = {});
/// probe_zarr, then every chunk decoded and checked, one at a time (what `meshless info` runs).
VolumeInfo prove_zarr(const std::string& path, const RawOptions& raw = {});

}  // namespace meshless
