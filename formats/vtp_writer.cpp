#include "formats/vtp_writer.hpp"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>

#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

static_assert(std::endian::native == std::endian::little, "the VTP writer writes host-order (little endian) data");

/// One DataArray on its way to the appended section: compressed block by block into an unlinked
/// temporary file, with the table of compressed sizes kept for the header.
class ArraySpool {
public:
    ArraySpool(std::string name, std::string type, int components, const VtpOptions& o)
        : name_(std::move(name)), type_(std::move(type)), components_(components), o_(o) {
        if (o_.block_size == 0 || o_.block_size > (std::size_t{1} << 30)) throw std::invalid_argument("VTP writer: bad block size");
        const char* dir = std::getenv("TMPDIR");
        std::string tmpl = std::string(dir && *dir ? dir : "/tmp") + "/meshless-vtp-" + name_ + "-XXXXXX";
        const int fd = ::mkstemp(tmpl.data());
        if (fd < 0) throw IoError(tmpl + ": cannot create the temporary VTP array spool: " + std::strerror(errno));
        spool_name_ = tmpl;
        ::unlink(spool_name_.c_str());  // freed however the process ends
        f_ = ::fdopen(fd, "w+b");
        if (!f_) {
            const int e = errno;
            ::close(fd);
            throw IoError(spool_name_ + ": cannot open the temporary VTP array spool: " + std::strerror(e));
        }
        raw_.reserve(o_.block_size);
    }
    ~ArraySpool() {
        if (f_) std::fclose(f_);
    }
    ArraySpool(const ArraySpool&) = delete;
    ArraySpool& operator=(const ArraySpool&) = delete;

    void append(const void* data, std::size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        while (n > 0) {
            const std::size_t take = std::min(n, o_.block_size - raw_.size());
            raw_.insert(raw_.end(), p, p + take);
            p += take;
            n -= take;
            if (raw_.size() == o_.block_size) flush_block();
        }
    }
    /// Flushes the partial last block; the array is complete.
    void close() {
        if (!raw_.empty()) flush_block();
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
    void flush_block() {
        raw_bytes_ += raw_.size();
        const unsigned char* data = raw_.data();
        std::size_t n = raw_.size();
        if (o_.compression == VtpCompression::zlib) {
            uLongf cap = compressBound(static_cast<uLong>(raw_.size()));
            packed_.resize(cap);
            const int rc = compress2(packed_.data(), &cap, raw_.data(), static_cast<uLong>(raw_.size()), o_.zlib_level);
            if (rc != Z_OK) throw IoError(spool_name_ + ": zlib compression failed (code " + std::to_string(rc) + ")");
            csizes_.push_back(cap);
            data = packed_.data();
            n = cap;
        }
        errno = 0;
        if (std::fwrite(data, 1, n, f_) != n) fail("write to");
        data_bytes_ += n;
        raw_.clear();
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
    std::vector<unsigned char> raw_, packed_;
    std::vector<std::uint64_t> csizes_;
    std::uint64_t raw_bytes_ = 0, data_bytes_ = 0;
};

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

/// Fills a cell array spool with vertex ids first..first+n-1 (connectivity, step 1) or offsets.
template <class T>
void append_sequence(ArraySpool& a, std::uint64_t n, std::uint64_t first, std::uint64_t step) {
    std::vector<T> buf;
    constexpr std::uint64_t kChunk = 1u << 16;
    buf.reserve(kChunk);
    for (std::uint64_t i = 0; i < n; i += kChunk) {
        buf.clear();
        const std::uint64_t e = std::min(n, i + kChunk);
        for (std::uint64_t k = i; k < e; ++k) buf.push_back(static_cast<T>(first + k * step));
        a.append(buf.data(), buf.size() * sizeof(T));
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
              const std::vector<Section>& sections) {
    std::string x = "<?xml version=\"1.0\"?>\n";
    for (const auto& c : comments) x += xml_comment(c);
    x += std::string("<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"") +
         compressor_attr(o) + ">\n  <PolyData>\n    <Piece " + piece_attrs + ">\n";
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

struct VtpPointWriter::Impl {
    std::string path;
    std::vector<std::string> comments;
    VtpOptions o;
    AtomicFile out;
    ArraySpool points, normals, radius, value;
    std::optional<ArraySpool> block;
    bool any = false;
    std::vector<float> scratch;
    Impl(const std::string& p, const std::vector<std::string>& c, const VtpOptions& opt)
        : path(p), comments(c), o(opt), out(p), points("Points", "Float32", 3, opt), normals("Normals", "Float32", 3, opt),
          radius("radius", "Float32", 1, opt), value("value", "Float32", 1, opt) {}
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
    for (std::size_t i = 0; i < n; ++i) std::memcpy(&s[3 * i], pts[i].normal, 12);
    d_->normals.append(s.data(), 12 * n);
    for (std::size_t i = 0; i < n; ++i) s[i] = pts[i].radius;
    d_->radius.append(s.data(), 4 * n);
    for (std::size_t i = 0; i < n; ++i) s[i] = pts[i].value;
    d_->value.append(s.data(), 4 * n);
    if (d_->block) d_->block->append(blocks.data(), 4 * n);
    count_ += n;
}

void VtpPointWriter::commit() {
    Impl& d = *d_;
    const std::uint64_t n = count_;
    const bool wide = n > static_cast<std::uint64_t>(std::numeric_limits<std::int32_t>::max());
    const char* itype = wide ? "Int64" : "Int32";
    ArraySpool conn("connectivity", itype, 1, d.o), offs("offsets", itype, 1, d.o);
    if (wide) {
        append_sequence<std::int64_t>(conn, n, 0, 1);
        append_sequence<std::int64_t>(offs, n, 1, 1);
    } else {
        append_sequence<std::int32_t>(conn, n, 0, 1);
        append_sequence<std::int32_t>(offs, n, 1, 1);
    }
    std::vector<ArraySpool*> pd{&d.normals, &d.radius, &d.value};
    if (d.block) pd.push_back(&*d.block);
    const std::string ns = std::to_string(n);
    assemble(d.out, d.comments, d.o,
             "NumberOfPoints=\"" + ns + "\" NumberOfVerts=\"" + ns + "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\"",
             {{"<PointData Normals=\"Normals\" Scalars=\"value\">", "</PointData>", pd},
              {"<Points>", "</Points>", {&d.points}},
              {"<Verts>", "</Verts>", {&conn, &offs}}});
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
    ArraySpool points("Points", "Float32", 3, o);
    points.append(mesh.xyz.data(), mesh.xyz.size() * sizeof(float));
    std::optional<ArraySpool> nrm;
    if (normals) {
        nrm.emplace("Normals", "Float32", 3, o);
        nrm->append(mesh.normals.data(), mesh.normals.size() * sizeof(float));
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
            conn.append(buf.data(), buf.size() * 8);
        }
        append_sequence<std::int64_t>(offs, nf, 3, 3);
    } else {
        // uint32 indices below 2^31 have the bytes of their int32 value
        conn.append(mesh.tri.data(), mesh.tri.size() * sizeof(std::uint32_t));
        append_sequence<std::int32_t>(offs, nf, 3, 3);
    }
    std::optional<ArraySpool> blk;
    if (blocks) {
        blk.emplace("block", "UInt32", 1, o);
        blk->append(mesh.block.data(), mesh.block.size() * sizeof(std::uint32_t));
    }
    std::vector<Section> sections;
    if (normals) sections.push_back({"<PointData Normals=\"Normals\">", "</PointData>", {&*nrm}});
    if (blocks) sections.push_back({"<CellData Scalars=\"block\">", "</CellData>", {&*blk}});
    sections.push_back({"<Points>", "</Points>", {&points}});
    sections.push_back({"<Polys>", "</Polys>", {&conn, &offs}});
    assemble(out, comments, o,
             "NumberOfPoints=\"" + std::to_string(nv) + "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
                 std::to_string(nf) + "\"",
             sections);
}

}  // namespace meshless
