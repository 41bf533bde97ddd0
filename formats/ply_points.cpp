#include "formats/ply_points.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>

#include "formats/atomic_file.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr int kCountWidth = 20;

std::string header_prefix(const std::vector<std::string>& comments) {
    std::string h = "ply\nformat binary_little_endian 1.0\n";
    for (const auto& c : comments) h += "comment " + c + "\n";
    return h;
}

std::string count_lines(std::uint64_t n) {
    // "element vertex N\ncomment<pad>\n": constant length whatever N is.
    const std::string digits = std::to_string(n);
    return "element vertex " + digits + "\ncomment" + std::string(kCountWidth - digits.size(), ' ') + "\n";
}

const char* kProperties =
    "property float x\nproperty float y\nproperty float z\n"
    "property float nx\nproperty float ny\nproperty float nz\n"
    "property float radius\nproperty float value\nend_header\n";

}  // namespace

PlyPointWriter::PlyPointWriter(const std::string& path, const std::vector<std::string>& comments)
    : file_(std::make_unique<AtomicFile>(path)) {
    if (file_->is_streaming())
        throw InvalidArgument(path + ": a PLY point output that cannot seek needs the whole point set (use write_ply_points)");
    const std::string pre = header_prefix(comments);
    file_->write(pre);
    count_offset_ = pre.size();
    file_->write(count_lines(0));
    file_->write(std::string(kProperties));
}

PlyPointWriter::~PlyPointWriter() = default;

void PlyPointWriter::append(std::span<const PointRecord> pts) {
    file_->write(pts.data(), pts.size_bytes());
    count_ += pts.size();
}

void PlyPointWriter::commit() {
    const std::string lines = count_lines(count_);
    file_->pwrite(count_offset_, lines.data(), lines.size());
    file_->commit();
}

void write_ply_points(const std::string& path, std::span<const PointRecord> pts,
                      const std::vector<std::string>& comments) {
    AtomicFile f(path);
    f.write(header_prefix(comments) + count_lines(pts.size()) + kProperties);
    f.write(pts.data(), pts.size_bytes());
    f.commit();
}

struct PlyPointReader::Impl {
    std::string path;
    std::ifstream in;
    enum class Enc { ascii, le, be } enc = Enc::ascii;
    std::vector<std::string> comments;
    std::uint64_t nvert = 0, done = 0;
    struct Prop { std::string name, type; int size; };
    std::vector<Prop> props;
    std::vector<std::string> other_elements;
    int ix[8];
    std::size_t stride = 0;
    bool native = false;  // binary little endian with exactly the 8 float properties of PointRecord
    std::vector<double> vals;
    std::vector<unsigned char> raw;
    bool checked_tail = false;
};

PlyPointReader::PlyPointReader(const std::string& path) : d_(std::make_unique<Impl>()) {
    Impl& d = *d_;
    d.path = path;
    d.in.open(path, std::ios::binary);
    std::ifstream& in = d.in;
    if (!in) throw IoError(path + ": cannot open");
    using Enc = Impl::Enc;
    std::string line;
    std::getline(in, line);
    if (line != "ply" && line != "ply\r") throw FormatError(path + ": not a PLY file (missing 'ply' magic)");
    bool in_vertex = false, have_format = false;
    auto type_size = [&](const std::string& t) -> int {
        if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
        if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
        if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
        if (t == "double" || t == "float64") return 8;
        throw FormatError(path + ": unknown PLY property type '" + t + "'");
    };
    for (;;) {
        if (!std::getline(in, line)) throw FormatError(path + ": truncated PLY header (no end_header)");
        if (!line.empty() && line.back() == '\r') line.pop_back();
        std::istringstream ls(line);
        std::string kw;
        ls >> kw;
        if (kw == "end_header") break;
        if (kw == "format") {
            std::string f, v;
            ls >> f >> v;
            if (f == "ascii") d.enc = Enc::ascii;
            else if (f == "binary_little_endian") d.enc = Enc::le;
            else if (f == "binary_big_endian") d.enc = Enc::be;
            else throw FormatError(path + ": unknown PLY format '" + f + "'");
            if (v != "1.0") throw FormatError(path + ": unsupported PLY version '" + v + "'");
            have_format = true;
        } else if (kw == "comment") {
            std::string rest;
            std::getline(ls, rest);
            while (!rest.empty() && (rest.front() == ' ')) rest.erase(rest.begin());
            while (!rest.empty() && (rest.back() == ' ')) rest.pop_back();
            if (!rest.empty()) d.comments.push_back(rest);
        } else if (kw == "element") {
            std::string name;
            long long n = -1;
            ls >> name >> n;
            if (n < 0) throw FormatError(path + ": malformed PLY element line '" + line + "'");
            in_vertex = name == "vertex";
            if (in_vertex) d.nvert = static_cast<std::uint64_t>(n);
            else if (n > 0) d.other_elements.push_back(name);
        } else if (kw == "property") {
            std::string t, name;
            ls >> t;
            if (t == "list") {
                if (in_vertex) throw FormatError(path + ": list properties on vertices are not supported");
                continue;
            }
            ls >> name;
            if (in_vertex) d.props.push_back({name, t, type_size(t)});
        } else if (kw == "obj_info" || kw.empty()) {
        } else {
            throw FormatError(path + ": malformed PLY header line '" + line + "'");
        }
    }
    if (!have_format) throw FormatError(path + ": PLY header has no format line");
    const char* names[8] = {"x", "y", "z", "nx", "ny", "nz", "radius", "value"};
    for (int a = 0; a < 8; ++a) {
        d.ix[a] = -1;
        for (std::size_t p = 0; p < d.props.size(); ++p)
            if (d.props[p].name == names[a]) d.ix[a] = static_cast<int>(p);
    }
    if (d.ix[0] < 0 || d.ix[1] < 0 || d.ix[2] < 0) throw FormatError(path + ": PLY vertices have no x y z");
    for (const auto& p : d.props) d.stride += p.size;
    if (d.enc != Enc::ascii) {  // a corrupt count must not allocate memory the file cannot fill
        const auto here = in.tellg();
        in.seekg(0, std::ios::end);
        const auto remaining = static_cast<std::uint64_t>(in.tellg() - here);
        in.seekg(here);
        if (d.stride && d.nvert > remaining / d.stride)
            throw FormatError(path + ": truncated or corrupt PLY: " + std::to_string(d.nvert) + " vertices of " +
                              std::to_string(d.stride) + " bytes need more than the " + std::to_string(remaining) +
                              " bytes left");
    }
    d.native = d.enc == Enc::le && std::endian::native == std::endian::little && d.props.size() == 8;
    for (int a = 0; a < 8 && d.native; ++a)
        d.native = d.ix[a] == a && (d.props[a].type == "float" || d.props[a].type == "float32");
    d.vals.resize(d.props.size());
    d.raw.resize(d.stride);
}

PlyPointReader::~PlyPointReader() = default;

const std::vector<std::string>& PlyPointReader::comments() const { return d_->comments; }
std::uint64_t PlyPointReader::count() const { return d_->nvert; }
const std::string& PlyPointReader::path() const { return d_->path; }

std::size_t PlyPointReader::read(std::vector<PointRecord>& out, std::size_t max) {
    Impl& d = *d_;
    using Enc = Impl::Enc;
    const std::string& path = d.path;
    std::ifstream& in = d.in;
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(max, d.nvert - d.done));
    out.resize(n);
    if (d.native) {
        static_assert(sizeof(PointRecord) == 32);
        if (n && !in.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(n * sizeof(PointRecord)))) {
            const std::uint64_t got = d.done + static_cast<std::uint64_t>(in.gcount()) / sizeof(PointRecord);
            throw FormatError(path + ": truncated PLY body at vertex " + std::to_string(got) + " of " + std::to_string(d.nvert));
        }
    } else {
        for (std::size_t i = 0; i < n; ++i) {
            const std::uint64_t v = d.done + i;
            if (d.enc == Enc::ascii) {
                for (auto& x : d.vals)
                    if (!(in >> x)) throw FormatError(path + ": truncated PLY body at vertex " + std::to_string(v));
            } else {
                if (!in.read(reinterpret_cast<char*>(d.raw.data()), static_cast<std::streamsize>(d.stride)))
                    throw FormatError(path + ": truncated PLY body at vertex " + std::to_string(v) + " of " + std::to_string(d.nvert));
                std::size_t off = 0;
                for (std::size_t p = 0; p < d.props.size(); ++p) {
                    unsigned char b[8];
                    std::memcpy(b, d.raw.data() + off, d.props[p].size);
                    if ((d.enc == Enc::be) == (std::endian::native == std::endian::little))
                        std::reverse(b, b + d.props[p].size);
                    const std::string& t = d.props[p].type;
                    double x = 0;
                    if (t == "float" || t == "float32") { float f; std::memcpy(&f, b, 4); x = f; }
                    else if (t == "double" || t == "float64") { double dd; std::memcpy(&dd, b, 8); x = dd; }
                    else if (t == "uchar" || t == "uint8") x = b[0];
                    else if (t == "char" || t == "int8") x = static_cast<signed char>(b[0]);
                    else if (t == "short" || t == "int16") { std::int16_t s; std::memcpy(&s, b, 2); x = s; }
                    else if (t == "ushort" || t == "uint16") { std::uint16_t s; std::memcpy(&s, b, 2); x = s; }
                    else if (t == "int" || t == "int32") { std::int32_t s; std::memcpy(&s, b, 4); x = s; }
                    else { std::uint32_t s; std::memcpy(&s, b, 4); x = s; }
                    d.vals[p] = x;
                    off += d.props[p].size;
                }
            }
            float f[8];
            for (int a = 0; a < 8; ++a) f[a] = d.ix[a] >= 0 ? static_cast<float>(d.vals[d.ix[a]]) : 0.0f;
            std::memcpy(&out[i], f, sizeof f);
        }
    }
    d.done += n;
    if (d.done == d.nvert && d.other_elements.empty() && d.enc != Enc::ascii && !d.checked_tail) {
        d.checked_tail = true;
        in.peek();
        if (!in.eof()) throw FormatError(path + ": trailing bytes after the PLY vertex data");
    }
    return n;
}

PlyPoints read_ply_points(const std::string& path) {
    PlyPointReader r(path);
    PlyPoints out;
    out.comments = r.comments();
    r.read(out.points, static_cast<std::size_t>(r.count()));
    if (r.count() == 0) r.read(out.points, 0);  // trailing-bytes check of an empty set
    return out;
}

}  // namespace meshless
