#include "formats/vtp_writer.hpp"

#include "formats/vtk_xml_output.hpp"

#include "formats/temporary_files.hpp"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <thread>

#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

static_assert(std::endian::native == std::endian::little, "the VTP writer writes host-order (little endian) data");

/// Blocks compressed together: the threads that compress them (2..16).
std::size_t drain_blocks() { return std::clamp<std::size_t>(std::thread::hardware_concurrency(), 2, 16); }

/// A zlib compressor reused across blocks (deflateReset): a fresh deflateInit per block would
/// allocate and clear ~300 KiB of state each time. One z_stream per strategy; not movable (zlib's
/// state points back to its z_stream), so held by unique_ptr.
class Deflater {
public:
    Deflater() = default;
    Deflater(const Deflater&) = delete;
    Deflater& operator=(const Deflater&) = delete;
    ~Deflater() {
        for (int k = 0; k < 2; ++k)
            if (init_[k]) deflateEnd(&z_[k]);
    }
    /// Compresses [in, in+n) into out (cap >= compressBound(n)); returns Z_OK and sets out_n.
    int compress(const unsigned char* in, std::size_t n, unsigned char* out, std::size_t cap, std::size_t& out_n, int level,
                 bool huffman_only) {
        const int k = huffman_only ? 1 : 0;
        z_stream& z = z_[k];
        if (!init_[k]) {
            const int rc = deflateInit2(&z, level, Z_DEFLATED, 15, 8, huffman_only ? Z_HUFFMAN_ONLY : Z_DEFAULT_STRATEGY);
            if (rc != Z_OK) return rc;
            init_[k] = true;
        } else if (const int rc = deflateReset(&z); rc != Z_OK) {
            return rc;
        }
        z.next_in = const_cast<unsigned char*>(in);
        z.avail_in = static_cast<uInt>(n);
        z.next_out = out;
        z.avail_out = static_cast<uInt>(cap);
        const int rc = deflate(&z, Z_FINISH);
        out_n = cap - z.avail_out;
        return rc == Z_STREAM_END ? Z_OK : (rc == Z_OK ? Z_BUF_ERROR : rc);
    }

private:
    z_stream z_[2]{};
    bool init_[2]{false, false};
};
/// The compressors of one writer: one per thread, at most `threads` threads.
struct Deflaters {
    std::vector<std::unique_ptr<Deflater>> d;
    std::size_t threads = 1;
    explicit Deflaters(int t)
        : threads(t > 0 ? static_cast<std::size_t>(t) : std::max<std::size_t>(1, std::thread::hardware_concurrency())) {}
};

/// One DataArray on its way to the appended section: compressed block by block into an unlinked
/// temporary file, with the table of compressed sizes kept for the header.
class ArraySpool {
public:
    /// may_skip_matching: float geometry (positions, normals), where zlib's string matching often
    /// finds almost nothing (2% of the size of projected isosurface points) at 3x the time of
    /// Huffman coding alone (Z_HUFFMAN_ONLY), but much on grid-aligned data (marching-cubes
    /// vertices). Probe blocks decide (is_probe). Other arrays (constants,
    /// index sequences, ids) always use the default strategy.
    ArraySpool(std::string name, std::string type, int components, const VtpOptions& o, bool may_skip_matching = false)
        : name_(std::move(name)), type_(std::move(type)), components_(components), o_(o), may_skip_(may_skip_matching) {
        if (o_.block_size == 0 || o_.block_size > (std::size_t{1} << 30)) throw std::invalid_argument("VTP writer: bad block size");
        f_ = unlinked_temporary("vtp-" + name_, spool_name_);
    }
    ~ArraySpool() {
        if (f_) std::fclose(f_);
    }
    ArraySpool(const ArraySpool&) = delete;
    ArraySpool& operator=(const ArraySpool&) = delete;

    /// Copies bytes into the current raw block; full blocks wait in the queue for drain().
    void append(const void* data, std::size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        while (n > 0) {
            if (queue_.empty() || queue_.back().raw.size() == o_.block_size) {
                if (spare_.empty()) {
                    queue_.emplace_back();
                    queue_.back().raw.reserve(o_.block_size);
                } else {
                    queue_.push_back(std::move(spare_.back()));
                    spare_.pop_back();
                    queue_.back().raw.clear();
                    queue_.back().done = false;
                }
            }
            std::vector<unsigned char>& raw = queue_.back().raw;
            const std::size_t take = std::min(n, o_.block_size - raw.size());
            raw.insert(raw.end(), p, p + take);
            p += take;
            n -= take;
        }
    }
    /// The full blocks waiting to be compressed (all but a partial last one unless `all`).
    std::size_t ready(bool all) const {
        if (queue_.empty()) return 0;
        return queue_.size() - (!all && queue_.back().raw.size() < o_.block_size ? 1 : 0);
    }
    /// Every kProbeEvery-th block of an array that may skip matching (block index 0, 8, 16, ...)
    /// is a probe: compressed both ways, it keeps Huffman-only coding when that is within 3% of
    /// the default strategy's size, and the blocks up to the next probe use the same choice.
    /// Deterministic: depends on the data only (blocks are fixed raw byte ranges).
    static constexpr std::uint64_t kProbeEvery = 8;
    bool is_probe(std::size_t i) const {
        return may_skip_ && o_.compression == VtpCompression::zlib && (csizes_.size() + i) % kProbeEvery == 0;
    }
    /// Compresses probe block i both ways (serially, before the blocks that follow it), keeps the
    /// chosen result and records the choice for them.
    void compress_probe(std::size_t i, Deflater& d) {
        Block& b = queue_[i];
        const uLong cap = compressBound(static_cast<uLong>(b.raw.size()));
        if (b.packed.size() < cap) b.packed.resize(cap);
        probe_out_.resize(cap);
        std::size_t huffman = 0;
        b.rc = d.compress(b.raw.data(), b.raw.size(), b.packed.data(), cap, b.packed_size, o_.zlib_level, false);
        if (b.rc != Z_OK) return;
        b.rc = d.compress(b.raw.data(), b.raw.size(), probe_out_.data(), cap, huffman, o_.zlib_level, true);
        entropy_only_ = static_cast<double>(huffman) <= 1.03 * static_cast<double>(b.packed_size);
        if (entropy_only_) {
            std::swap(b.packed, probe_out_);
            b.packed_size = huffman;
        }
        b.done = true;
    }
    /// Marks block i (not a probe) with the current choice (the last probe's).
    void assign_strategy(std::size_t i) { queue_[i].huffman_only = entropy_only_; }
    /// Block i of the queue (i < ready()): compresses it into its `packed` with its strategy
    /// (thread-safe across distinct blocks); probes are already done.
    void compress(std::size_t i, Deflater& d) {
        Block& b = queue_[i];
        if (o_.compression != VtpCompression::zlib || b.done) return;
        const uLong cap = compressBound(static_cast<uLong>(b.raw.size()));
        if (b.packed.size() < cap) b.packed.resize(cap);  // recycled blocks keep their buffers
        b.rc = d.compress(b.raw.data(), b.raw.size(), b.packed.data(), cap, b.packed_size, o_.zlib_level, b.huffman_only);
    }
    /// Writes the first k blocks (compressed by compress()) to the spool, in order.
    void write_ready(std::size_t k) {
        for (std::size_t i = 0; i < k; ++i) {
            Block& b = queue_[i];
            if (b.rc != Z_OK) throw IoError(spool_name_ + ": zlib compression failed (code " + std::to_string(b.rc) + ")");
            raw_bytes_ += b.raw.size();
            const bool z = o_.compression == VtpCompression::zlib;
            const unsigned char* out = z ? b.packed.data() : b.raw.data();
            const std::size_t n = z ? b.packed_size : b.raw.size();
            if (z) csizes_.push_back(n);
            errno = 0;
            if (std::fwrite(out, 1, n, f_) != n) fail("write to");
            data_bytes_ += n;
        }
        // keep a few emptied blocks for reuse (no fresh pages, no zero-filling per block)
        for (std::size_t i = 0; i < k; ++i)
            if (spare_.size() < 2 * drain_blocks()) spare_.push_back(std::move(queue_[i]));
        queue_.erase(queue_.begin(), queue_.begin() + static_cast<std::ptrdiff_t>(k));
    }
    /// Flushes the spool; the array is complete (drain(..., true) must have run).
    void close() {
        if (!queue_.empty()) throw std::logic_error("VTP writer: array closed with blocks pending");
        if (std::fflush(f_) != 0) fail("write to");
    }
    std::uint64_t raw_bytes() const { return raw_bytes_; }
    /// Bytes this array takes in the appended section (header + data).
    std::uint64_t appended_bytes() const { return header().size() * 8 + data_bytes_; }
    /// Copies header and data to the output.
    void copy_to(AtomicFile& out) {
        const auto h = header();
        out.write(h.data(), h.size() * sizeof(std::uint64_t));
        if (std::fseek(f_, 0, SEEK_SET) != 0) fail("rewind");
        std::vector<unsigned char> buf(std::size_t{1} << 20);
        std::uint64_t left = data_bytes_;
        while (left > 0) {
            const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(left, buf.size()));
            if (std::fread(buf.data(), 1, n, f_) != n) fail("read back");
            out.write(buf.data(), n);
            left -= n;
        }
    }
    /// The <DataArray .../> element (offset: within the appended section).
    std::string element(std::uint64_t offset, const std::string& indent) const {
        std::string s = indent + "<DataArray type=\"" + type_ + "\" Name=\"" + name_ + "\"";
        if (components_ != 1) s += " NumberOfComponents=\"" + std::to_string(components_) + "\"";
        return s + " format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
    }

private:
    std::vector<std::uint64_t> header() const {
        if (o_.compression == VtpCompression::none) return {raw_bytes_};
        std::vector<std::uint64_t> h{csizes_.size(), o_.block_size, raw_bytes_ % o_.block_size};
        h.insert(h.end(), csizes_.begin(), csizes_.end());
        return h;
    }
    [[noreturn]] void fail(const char* what) const {
        const int e = errno;
        throw IoError(spool_name_ + ": cannot " + what + " the VTP array spool (deleted temporary file): " +
                      (e ? std::strerror(e) : "short file"));
    }

    std::string name_, type_;
    int components_;
    VtpOptions o_;
    std::string spool_name_;
    std::FILE* f_ = nullptr;
    struct Block {
        std::vector<unsigned char> raw, packed;
        std::size_t packed_size = 0;
        int rc = Z_OK;
        bool huffman_only = false, done = false;
    };
    std::vector<Block> queue_, spare_;
    bool may_skip_ = false, entropy_only_ = false;
    std::vector<unsigned char> probe_out_;
    std::vector<std::uint64_t> csizes_;
    std::uint64_t raw_bytes_ = 0, data_bytes_ = 0;
};

/// Compresses the queued blocks of `arrays` (all of them with `all`, else the full ones) on up to
/// VtpOptions::threads threads and writes them to their spools in order. Deterministic: each
/// block is compressed alone, so the bytes do not depend on the thread count.
void drain(const std::vector<ArraySpool*>& arrays, bool all, Deflaters& pool) {
    std::vector<std::pair<ArraySpool*, std::size_t>> jobs;
    std::vector<std::size_t> counts;
    if (pool.d.empty()) pool.d.push_back(std::make_unique<Deflater>());
    for (ArraySpool* a : arrays) {
        counts.push_back(a->ready(all));
        for (std::size_t i = 0; i < counts.back(); ++i) {
            if (a->is_probe(i)) {
                a->compress_probe(i, *pool.d[0]);
            } else {
                a->assign_strategy(i);
                jobs.emplace_back(a, i);
            }
        }
    }
    const std::size_t nthreads = std::min(jobs.size(), pool.threads);
    while (pool.d.size() < nthreads) pool.d.push_back(std::make_unique<Deflater>());
    if (nthreads <= 1) {
        for (auto& [a, i] : jobs) a->compress(i, *pool.d[0]);
    } else {
        std::atomic<std::size_t> next{0};
        auto work = [&](Deflater& d) {
            for (std::size_t j; (j = next.fetch_add(1)) < jobs.size();) jobs[j].first->compress(jobs[j].second, d);
        };
        std::vector<std::thread> threads;
        for (std::size_t t = 1; t < nthreads; ++t) threads.emplace_back(work, std::ref(*pool.d[t]));
        work(*pool.d[0]);
        for (auto& t : threads) t.join();
    }
    for (std::size_t k = 0; k < arrays.size(); ++k) arrays[k]->write_ready(counts[k]);
}

/// "--" may not appear in an XML comment, nor may bytes outside printable ASCII (the file must be
/// UTF-8; a file name's bytes need not be): escaped as \xNN.
std::string xml_comment(const std::string& text) {
    std::string s = "<!-- ";
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c < 0x20 || c >= 0x7f || c == '\\') {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", c);
            s += hex;
        } else if (c == '-' && !s.empty() && s.back() == '-') {
            s += "\\x2d";
        } else {
            s += static_cast<char>(c);
        }
    }
    if (s.back() == '-') s += ' ';
    return s + " -->\n";
}

/// Appends a large array in pieces of drain_blocks() blocks, compressing each piece in parallel:
/// memory = that many blocks, whatever the array's size.

void append_bulk(ArraySpool& a, const void* data, std::size_t n, std::size_t block_size, Deflaters& pool) {
    const auto* p = static_cast<const unsigned char*>(data);
    const std::size_t piece = drain_blocks() * block_size;
    for (std::size_t i = 0; i < n; i += piece) {
        a.append(p + i, std::min(piece, n - i));
        drain({&a}, false, pool);
    }
}

/// Fills a cell array spool with first, first+step, ... (n values of type T).
template <class T>
void append_sequence(ArraySpool& a, std::uint64_t n, std::uint64_t first, std::uint64_t step, std::size_t block_size,
                     Deflaters& pool) {
    std::vector<T> buf;
    const std::uint64_t chunk = std::max<std::uint64_t>(1, drain_blocks() * block_size / sizeof(T));
    for (std::uint64_t i = 0; i < n; i += chunk) {
        buf.clear();
        const std::uint64_t e = std::min(n, i + chunk);
        for (std::uint64_t k = i; k < e; ++k) buf.push_back(static_cast<T>(first + k * step));
        a.append(buf.data(), buf.size() * sizeof(T));
        drain({&a}, false, pool);
    }
}

const char* compressor_attr(const VtpOptions& o) {
    return o.compression == VtpCompression::zlib ? " compressor=\"vtkZLibDataCompressor\"" : "";
}

struct Section {
    const char* open;   ///< e.g. "<PointData Normals=\"Normals\" Scalars=\"value\">"
    const char* close;  ///< e.g. "</PointData>"
    std::vector<ArraySpool*> arrays;
};

/// Writes the whole file: comments, header with offsets, appended arrays, trailer.
void assemble(AtomicFile& out, const std::vector<std::string>& comments, const VtpOptions& o, const std::string& piece_attrs,
              const std::vector<Section>& sections, Deflaters& pool) {
    std::string x = "<?xml version=\"1.0\"?>\n";
    for (const auto& c : comments) x += xml_comment(c);
    x += std::string("<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"") +
         compressor_attr(o) + ">\n  <PolyData>\n    <Piece " + piece_attrs + ">\n";
    std::vector<ArraySpool*> all;
    for (const auto& s : sections) all.insert(all.end(), s.arrays.begin(), s.arrays.end());
    drain(all, true, pool);
    std::uint64_t offset = 0;
    std::vector<ArraySpool*> order;
    for (const auto& s : sections) {
        if (s.arrays.empty()) continue;
        x += std::string("      ") + s.open + "\n";
        for (ArraySpool* a : s.arrays) {
            a->close();
            x += a->element(offset, "        ");
            const std::uint64_t n = a->appended_bytes();
            if (offset > std::numeric_limits<std::uint64_t>::max() / 2 - n) throw std::length_error(out.path() + ": VTP output too large");
            offset += n;
            order.push_back(a);
        }
        x += std::string("      ") + s.close + "\n";
    }
    x += "    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";
    out.write(x);
    for (ArraySpool* a : order) a->copy_to(out);
    out.write(std::string("\n  </AppendedData>\n</VTKFile>\n"));
    out.commit();
}

}  // namespace

namespace {
/// The value array's name as the options ask (see VtpOptions::value_name).
std::string value_array_name(const VtpOptions& o) {
    const std::string& n = o.value_name;
    if (n.empty()) return "value";
    // a name the other arrays take gets a suffix: "radius_value" (the values are another array's)
    return n == "Normals" || n == "radius" || n == "block" || n == "Points" || n == "connectivity" || n == "offsets" ? n + "_value" : n;
}
}  // namespace

struct VtpPointWriter::Impl {
    std::string path;
    std::vector<std::string> comments;
    VtpOptions o;
    AtomicFile out;
    Deflaters pool;
    ArraySpool points, normals, radius, value;
    std::optional<ArraySpool> block;
    bool any = false;
    std::vector<float> scratch;
    Impl(const std::string& p, const std::vector<std::string>& c, const VtpOptions& opt)
        : path(p), comments(c), o(opt), out(p), pool(opt.threads), points("Points", "Float32", 3, opt, true), normals("Normals", "Float32", 3, opt, true),
          radius("radius", "Float32", 1, opt), value(vtk_xml_escape(value_array_name(opt)), "Float32", 1, opt) {}
};

VtpPointWriter::VtpPointWriter(const std::string& path, const std::vector<std::string>& comments, VtpOptions options)
    : d_(std::make_unique<Impl>(path, comments, options)) {}

VtpPointWriter::~VtpPointWriter() = default;

bool VtpPointWriter::has_blocks() const { return d_->block.has_value(); }

void VtpPointWriter::append(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks) {
    if (pts.empty()) return;
    if (!blocks.empty() && blocks.size() != pts.size())
        throw FormatError(d_->path + ": " + std::to_string(blocks.size()) + " block ids for " + std::to_string(pts.size()) + " points");
    if (!d_->any && !blocks.empty()) d_->block.emplace("block", "UInt32", 1, d_->o);
    if (blocks.empty() == d_->block.has_value())
        throw FormatError(d_->path + ": points with and without block ids mixed in one output");
    d_->any = true;
    auto& s = d_->scratch;
    const std::size_t n = pts.size();
    s.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) std::memcpy(&s[3 * i], pts[i].pos, 12);
    d_->points.append(s.data(), 12 * n);
    const bool oriented = d_->o.oriented;
    if (oriented) {
        for (std::size_t i = 0; i < n; ++i) std::memcpy(&s[3 * i], pts[i].normal, 12);
        d_->normals.append(s.data(), 12 * n);
        for (std::size_t i = 0; i < n; ++i) s[i] = pts[i].radius;
        d_->radius.append(s.data(), 4 * n);
    }
    for (std::size_t i = 0; i < n; ++i) s[i] = pts[i].value;
    d_->value.append(s.data(), 4 * n);
    if (d_->block) d_->block->append(blocks.data(), 4 * n);
    std::vector<ArraySpool*> arrays{&d_->points, &d_->value};
    if (oriented) arrays.insert(arrays.begin() + 1, {&d_->normals, &d_->radius});
    if (d_->block) arrays.push_back(&*d_->block);
    drain(arrays, false, d_->pool);
    count_ += n;
}

void VtpPointWriter::commit() {
    Impl& d = *d_;
    const std::uint64_t n = count_;
    const bool wide = n > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max());
    const char* itype = wide ? "Int64" : "Int32";
    ArraySpool conn("connectivity", itype, 1, d.o), offs("offsets", itype, 1, d.o);
    if (wide) {
        append_sequence<std::int64_t>(conn, n, 0, 1, d.o.block_size, d.pool);
        append_sequence<std::int64_t>(offs, n, 1, 1, d.o.block_size, d.pool);
    } else {
        append_sequence<std::int32_t>(conn, n, 0, 1, d.o.block_size, d.pool);
        append_sequence<std::int32_t>(offs, n, 1, 1, d.o.block_size, d.pool);
    }
    std::vector<ArraySpool*> pd{&d.value};
    if (d.o.oriented) pd.insert(pd.begin(), {&d.normals, &d.radius});
    if (d.block) pd.push_back(&*d.block);
    const std::string ns = std::to_string(n);
    const std::string scalars = "Scalars=\"" + vtk_xml_escape(value_array_name(d.o)) + "\">";
    const std::string pd_open = d.o.oriented ? "<PointData Normals=\"Normals\" " + scalars : "<PointData " + scalars;
    assemble(d.out, d.comments, d.o,
             "NumberOfPoints=\"" + ns + "\" NumberOfVerts=\"" + ns + "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\"",
             {{pd_open.c_str(), "</PointData>", pd},
              {"<Points>", "</Points>", {&d.points}},
              {"<Verts>", "</Verts>", {&conn, &offs}}},
             d.pool);
}

void write_vtp_mesh(const Mesh& mesh, const std::string& path, const std::vector<std::string>& comments, VtpOptions o) {
    if (mesh.xyz.size() % 3 != 0 || mesh.tri.size() % 3 != 0)
        throw std::invalid_argument(path + ": mesh arrays are not multiples of 3");
    const bool normals = !mesh.normals.empty();
    if (normals && mesh.normals.size() != mesh.xyz.size())
        throw std::invalid_argument(path + ": mesh has " + std::to_string(mesh.normals.size()) + " normal floats for " +
                                    std::to_string(mesh.xyz.size()) + " position floats");
    const std::size_t nv = mesh.vertex_count(), nf = mesh.triangle_count();
    for (std::uint32_t i : mesh.tri)
        if (i >= nv)
            throw std::invalid_argument(path + ": triangle index " + std::to_string(i) + " out of range (" + std::to_string(nv) +
                                        " vertices)");
    const bool blocks = !mesh.block.empty();
    if (blocks && mesh.block.size() != nf)
        throw std::invalid_argument(path + ": mesh has " + std::to_string(mesh.block.size()) + " block ids for " +
                                    std::to_string(nf) + " triangles");
    AtomicFile out(path);
    Deflaters pool(o.threads);
    ArraySpool points("Points", "Float32", 3, o, true);
    append_bulk(points, mesh.xyz.data(), mesh.xyz.size() * sizeof(float), o.block_size, pool);
    std::optional<ArraySpool> nrm;
    if (normals) {
        nrm.emplace("Normals", "Float32", 3, o, true);
        append_bulk(*nrm, mesh.normals.data(), mesh.normals.size() * sizeof(float), o.block_size, pool);
    }
    // indices < 2^32 (uint32 in Mesh); offsets reach 3 * nf
    const auto imax = static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max());
    const bool wide = 3 * static_cast<std::uint64_t>(nf) > imax || nv > imax;
    const char* itype = wide ? "Int64" : "Int32";
    ArraySpool conn("connectivity", itype, 1, o), offs("offsets", itype, 1, o);
    constexpr std::size_t kChunk = 1u << 16;
    if (wide) {
        std::vector<std::int64_t> buf;
        for (std::size_t i = 0; i < mesh.tri.size(); i += kChunk) {
            const std::size_t e = std::min(mesh.tri.size(), i + kChunk);
            buf.assign(mesh.tri.begin() + static_cast<std::ptrdiff_t>(i), mesh.tri.begin() + static_cast<std::ptrdiff_t>(e));
            append_bulk(conn, buf.data(), buf.size() * 8, o.block_size, pool);
        }
        append_sequence<std::int64_t>(offs, nf, 3, 3, o.block_size, pool);
    } else {
        // uint32 indices below 2^31 have the bytes of their int32 value
        append_bulk(conn, mesh.tri.data(), mesh.tri.size() * sizeof(std::uint32_t), o.block_size, pool);
        append_sequence<std::int32_t>(offs, nf, 3, 3, o.block_size, pool);
    }
    std::optional<ArraySpool> blk;
    if (blocks) {
        blk.emplace("block", "UInt32", 1, o);
        append_bulk(*blk, mesh.block.data(), mesh.block.size() * sizeof(std::uint32_t), o.block_size, pool);
    }
    std::vector<Section> sections;
    if (normals) sections.push_back({"<PointData Normals=\"Normals\">", "</PointData>", {&*nrm}});
    if (blocks) sections.push_back({"<CellData Scalars=\"block\">", "</CellData>", {&*blk}});
    sections.push_back({"<Points>", "</Points>", {&points}});
    sections.push_back({"<Polys>", "</Polys>", {&conn, &offs}});
    assemble(out, comments, o,
             "NumberOfPoints=\"" + std::to_string(nv) + "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
                 std::to_string(nf) + "\"",
             sections, pool);
}

}  // namespace meshless
