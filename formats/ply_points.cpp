#include "formats/ply_points.hpp"

#include <algorithm>
#include <cmath>
#include <bit>
#include <cstring>
#include <stdexcept>

#include "formats/ply.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

static_assert(sizeof(PointRecord) == 32);
constexpr const char* kNames[8] = {"x", "y", "z", "nx", "ny", "nz", "radius", "value"};

PlyHeader point_header(const std::vector<std::string>& comments, std::uint64_t n, bool with_blocks, bool with_colors = false) {
    PlyHeader h;
    h.encoding = PlyEncoding::binary_little_endian;
    h.comments = comments;
    PlyElement v;
    v.name = "vertex";
    v.count = n;
    for (const char* name : kNames) v.props.push_back(PlyProperty{name, StoredType::f32, false, StoredType::u8});
    if (with_blocks) v.props.push_back(PlyProperty{"block", StoredType::u32, false, StoredType::u8});
    if (with_colors)
        for (const char* name : {"red", "green", "blue"}) v.props.push_back(PlyProperty{name, StoredType::u8, false, StoredType::u8});
    h.elements.push_back(std::move(v));
    return h;
}

/// Points, optional block ids (4 bytes) and optional colours (3 bytes) packed as vertex records.
void pack_points(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks, std::span<const std::uint8_t> rgb,
                 bool with_blocks, bool with_colors, std::vector<char>& out) {
    if (with_blocks && blocks.size() != pts.size())
        throw std::invalid_argument("PLY point writer: " + std::to_string(pts.size()) + " points with " +
                                    std::to_string(blocks.size()) + " block ids");
    if (with_colors && rgb.size() != 3 * pts.size())
        throw std::invalid_argument("PLY point writer: " + std::to_string(pts.size()) + " points with " +
                                    std::to_string(rgb.size()) + " colour bytes");
    const std::size_t rec = sizeof(PointRecord) + (with_blocks ? 4 : 0) + (with_colors ? 3 : 0);
    out.resize(pts.size() * rec);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        char* o = out.data() + i * rec;
        std::memcpy(o, &pts[i], sizeof(PointRecord));
        o += sizeof(PointRecord);
        if (with_blocks) {
            std::memcpy(o, &blocks[i], 4);
            o += 4;
        }
        if (with_colors) std::memcpy(o, &rgb[3 * i], 3);
    }
}

}  // namespace

PlyPointWriter::PlyPointWriter(const std::string& path, const std::vector<std::string>& comments, bool with_blocks,
                               bool with_colors, std::optional<std::uint64_t> count)
    : w_(std::make_unique<PlyWriter>(path, point_header(comments, count.value_or(0), with_blocks, with_colors),
                                     count ? PlyCounts::declared_padded : PlyCounts::patched)),
      blocks_(with_blocks), colors_(with_colors) {}

PlyPointWriter::~PlyPointWriter() = default;

void PlyPointWriter::append(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks,
                            std::span<const std::uint8_t> rgb) {
    pack_points(pts, blocks, rgb, blocks_, colors_, packed_);
    w_->append(packed_.data(), packed_.size());
    count_ += pts.size();
}

void PlyPointWriter::append(std::span<const PointRecord> pts) {
    if (colors_) throw std::invalid_argument("PLY point writer: points without colours for a file with colour properties");
    if (blocks_) throw std::invalid_argument("PLY point writer: points without block ids for a file with a block property");
    w_->append(pts.data(), pts.size_bytes());
    count_ += pts.size();
}

void PlyPointWriter::append(std::span<const PointRecord> pts, std::span<const std::uint32_t> blocks) {
    if (colors_) throw std::invalid_argument("PLY point writer: points without colours for a file with colour properties");
    if (!blocks_) throw std::invalid_argument("PLY point writer: block ids for a file without a block property");
    pack_points(pts, blocks, {}, true, false, packed_);
    w_->append(packed_.data(), packed_.size());
    count_ += pts.size();
}

void PlyPointWriter::commit() { w_->commit(); }

void write_ply_points(const std::string& path, std::span<const PointRecord> pts,
                      const std::vector<std::string>& comments, std::optional<std::span<const std::uint32_t>> blocks,
                      std::optional<std::span<const std::uint8_t>> rgb) {
    PlyPointWriter w(path, comments, blocks.has_value(), rgb.has_value(), pts.size());
    if (rgb) w.append(pts, blocks.value_or(std::span<const std::uint32_t>{}), *rgb);
    else if (blocks) w.append(pts, *blocks);
    else w.append(pts);
    w.commit();
}

struct PlyPointReader::Impl {
    explicit Impl(const std::string& path) : r(path) {}
    PlyReader r;
    std::size_t vi = 0;
    std::uint64_t count = 0, done = 0;
    int ix[8];
    int block = -1;       // index of the `block` property, if any
    bool native = false;  // binary little endian with exactly the 8 float properties of PointRecord
                          // (and, when block >= 0, a ninth: uint32 block)
    std::vector<char> packed;
    bool last = false;    // the vertices are the last element: check for trailing bytes at their end
    std::vector<double> vals;
};

PlyPointReader::PlyPointReader(const std::string& path) : d_(std::make_unique<Impl>(path)) {
    Impl& d = *d_;
    const PlyHeader& h = d.r.header();
    const int vi = h.find("vertex");
    if (vi < 0) throw FormatError(path + ": PLY file has no vertex element");
    d.vi = static_cast<std::size_t>(vi);
    const PlyElement& V = h.elements[d.vi];
    if (V.has_lists()) throw FormatError(path + ": line " + std::to_string(V.line) + ": list properties on PLY vertices are not supported");
    for (int a = 0; a < 8; ++a) d.ix[a] = V.find(kNames[a]);
    if (d.ix[0] < 0 || d.ix[1] < 0 || d.ix[2] < 0) throw FormatError(path + ": line " + std::to_string(V.line) + ": PLY vertices have no x y z properties");
    d.count = V.count;
    d.last = d.vi + 1 == h.elements.size();
    d.block = V.find("block");
    if (d.block >= 0) {
        const StoredType t = V.props[static_cast<std::size_t>(d.block)].type;
        if (t == StoredType::f32 || t == StoredType::f64)
            throw FormatError(path + ": line " + std::to_string(V.line) + ": the vertex property 'block' must be an integer type");
    }
    d.native = h.encoding == PlyEncoding::binary_little_endian && std::endian::native == std::endian::little &&
               V.props.size() == (d.block >= 0 ? 9u : 8u);
    for (int a = 0; a < 8 && d.native; ++a) d.native = d.ix[a] == a && V.props[a].type == StoredType::f32;
    if (d.native && d.block >= 0) d.native = d.block == 8 && V.props[8].type == StoredType::u32;
    d.r.skip_to(d.vi);
}

PlyPointReader::~PlyPointReader() = default;

const std::vector<std::string>& PlyPointReader::comments() const { return d_->r.header().comments; }
std::uint64_t PlyPointReader::count() const { return d_->count; }
const std::string& PlyPointReader::path() const { return d_->r.name(); }
bool PlyPointReader::size_known() const { return d_->r.size_known(); }
bool PlyPointReader::has_blocks() const { return d_->block >= 0; }
std::optional<std::uint64_t> PlyPointReader::records_offset() const {
    const Impl& d = *d_;
    if (!d.native || d.block >= 0 || d.vi != 0 || !d.r.size_known()) return std::nullopt;
    return d.r.header().header_bytes;
}

std::size_t PlyPointReader::read(std::vector<PointRecord>& out, std::size_t max, std::vector<std::uint32_t>* blocks) {
    Impl& d = *d_;
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(max, d.count - d.done));
    const bool want_blocks = blocks && d.block >= 0;
    if (blocks) blocks->clear();
    if (d.native && d.block < 0) {
        out.resize(n);
        if (n) d.r.read_raw(reinterpret_cast<std::byte*>(out.data()), n);
    } else if (d.native) {
        constexpr std::size_t rec = sizeof(PointRecord) + sizeof(std::uint32_t);
        out.resize(n);
        if (want_blocks) blocks->resize(n);
        for (std::size_t i = 0; i < n;) {  // pieces of at most 1 Mi records through a staging buffer
            const std::size_t k = std::min<std::size_t>(n - i, std::size_t(1) << 20);
            d.packed.resize(k * rec);
            d.r.read_raw(reinterpret_cast<std::byte*>(d.packed.data()), k);
            for (std::size_t j = 0; j < k; ++j, ++i) {
                std::memcpy(&out[i], d.packed.data() + j * rec, sizeof(PointRecord));
                if (want_blocks) std::memcpy(&(*blocks)[i], d.packed.data() + j * rec + sizeof(PointRecord), sizeof(std::uint32_t));
            }
        }
    } else {
        // the properties PointRecord has, in its order (then block); missing ones read as 0
        int cols[9], slot[9];
        std::size_t nc = 0;
        for (int a = 0; a < 8; ++a)
            if (d.ix[a] >= 0) slot[nc] = a, cols[nc++] = d.ix[a];
        if (want_blocks) slot[nc] = 8, cols[nc++] = d.block;
        out.resize(n);
        if (want_blocks) blocks->resize(n);
        for (std::size_t i = 0; i < n;) {  // pieces: the converted values stay small
            const std::size_t k = d.r.read_values(d.vals, std::min<std::size_t>(n - i, 65536), std::span<const int>(cols, nc));
            if (k == 0) throw std::logic_error(d.r.name() + ": PLY vertices ended early");
            for (std::size_t j = 0; j < k; ++j, ++i) {
                float f[8] = {0, 0, 0, 0, 0, 0, 0, 0};
                for (std::size_t c = 0; c < nc; ++c) {
                    if (slot[c] < 8) {
                        f[slot[c]] = static_cast<float>(d.vals[j * nc + c]);
                        continue;
                    }
                    const double b = d.vals[j * nc + c];
                    if (!(b >= 0 && b <= 4294967295.0) || b != std::floor(b))
                        throw FormatError(d.r.name() + ": vertex " + std::to_string(d.done + i) + ": block " + std::to_string(b) +
                                          " is not an id in 0..4294967295");
                    (*blocks)[i] = static_cast<std::uint32_t>(b);
                }
                std::memcpy(&out[i], f, sizeof f);
            }
        }
    }
    d.done += n;
    if (d.done == d.count && d.last && d.r.element() == d.vi + 1) d.r.finish();
    return n;
}

PlyPoints read_ply_points(const std::string& path) {
    PlyPointReader r(path);
    PlyPoints out;
    out.comments = r.comments();
    std::vector<PointRecord> piece;
    std::vector<std::uint32_t> piece_blocks;
    // pieces: memory grows with the points the file holds, not with what its header claims
    constexpr std::size_t kPiece = std::size_t(1) << 20;
    if (r.count() <= kPiece || r.size_known()) {
        r.read(out.points, static_cast<std::size_t>(r.count()), &out.block);
    } else {
        while (r.read(piece, kPiece, &piece_blocks)) {
            out.points.insert(out.points.end(), piece.begin(), piece.end());
            out.block.insert(out.block.end(), piece_blocks.begin(), piece_blocks.end());
        }
    }
    if (r.count() == 0) r.read(out.points, 0);  // trailing-bytes check of an empty set
    return out;
}

}  // namespace meshless
