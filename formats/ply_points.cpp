#include "formats/ply_points.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>

#include "formats/ply.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

static_assert(sizeof(PointRecord) == 32);
constexpr const char* kNames[8] = {"x", "y", "z", "nx", "ny", "nz", "radius", "value"};

PlyHeader point_header(const std::vector<std::string>& comments, std::uint64_t n) {
    PlyHeader h;
    h.encoding = PlyEncoding::binary_little_endian;
    h.comments = comments;
    PlyElement v;
    v.name = "vertex";
    v.count = n;
    for (const char* name : kNames) v.props.push_back(PlyProperty{name, StoredType::f32, false, StoredType::u8});
    h.elements.push_back(std::move(v));
    return h;
}

}  // namespace

PlyPointWriter::PlyPointWriter(const std::string& path, const std::vector<std::string>& comments)
    : w_(std::make_unique<PlyWriter>(path, point_header(comments, 0), PlyCounts::patched)) {}

PlyPointWriter::~PlyPointWriter() = default;

void PlyPointWriter::append(std::span<const PointRecord> pts) {
    w_->append(pts.data(), pts.size_bytes());
    count_ += pts.size();
}

void PlyPointWriter::commit() { w_->commit(); }

void write_ply_points(const std::string& path, std::span<const PointRecord> pts,
                      const std::vector<std::string>& comments) {
    PlyWriter w(path, point_header(comments, pts.size()), PlyCounts::declared_padded);
    w.append(pts.data(), pts.size_bytes());
    w.commit();
}

struct PlyPointReader::Impl {
    explicit Impl(const std::string& path) : r(path) {}
    PlyReader r;
    std::size_t vi = 0;
    std::uint64_t count = 0, done = 0;
    int ix[8];
    bool native = false;  // binary little endian with exactly the 8 float properties of PointRecord
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
    d.native = h.encoding == PlyEncoding::binary_little_endian && std::endian::native == std::endian::little &&
               V.props.size() == 8;
    for (int a = 0; a < 8 && d.native; ++a) d.native = d.ix[a] == a && V.props[a].type == StoredType::f32;
    d.r.skip_to(d.vi);
}

PlyPointReader::~PlyPointReader() = default;

const std::vector<std::string>& PlyPointReader::comments() const { return d_->r.header().comments; }
std::uint64_t PlyPointReader::count() const { return d_->count; }
const std::string& PlyPointReader::path() const { return d_->r.name(); }
bool PlyPointReader::size_known() const { return d_->r.size_known(); }

std::size_t PlyPointReader::read(std::vector<PointRecord>& out, std::size_t max) {
    Impl& d = *d_;
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(max, d.count - d.done));
    if (d.native) {
        out.resize(n);
        if (n) d.r.read_raw(reinterpret_cast<std::byte*>(out.data()), n);
    } else {
        // the properties PointRecord has, in its order; missing ones read as 0
        int cols[8], slot[8];
        std::size_t nc = 0;
        for (int a = 0; a < 8; ++a)
            if (d.ix[a] >= 0) slot[nc] = a, cols[nc++] = d.ix[a];
        out.resize(n);
        for (std::size_t i = 0; i < n;) {  // pieces: the converted values stay small
            const std::size_t k = d.r.read_values(d.vals, std::min<std::size_t>(n - i, 65536), std::span<const int>(cols, nc));
            if (k == 0) throw std::logic_error(d.r.name() + ": PLY vertices ended early");
            for (std::size_t j = 0; j < k; ++j, ++i) {
                float f[8] = {0, 0, 0, 0, 0, 0, 0, 0};
                for (std::size_t c = 0; c < nc; ++c) f[slot[c]] = static_cast<float>(d.vals[j * nc + c]);
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
    // pieces: memory grows with the points the file holds, not with what its header claims
    constexpr std::size_t kPiece = std::size_t(1) << 20;
    if (r.count() <= kPiece || r.size_known()) {
        r.read(out.points, static_cast<std::size_t>(r.count()));
    } else {
        while (r.read(piece, kPiece)) out.points.insert(out.points.end(), piece.begin(), piece.end());
    }
    if (r.count() == 0) r.read(out.points, 0);  // trailing-bytes check of an empty set
    return out;
}

}  // namespace meshless
