#include "formats/hdf5_volume.hpp"

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "formats/gzip.hpp"
#include "formats/reference_policy.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace fs = std::filesystem;

namespace {

/// The most slices' bytes a row of a contiguous dataset holds.
constexpr std::uint64_t kContiguousRowBytes = std::uint64_t{16} << 20;
/// The largest decoded chunk read (as for Zarr chunks: formats/zarr.hpp).
constexpr std::uint64_t kMaxChunkBytes = std::uint64_t{1} << 31;
/// The datasets probe_hdf5 lists.
constexpr std::size_t kListedDatasets = 64;

bool has_signature(const std::string& file) {
    static constexpr char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
    std::ifstream in(file, std::ios::binary);
    if (!in) return false;
    for (std::streamoff at : {0, 512, 1024, 2048}) {
        char b[8] = {};
        in.clear();
        in.seekg(at);
        if (!in.read(b, 8)) return false;
        if (std::memcmp(b, kSignature, 8) == 0) return true;
    }
    return false;
}

bool hdf5_extension(const std::string& file) {
    std::string e = fs::path(file).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return e == ".h5" || e == ".hdf5" || e == ".he5" || e == ".hdf";
}

bool hdf5_file(const std::string& file) {
    std::error_code ec;
    return fs::is_regular_file(file, ec) && (hdf5_extension(file) || has_signature(file));
}

std::string shape_text(const std::vector<std::int64_t>& v) {
    std::string s = "(";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    return s + (v.size() == 1 ? ",)" : ")");
}

/// The dataset `path` and `raw` name: FILE:/DATASET, --array, or the file's only 3-D dataset.
std::string chosen_dataset(const Hdf5Path& p, const std::string& path, const RawOptions& raw) {
    std::string named = raw.array.empty() || raw.array[0] == '/' ? raw.array : "/" + raw.array;
    if (!p.dataset.empty()) {
        if (!named.empty() && named != p.dataset)
            throw InvalidArgument(path + " names the dataset " + escape_field(p.dataset, 120) + ", --array another (" +
                                  escape_field(named, 120) + "): give one");
        return p.dataset;
    }
    if (!named.empty()) return named;
    bool more = false;
    const std::vector<Hdf5Listing> found = hdf5_volume_datasets(p.file, kListedDatasets, more);
    if (found.size() == 1 && !more) return found[0].path;
    if (found.empty()) throw FormatError(p.file + ": no numeric dataset of 3 dimensions (a volume) in the file");
    std::string list;
    for (std::size_t i = 0; i < std::min<std::size_t>(found.size(), 8); ++i) list += (i ? ", " : "") + escape_field(found[i].path, 80);
    throw FormatError(p.file + ": holds " + std::to_string(found.size()) + (more ? " or more" : "") + " volumes (" + list +
                      (found.size() > 8 ? ", ..." : "") + "): name one as " + escape_field(p.file, 120) + ":/PATH or with --array PATH");
}

/// The H5Z filters this reader decodes itself (deflate, shuffle, fletcher32): libhdf5 1.10 copies a
/// chunk that inflates to fewer bytes than its size beyond its buffer, so no filtered chunk is left to it.
constexpr int kDeflate = 1, kShuffle = 2, kFletcher32 = 3;

/// Bytes grouped by significance (shuffle) back into elements of `size` bytes.
void unshuffle(std::vector<std::byte>& data, std::size_t size) {
    const std::size_t n = data.size() / size;
    if (size < 2 || n < 2) return;
    std::vector<std::byte> out(data.size());
    for (std::size_t b = 0; b < size; ++b)
        for (std::size_t i = 0; i < n; ++i) out[i * size + b] = data[b * n + i];
    std::copy(data.begin() + static_cast<std::ptrdiff_t>(n * size), data.end(), out.begin() + static_cast<std::ptrdiff_t>(n * size));
    data.swap(out);
}

}  // namespace

std::optional<Hdf5Path> hdf5_path(const std::string& path) {
    try {
        if (hdf5_file(path)) return Hdf5Path{path, ""};
        for (std::size_t i = path.find(":/"); i != std::string::npos; i = path.find(":/", i + 1)) {
            const std::string file = path.substr(0, i);
            if (!file.empty() && hdf5_file(file)) return Hdf5Path{file, path.substr(i + 1)};
        }
    } catch (const std::exception&) {
    }
    return std::nullopt;
}

bool is_hdf5_input(const std::string& path) { return hdf5_path(path).has_value(); }

Hdf5Slices::Hdf5Slices(const std::string& path, const RawOptions& raw)
    : dataset_([&] {
          const std::optional<Hdf5Path> p = hdf5_path(path);
          if (!p) throw FormatError(path + ": not an HDF5 file (no HDF5 signature, no .h5 or .hdf5 extension)");
          if (!hdf5_reader_available())
              throw FormatError(p->file + ": this build has no HDF5 reader (configured without libhdf5: install libhdf5-dev "
                                          "and configure with -DMESHLESS_WITH_HDF5=ON)");
          check_reference(raw.references, path, p->file);
          const std::string dataset = chosen_dataset(*p, path, raw);
          file_ = p->file;
          name_ = p->file + ":" + escape_field(dataset, 120);
          return Hdf5Dataset(p->file, dataset);
      }()) {
    const Hdf5DatasetHeader& h = dataset_.header();
    const std::vector<std::int64_t>& s = h.shape;
    bool volume = s.size() >= 3;
    for (std::size_t d = 0; volume && d + 3 < s.size(); ++d) volume = s[d] == 1;
    if (!volume) throw FormatError(name_ + ": shape " + shape_text(s) + " is not a volume (3 dimensions, z, y, x, after leading ones)");
    if (!h.type) throw FormatError(name_ + ": type " + h.type_text + " is not read (integers of 1-8 bytes, float32, float64)");
    const std::size_t r = s.size();
    grid_.dims = {s[r - 1], s[r - 2], s[r - 3]};
    for (std::int64_t n : grid_.dims)
        if (n < 2) throw FormatError(name_ + ": shape " + shape_text(s) + ": every axis needs at least 2 samples");
    if (h.spacing) {
        grid_.spacing = *h.spacing;
    } else if (h.element_size_um) {
        grid_.spacing = {(*h.element_size_um)[2], (*h.element_size_um)[1], (*h.element_size_um)[0]};
    } else if (raw.spacing) {
        grid_.spacing = *raw.spacing;
    }
    if (h.origin) grid_.origin = *h.origin;
    validate_grid(grid_, name_);
    type_ = volume_type_for(*h.type);
    const std::uint64_t stored = checked_mul(static_cast<std::uint64_t>(grid_.voxel_count()), stored_size(*h.type), name_ + ": stored size");
    const std::uint64_t slice = static_cast<std::uint64_t>(grid_.dims[0] * grid_.dims[1]) * sample_size(type_);
    // what the header claims is checked against the file before libhdf5 allocates from it: the
    // dataset's stored bytes (every chunk, compressed) fit in the file, and a chunk decodes to at
    // most kMaxChunkBytes
    std::error_code ec;
    const std::uintmax_t file_bytes = fs::file_size(file_, ec);
    if (ec || h.storage_bytes > file_bytes)
        throw FormatError(name_ + ": its storage claims " + std::to_string(h.storage_bytes) + " bytes, more than the file's " +
                          std::to_string(file_bytes) + ": truncated or corrupt");
    if (!h.chunk.empty()) {
        std::uint64_t chunk_bytes = stored_size(*h.type);
        for (std::int64_t c : h.chunk) {
            if (c < 1) throw FormatError(name_ + ": chunk " + shape_text(h.chunk) + " has an empty dimension");
            chunk_bytes = checked_mul(chunk_bytes, static_cast<std::uint64_t>(c), name_ + ": chunk size");
        }
        if (chunk_bytes > kMaxChunkBytes)
            throw FormatError(name_ + ": chunk " + shape_text(h.chunk) + " of " + std::to_string(chunk_bytes) + " bytes, more than " +
                              std::to_string(kMaxChunkBytes >> 20) + " MiB");
    }
    for (int id : h.filters_ids)
        if (id != kDeflate && id != kShuffle && id != kFletcher32)
            throw FormatError(name_ + ": filters " + h.filters + ": only deflate, shuffle and fletcher32 are read (rewrite it with "
                                      "h5repack -f GZIP=4)");
    // HDF5 itself never writes a chunk larger than a fixed dimension (only a growable one)
    for (std::size_t d = 0; h.layout == "chunked" && d < r; ++d)
        if (h.max_shape.size() == r && h.max_shape[d] >= 0 && h.chunk[d] > h.max_shape[d])
            throw FormatError(name_ + ": chunk " + shape_text(h.chunk) + " is larger than the dataset " + shape_text(s) +
                              " along a dimension that cannot grow: corrupt");
    if (h.layout == "contiguous") {
        // the dataset's bytes lie within the file (or were never written: fill values)
        if (h.storage_bytes != 0 && h.storage_bytes != stored)
            throw FormatError(name_ + ": its storage holds " + std::to_string(h.storage_bytes) + " bytes, its shape and type need " +
                              std::to_string(stored));
        if (h.data_offset && (ec || *h.data_offset > file_bytes || h.storage_bytes > file_bytes - *h.data_offset))
            throw FormatError(name_ + ": its " + std::to_string(h.storage_bytes) + " bytes at offset " + std::to_string(*h.data_offset) +
                              " lie beyond the end of the file (" + std::to_string(file_bytes) + " bytes): truncated");
        row_depth_ = std::clamp<std::int64_t>(static_cast<std::int64_t>(kContiguousRowBytes / std::max<std::uint64_t>(slice, 1)), 1, grid_.dims[2]);
    } else if (h.layout == "chunked") {
        row_depth_ = std::clamp<std::int64_t>(h.chunk[r - 3], 1, grid_.dims[2]);
    } else {
        row_depth_ = grid_.dims[2];  // compact: at most 64 KiB in the header
    }
}

Hdf5Slices::~Hdf5Slices() = default;
Hdf5Slices::Hdf5Slices(Hdf5Slices&&) noexcept = default;

void Hdf5Slices::read_slices(std::int64_t k, std::int64_t count, std::byte* out) {
    if (k < 0 || count < 0 || k + count > grid_.dims[2])
        throw InvalidArgument(name_ + ": slices " + std::to_string(k) + " + " + std::to_string(count) + " outside 0.." +
                              std::to_string(grid_.dims[2]));
    const std::size_t slice = static_cast<std::size_t>(grid_.dims[0] * grid_.dims[1]) * sample_size(type_);
    for (std::int64_t s = k; s < k + count;) {
        const std::int64_t r = s / row_depth_, z0 = r * row_depth_, z1 = std::min(grid_.dims[2], z0 + row_depth_);
        const std::int64_t take = std::min(k + count, z1) - s;
        std::byte* dst = out + static_cast<std::size_t>(s - k) * slice;
        if (s == z0 && take == z1 - z0) {
            read_row(z0, z1, dst);
        } else {
            if (row_index_ != r) {
                row_.resize(static_cast<std::size_t>(z1 - z0) * slice);
                row_index_ = -1;
                read_row(z0, z1, row_.data());
                row_index_ = r;
            }
            std::memcpy(dst, row_.data() + static_cast<std::size_t>(s - z0) * slice, static_cast<std::size_t>(take) * slice);
        }
        s += take;
    }
}

void Hdf5Slices::read_row(std::int64_t z0, std::int64_t z1, std::byte* out) {
    const Hdf5DatasetHeader& h = dataset_.header();
    if (h.filters_ids.empty()) {  // stored as it is: libhdf5 reads and converts the slices
        dataset_.read_slices(z0, z1 - z0, type_, out);
        return;
    }
    // filtered chunks (see kDeflate): their stored bytes read one after another (libhdf5 serialises
    // its calls), then decoded in parallel (TBB, in the caller's arena) into the row in the stored
    // type, which is the output itself when the stored type is the volume's in host order
    const std::size_t r = h.shape.size(), es = stored_size(*h.type);
    const std::int64_t cz = h.chunk[r - 3], cy = h.chunk[r - 2], cx = h.chunk[r - 1];
    const std::int64_t nx = grid_.dims[0], ny = grid_.dims[1], depth = z1 - z0;
    const std::size_t chunk_bytes = static_cast<std::size_t>(cz * cy * cx) * es;
    const StoredType t = *h.type;  // kept as it is stored (formats/stored_type.hpp): u8, i16, u16, f32
    const bool native = t == StoredType::u8 || t == StoredType::i16 || t == StoredType::u16 || t == StoredType::f32;
    const bool in_place = native && (es == 1 || h.big_endian != host_is_little_endian());
    std::vector<std::byte> converted;
    if (!in_place) converted.resize(static_cast<std::size_t>(nx * ny * depth) * es);
    std::byte* stored = in_place ? out : converted.data();
    struct Chunk {
        std::int64_t y0, x0;
        bool present;
        unsigned mask;
        std::vector<std::byte> raw;
    };
    std::vector<Chunk> chunks;
    for (std::int64_t y0 = 0; y0 < ny; y0 += cy)
        for (std::int64_t x0 = 0; x0 < nx; x0 += cx) {
            Chunk c{y0, x0, false, 0, {}};
            c.present = dataset_.read_chunk(z0, y0, x0, std::min<std::uint64_t>(chunk_bytes * kMaxDeflateRatio + 64, kMaxChunkBytes),
                                            c.raw, c.mask);
            chunks.push_back(std::move(c));
        }
    std::vector<std::exception_ptr> failed(chunks.size());
    auto one = [&](std::size_t i) {
        try {
            Chunk& c = chunks[i];
            const std::string at = name_ + ": chunk at (" + std::to_string(z0) + ", " + std::to_string(c.y0) + ", " + std::to_string(c.x0) + ")";
            std::vector<std::byte> chunk;
            if (!c.present) {
                chunk.resize(chunk_bytes);
                for (std::size_t k = 0; k < chunk_bytes; k += es) std::memcpy(chunk.data() + k, h.fill.data(), es);
            } else {
                chunk.swap(c.raw);
                for (std::size_t f = h.filters_ids.size(); f-- > 0;) {
                    if (c.mask & (1u << f)) continue;  // skipped for this chunk when it was written
                    switch (h.filters_ids[f]) {
                        case kFletcher32:  // the checksum's 4 bytes at the end (not verified)
                            if (chunk.size() < 4) throw FormatError(at + ": shorter than its fletcher32 checksum");
                            chunk.resize(chunk.size() - 4);
                            break;
                        case kDeflate: {
                            if (chunk_bytes > chunk.size() * kMaxDeflateRatio)
                                throw FormatError(at + ": " + std::to_string(chunk.size()) + " deflated bytes cannot hold " +
                                                  std::to_string(chunk_bytes) + " (deflate expands at most 1032:1): truncated");
                            std::vector<std::byte> inflated(chunk_bytes);
                            inflate_into(chunk.data(), chunk.size(), inflated.data(), chunk_bytes, at);
                            chunk.swap(inflated);
                            break;
                        }
                        case kShuffle: unshuffle(chunk, es); break;
                    }
                }
                if (chunk.size() != chunk_bytes)
                    throw FormatError(at + ": decodes to " + std::to_string(chunk.size()) + " bytes, expected " + std::to_string(chunk_bytes));
            }
            // the chunk's part inside the dataset and these slices (chunk: z, y, x with x fastest)
            const std::int64_t wy = std::min(cy, ny - c.y0), wx = std::min(cx, nx - c.x0), wz = std::min(cz, depth);
            for (std::int64_t k = 0; k < wz; ++k)
                for (std::int64_t j = 0; j < wy; ++j)
                    std::memcpy(stored + static_cast<std::size_t>(((k * ny) + c.y0 + j) * nx + c.x0) * es,
                                chunk.data() + static_cast<std::size_t>((k * cy + j) * cx) * es, static_cast<std::size_t>(wx) * es);
        } catch (...) {
            failed[i] = std::current_exception();
        }
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks.size(), 1), [&](const tbb::blocked_range<std::size_t>& q) {
        for (std::size_t i = q.begin(); i < q.end(); ++i) one(i);
    });
    for (const std::exception_ptr& e : failed)  // the first bad chunk in the row's order
        if (e) std::rethrow_exception(e);
    if (in_place) return;
    GridSpec g = grid_;
    g.dims[2] = depth;
    const Volume v = make_volume(SampleBytes(std::move(converted)), *h.type, h.big_endian, g, name_);
    std::memcpy(out, v.bytes.data(), v.bytes.size());
}

Volume read_hdf5(const std::string& path, const RawOptions& raw) {
    Hdf5Slices slices(path, raw);
    Volume v;
    v.grid = slices.grid();
    v.type = slices.type();
    // fresh zero pages, written row by row
    v.bytes = SampleBytes::lazy_zeroed(static_cast<std::size_t>(
        checked_mul(static_cast<std::uint64_t>(v.grid.voxel_count()), sample_size(v.type), slices.name() + ": decoded size")));
    const std::size_t slice = static_cast<std::size_t>(v.grid.dims[0] * v.grid.dims[1]) * sample_size(v.type);
    for (std::int64_t z = 0; z < v.grid.dims[2]; z += slices.row_depth()) {
        const std::int64_t n = std::min(slices.row_depth(), v.grid.dims[2] - z);
        slices.read_slices(z, n, v.bytes.data() + static_cast<std::size_t>(z) * slice);
    }
    return v;
}

VolumeInfo probe_hdf5(const std::string& path, const RawOptions& raw) {
    const Hdf5Slices slices(path, raw);
    const Hdf5DatasetHeader& h = slices.header();
    VolumeInfo i;
    i.format = "hdf5";
    i.grid = slices.grid();
    i.type = slices.type();
    i.encoding = "HDF5 dataset " + slices.name().substr(slices.name().find(':') + 1) + ", shape " + shape_text(h.shape) + " " +
                 h.type_text + ", " + h.layout + (h.chunk.empty() ? std::string() : " " + shape_text(h.chunk)) + ", filters " + h.filters +
                 ", " + std::to_string(h.storage_bytes) + " bytes stored";
    const std::string file = slices.name().substr(0, slices.name().find(':'));
    i.data_files = {file};
    bool more = false;
    const std::string read = slices.name().substr(slices.name().find(':') + 1);
    for (const Hdf5Listing& d : hdf5_volume_datasets(file, kListedDatasets, more)) {
        if (escape_field(d.path, 120) == read) i.read_array = i.arrays.size();
        i.arrays.push_back(VolumeArray{d.path, d.type, 1});
    }
    i.default_array = i.read_array;
    return i;
}

VolumeInfo prove_hdf5(const std::string& path, const RawOptions& raw) {
    VolumeInfo i = probe_hdf5(path, raw);
    Hdf5Slices slices(path, raw);
    const std::size_t slice = static_cast<std::size_t>(i.grid.dims[0] * i.grid.dims[1]) * sample_size(i.type);
    std::vector<std::byte> row(static_cast<std::size_t>(slices.row_depth()) * slice);
    for (std::int64_t z = 0; z < i.grid.dims[2]; z += slices.row_depth())
        slices.read_slices(z, std::min(slices.row_depth(), i.grid.dims[2] - z), row.data());
    return i;
}

}  // namespace meshless
