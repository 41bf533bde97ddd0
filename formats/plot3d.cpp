#include "formats/plot3d.hpp"

#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "formats/binary_file.hpp"
#include "formats/json.hpp"
#include "formats/stored_type.hpp"
#include "formats/text_header.hpp"
#include "formats/ply.hpp"

namespace meshless {

namespace {

enum class Kind { xyz, q, func };
const char* kind_name(Kind k) { return k == Kind::xyz ? "xyz" : k == Kind::q ? "q" : "function"; }

using Dims = std::array<std::int64_t, 3>;

struct Layout {
    bool ascii = false, big = false, records = false, multi = false, iblank = false;
    int prec = 4;
    std::vector<Dims> dims;
    std::vector<std::int64_t> nvars;   // function files
    std::vector<std::uint64_t> base;   // per grid: byte offset (binary) or token index (ascii) of the first field value
    std::uint64_t expected = 0;        // bytes (binary) or tokens (ascii)
    std::string describe() const {
        std::string s = ascii ? "ASCII" : std::string(big ? "big" : "little") + "-endian " + (prec == 4 ? "float32" : "float64") +
                                              (records ? " Fortran-record" : " C");
        s += multi ? ", " + std::to_string(dims.size()) + " grids" : ", single grid";
        if (iblank) s += ", IBLANK";
        return s;
    }
};

std::string dims_text(const std::vector<Dims>& d) {
    std::string s;
    for (std::size_t g = 0; g < d.size(); ++g)
        s += (g ? ", " : "") + std::to_string(d[g][0]) + "x" + std::to_string(d[g][1]) + "x" + std::to_string(d[g][2]);
    return s;
}

struct Bin {
    const std::byte* p = nullptr;
    std::uint64_t n = 0;
    bool swap = false;
    std::int32_t i32(std::uint64_t off) const {
        std::uint32_t u;
        std::memcpy(&u, p + off, 4);
        if (swap) u = __builtin_bswap32(u);
        std::int32_t v;
        std::memcpy(&v, &u, 4);
        return v;
    }
    double real(std::uint64_t off, int prec) const {
        if (prec == 4) {
            std::uint32_t u;
            std::memcpy(&u, p + off, 4);
            if (swap) u = __builtin_bswap32(u);
            float f;
            std::memcpy(&f, &u, 4);
            return f;
        }
        std::uint64_t u;
        std::memcpy(&u, p + off, 8);
        if (swap) u = __builtin_bswap64(u);
        double d;
        std::memcpy(&d, &u, 8);
        return d;
    }
};

// dims[0]*dims[1]*dims[2] without overflow (false when it would overflow).
bool node_count(const Dims& d, std::uint64_t& n) {
    std::uint64_t ij = 0;
    return !__builtin_mul_overflow(static_cast<std::uint64_t>(d[0]), static_cast<std::uint64_t>(d[1]), &ij) &&
           !__builtin_mul_overflow(ij, static_cast<std::uint64_t>(d[2]), &n);
}

std::uint64_t grid_payload(Kind k, std::uint64_t N, int prec, bool iblank, std::int64_t nv) {
    if (k == Kind::xyz) return 3 * N * prec + (iblank ? 4 * N : 0);
    if (k == Kind::q) return 5 * N * prec;
    return static_cast<std::uint64_t>(nv) * N * prec;
}

// Parses a binary header under one layout hypothesis; false when implausible.
bool try_binary(const Bin& b, Kind kind, Layout& L) {
    const std::uint64_t n = b.n;
    std::uint64_t off = 0;
    std::int64_t ng = 1;
    const int per = kind == Kind::func ? 4 : 3;
    const std::uint64_t mk = L.records ? 4 : 0;
    if (L.multi) {
        if (n < 2 * mk + 4) return false;
        if (L.records && (b.i32(0) != 4 || b.i32(8) != 4)) return false;
        ng = b.i32(mk);
        off = 2 * mk + 4;
        if (ng < 1 || ng > 1000000) return false;
    }
    const std::uint64_t hb = 4ull * per * static_cast<std::uint64_t>(ng);
    if (off + hb + 2 * mk > n) return false;
    if (L.records && (b.i32(off) != static_cast<std::int64_t>(hb) || b.i32(off + 4 + hb) != static_cast<std::int64_t>(hb)))
        return false;
    off += mk;
    L.dims.assign(static_cast<std::size_t>(ng), Dims{});
    L.nvars.assign(static_cast<std::size_t>(ng), 0);
    for (std::int64_t g = 0; g < ng; ++g) {
        for (int a = 0; a < 3; ++a) {
            const std::int64_t d = b.i32(off + 4 * (per * g + a));
            if (d < 1 || static_cast<std::uint64_t>(d) > n) return false;
            L.dims[g][a] = d;
        }
        if (kind == Kind::func) {
            const std::int64_t nv = b.i32(off + 4 * (per * g + 3));
            if (nv < 1 || nv > 100000) return false;
            L.nvars[g] = nv;
        }
    }
    off += hb + mk;
    L.base.assign(static_cast<std::size_t>(ng), 0);
    for (std::int64_t g = 0; g < ng; ++g) {
        std::uint64_t N = 0;
        if (!node_count(L.dims[g], N) || N > n) return false;
        if (kind == Kind::q) {  // fsmach alpha re time
            const std::uint64_t rb = 4ull * L.prec;
            if (L.records && (off + 4 > n || b.i32(off) != static_cast<std::int64_t>(rb))) return false;
            off += rb + 2 * mk;
        }
        const std::uint64_t pb = grid_payload(kind, N, L.prec, L.iblank, L.nvars[g]);
        if (L.records && (off + 4 > n || b.i32(off) != static_cast<std::int64_t>(pb))) return false;
        L.base[g] = off + mk;
        off += pb + 2 * mk;
        if (off > 4 * n + (1u << 20)) return false;
    }
    L.expected = off;
    return true;
}

bool looks_ascii(const std::vector<std::byte>& bytes) {
    const std::size_t m = std::min<std::size_t>(bytes.size(), 256);
    if (m == 0) return false;
    for (std::size_t i = 0; i < m; ++i) {
        const char c = static_cast<char>(bytes[i]);
        if (!(std::isdigit(static_cast<unsigned char>(c)) || std::isspace(static_cast<unsigned char>(c)) || c == '.' ||
              c == '-' || c == '+' || c == 'e' || c == 'E' || c == 'd' || c == 'D' || c == ','))
            return false;
    }
    return true;
}

std::vector<double> ascii_tokens(const std::vector<std::byte>& bytes, const std::string& path) {
    std::vector<double> out;
    const char* s = reinterpret_cast<const char*>(bytes.data());
    const std::size_t n = bytes.size();
    std::size_t i = 0;
    std::string tmp;
    while (i < n) {
        while (i < n && (std::isspace(static_cast<unsigned char>(s[i])) || s[i] == ',')) ++i;
        std::size_t j = i;
        while (j < n && !std::isspace(static_cast<unsigned char>(s[j])) && s[j] != ',') ++j;
        if (j == i) break;
        double v;
        const char* b = s + i;
        if (*b == '+') ++b;
        auto r = std::from_chars(b, s + j, v);
        if (r.ec != std::errc() || r.ptr != s + j) {  // Fortran 'D' exponents
            tmp.assign(s + i, j - i);
            for (char& c : tmp)
                if (c == 'd' || c == 'D') c = 'e';
            char* e = nullptr;
            v = std::strtod(tmp.c_str(), &e);
            if (e != tmp.c_str() + tmp.size())
                throw FormatError(path + ": bad number '" + ply_escape(std::string_view(s + i, j - i)) + "' at token " + std::to_string(out.size()));
        }
        out.push_back(v);
        i = j;
    }
    return out;
}

bool try_ascii(const std::vector<double>& t, Kind kind, Layout& L) {
    std::uint64_t off = 0;
    std::int64_t ng = 1;
    auto int_at = [&](std::uint64_t k, std::int64_t& v) {
        if (k >= t.size() || t[k] != std::floor(t[k]) || t[k] < 1 || t[k] > 1e9) return false;
        v = static_cast<std::int64_t>(t[k]);
        return true;
    };
    if (L.multi) {
        if (!int_at(0, ng) || ng > 1000000) return false;
        off = 1;
    }
    const int per = kind == Kind::func ? 4 : 3;
    L.dims.assign(static_cast<std::size_t>(ng), Dims{});
    L.nvars.assign(static_cast<std::size_t>(ng), 0);
    for (std::int64_t g = 0; g < ng; ++g) {
        for (int a = 0; a < 3; ++a)
            if (!int_at(off + per * g + a, L.dims[g][a])) return false;
        if (kind == Kind::func && !int_at(off + per * g + 3, L.nvars[g])) return false;
    }
    off += static_cast<std::uint64_t>(per * ng);
    L.base.assign(static_cast<std::size_t>(ng), 0);
    for (std::int64_t g = 0; g < ng; ++g) {
        std::uint64_t N = 0;
        if (!node_count(L.dims[g], N) || N > t.size()) return false;
        if (kind == Kind::q) off += 4;
        L.base[g] = off;
        off += kind == Kind::xyz ? (3 + (L.iblank ? 1 : 0)) * N : kind == Kind::q ? 5 * N : static_cast<std::uint64_t>(L.nvars[g]) * N;
    }
    L.expected = off;
    return true;
}

std::string order_name(bool big) { return big ? "big-endian" : "little-endian"; }

// Whether the file is named as a PLOT3D grid: a grid extension (.x, .xyz, .g), or a name with "xyz"
// whose q file lies beside it (combxyz.bin and combq.bin). Then a header that parses is trusted
// even when the data is shorter than it says (a truncated grid file), as one framed by Fortran
// record markers always is. ("xyz" alone is not enough: cloud_xyzv.bin may hold float32 records.)
bool named_xyz(const std::string& path) {
    const std::string e = to_lower(std::filesystem::path(path).extension().string());
    return e == ".x" || e == ".xyz" || e == ".g" || !plot3d_sibling_q(path).empty();
}

// Detects the layout of an xyz file.
Layout detect_xyz(const std::vector<std::byte>& bytes, const std::vector<double>* tokens, const std::string& path,
                  const PointSetOptions& o, std::vector<std::string>* notes) {
    std::vector<Layout> exact, trailing, cut;  // cut: a plausible header, the data shorter than it says
    if (tokens) {
        for (int multi = 0; multi < 2; ++multi)
            for (int ib = 0; ib < 2; ++ib) {
                Layout L;
                L.ascii = true, L.multi = multi, L.iblank = ib;
                if (!try_ascii(*tokens, Kind::xyz, L)) continue;
                if (L.expected == tokens->size()) exact.push_back(L);
                else if (L.expected < tokens->size()) trailing.push_back(L);
            }
    } else {
        for (int big = 0; big < 2; ++big)
            for (int rec = 1; rec >= 0; --rec)
                for (int multi = 0; multi < 2; ++multi)
                    for (int prec = 4; prec <= 8; prec += 4)
                        for (int ib = 0; ib < 2; ++ib) {
                            Layout L;
                            L.big = big, L.records = rec, L.multi = multi, L.prec = prec, L.iblank = ib;
                            Bin b{bytes.data(), bytes.size(), (big == 1) == host_is_little_endian()};
                            if (!try_binary(b, Kind::xyz, L)) continue;
                            if (L.expected == bytes.size()) exact.push_back(L);
                            else if (L.expected < bytes.size()) trailing.push_back(L);
                            else if (L.records || named_xyz(path)) cut.push_back(L);
                        }
    }
    const std::uint64_t size = tokens ? tokens->size() : bytes.size();
    const char* unit = tokens ? " numbers" : " bytes";
    auto allowed = [&](const Layout& L) {
        return tokens || o.byte_order == ByteOrder::detect || L.big == (o.byte_order == ByteOrder::big);
    };
    for (const auto& L : exact)
        if (allowed(L)) return L;
    // a header framed by matching Fortran record markers is the file's, even cut short, before a
    // C-layout guess that would leave trailing bytes
    auto truncated = [&](const Layout& L) {
        return FormatError(path + ": truncated PLOT3D xyz file: " + std::to_string(size) + unit + ", the header (" + L.describe() +
                           ", " + dims_text(L.dims) + ") needs " + std::to_string(L.expected));
    };
    for (const auto& L : cut)
        if (L.records && allowed(L)) throw truncated(L);
    const Layout* shortest_cut = nullptr;
    for (const auto& L : cut)
        if (allowed(L) && (!shortest_cut || L.expected < shortest_cut->expected)) shortest_cut = &L;
    const Layout* best = nullptr;
    for (const auto& L : trailing)
        if (allowed(L) && (!best || L.expected > best->expected)) best = &L;
    if (best) {
        const std::uint64_t extra = size - best->expected;
        if (!o.allow_trailing) {
            const std::string over = std::to_string(extra) + " trailing" + unit + " after the PLOT3D xyz data (" +
                                     best->describe() + ", " + dims_text(best->dims) + "); --allow-trailing ignores them";
            // a grid file cut short can also read as a smaller layout (float32 for float64, no
            // IBLANK, ...) with bytes to spare: both readings are said, the nearer one first
            if (!shortest_cut) throw FormatError(path + ": " + over);
            const FormatError cut_short = truncated(*shortest_cut);
            if (shortest_cut->expected - size < extra) throw FormatError(std::string(cut_short.what()) + "; or " + over);
            throw FormatError(path + ": " + over + "; or " + std::string(cut_short.what()).substr(path.size() + 2));
        }
        if (notes) notes->push_back(std::to_string(extra) + unit + " after the xyz data ignored");
        return *best;
    }
    if (!exact.empty())
        throw FormatError(path + ": PLOT3D header dims are implausible as " + order_name(o.byte_order == ByteOrder::big) +
                          " (they only make sense byte-swapped: " + dims_text(exact.front().dims) + "); the file looks " +
                          order_name(exact.front().big));
    if (size == 0) throw FormatError(path + ": empty file");
    if (shortest_cut) throw truncated(*shortest_cut);
    throw FormatError(path + ": not a PLOT3D xyz file: no layout (byte order, C/Fortran records, grids, float32/64, IBLANK) "
                             "fits its " + std::to_string(size) + unit);
}

// Parses a q or function file with the xyz file's layout; checks the grids agree.
Layout parse_values_file(const std::vector<std::byte>& bytes, const std::vector<double>* tokens, Kind kind,
                         const Layout& xyz, const std::string& path, const std::string& xyz_path,
                         const PointSetOptions& o, std::vector<std::string>* notes) {
    if (bytes.empty()) throw FormatError(path + ": empty file");
    Layout L;
    L.ascii = xyz.ascii, L.big = xyz.big, L.records = xyz.records, L.multi = xyz.multi, L.prec = xyz.prec;
    bool ok = false;
    if (xyz.ascii) {
        if (!tokens) throw FormatError(path + ": binary " + kind_name(kind) + " file for the ASCII xyz file " + xyz_path);
        ok = try_ascii(*tokens, kind, L);
    } else {
        if (tokens) throw FormatError(path + ": ASCII " + std::string(kind_name(kind)) + " file for the binary xyz file " + xyz_path);
        Bin b{bytes.data(), bytes.size(), xyz.big == host_is_little_endian()};
        ok = try_binary(b, kind, L);
        if (!ok) {  // explain a byte-order mismatch
            Layout S = L;
            S.big = !xyz.big;
            Bin bs{bytes.data(), bytes.size(), S.big == host_is_little_endian()};
            if (try_binary(bs, kind, S))
                throw FormatError(path + ": PLOT3D " + kind_name(kind) + " header is " + order_name(S.big) + " but the xyz file " +
                                  xyz_path + " is " + order_name(xyz.big));
        }
    }
    if (!ok) throw FormatError(path + ": implausible PLOT3D " + std::string(kind_name(kind)) + " header for the xyz layout (" + xyz.describe() + ")");
    if (L.dims != xyz.dims)
        throw FormatError(path + ": PLOT3D " + std::string(kind_name(kind)) + " dims " + dims_text(L.dims) + " disagree with the xyz dims " +
                          dims_text(xyz.dims) + " of " + xyz_path);
    const std::uint64_t size = tokens ? tokens->size() : bytes.size();
    const char* unit = tokens ? " numbers" : " bytes";
    if (L.expected > size)
        throw FormatError(path + ": truncated PLOT3D " + std::string(kind_name(kind)) + " file: " + std::to_string(size) + unit + ", the header needs " +
                          std::to_string(L.expected));
    if (L.expected < size) {
        const std::uint64_t extra = size - L.expected;
        if (!o.allow_trailing)
            throw FormatError(path + ": " + std::to_string(extra) + " trailing" + unit + " after the PLOT3D " + kind_name(kind) +
                              " data (the header accounts for " + std::to_string(L.expected) + "); --allow-trailing ignores them");
        if (notes) notes->push_back(std::to_string(extra) + unit + " after the " + kind_name(kind) + " data ignored");
    }
    return L;
}

int q_component(const PointSetOptions& o, const std::string& path) {
    if (o.value_name.empty()) {
        if (o.q_component < 0 || o.q_component > 5) throw FormatError(path + ": q component " + std::to_string(o.q_component) + " out of 0..5");
        return o.q_component;
    }
    const std::string n = to_lower(o.value_name);
    if (n == "density" || n == "rho") return 0;
    if (n == "rhou" || n == "x-momentum") return 1;
    if (n == "rhov" || n == "y-momentum") return 2;
    if (n == "rhow" || n == "z-momentum") return 3;
    if (n == "energy" || n == "rhoe") return 4;
    if (n == "speed" || n == "velocity-magnitude") return 5;
    throw FormatError(path + ": no q quantity '" + o.value_name + "' (density, rhou, rhov, rhow, energy, speed)");
}

constexpr const char* kQNames[6] = {"density", "x-momentum", "y-momentum", "z-momentum", "energy", "speed"};

std::string file_name(const std::string& p) { return std::filesystem::path(p).filename().string(); }

}  // namespace

std::string plot3d_sibling_q(const std::string& xyz_path) {
    const std::filesystem::path p(xyz_path);
    std::string name = p.filename().string();
    std::string cand;
    const std::size_t k = name.rfind("xyz");
    if (k != std::string::npos) {
        cand = name.substr(0, k) + "q" + name.substr(k + 3);
    } else if (p.extension() == ".x") {
        cand = p.stem().string() + ".q";
    }
    if (cand.empty()) return "";
    const std::filesystem::path q = p.parent_path() / cand;
    std::error_code ec;
    return std::filesystem::is_regular_file(q, ec) ? q.string() : "";
}

bool looks_like_plot3d_xyz(const std::string& path) {
    try {
        const std::uint64_t size = regular_file_size(path);
        if (size < 12) return false;
        const auto bytes = read_file_bytes(path);
        if (looks_ascii(bytes)) {
            const auto t = ascii_tokens(bytes, path);
            for (int multi = 0; multi < 2; ++multi)
                for (int ib = 0; ib < 2; ++ib) {
                    Layout L;
                    L.ascii = true, L.multi = multi, L.iblank = ib;
                    if (try_ascii(t, Kind::xyz, L) && L.expected <= t.size()) return true;
                }
            return false;
        }
        for (int big = 0; big < 2; ++big)
            for (int rec = 0; rec < 2; ++rec)
                for (int multi = 0; multi < 2; ++multi)
                    for (int prec = 4; prec <= 8; prec += 4)
                        for (int ib = 0; ib < 2; ++ib) {
                            Layout L;
                            L.big = big, L.records = rec, L.multi = multi, L.prec = prec, L.iblank = ib;
                            Bin b{bytes.data(), bytes.size(), (big == 1) == host_is_little_endian()};
                            if (try_binary(b, Kind::xyz, L) &&
                                (L.expected == bytes.size() || (L.expected > bytes.size() && (L.records || named_xyz(path)))))
                                return true;  // (a cut one: the reader says it is truncated)
                        }
    } catch (const std::exception&) {
    }
    return false;
}

namespace {

// One parse of an xyz file and its q/function file, shared by the point-set and the structured
// readers (the layout is detected once, here).
struct Parsed {
    std::string xyz_path, vpath;
    std::vector<std::byte> xb, vb;
    std::vector<double> xt, vt;
    Layout X, V;
    Kind vkind = Kind::xyz;  // xyz: positions only
    int comp = 0;
    std::string value_name;
};

Parsed parse_plot3d(const std::string& xyz_path, const PointSetOptions& o, std::vector<std::string>* notes) {
    Parsed P;
    P.xyz_path = xyz_path;
    P.xb = read_file_bytes(xyz_path);
    if (P.xb.empty()) throw FormatError(xyz_path + ": empty file");
    const bool ascii = looks_ascii(P.xb);
    if (ascii) P.xt = ascii_tokens(P.xb, xyz_path);
    P.X = detect_xyz(P.xb, ascii ? &P.xt : nullptr, xyz_path, o, notes);
    if (notes) notes->push_back("xyz layout: " + P.X.describe());

    if (!o.function_file.empty()) P.vkind = Kind::func, P.vpath = o.function_file;
    else if (!o.q_file.empty()) P.vkind = Kind::q, P.vpath = o.q_file;
    else if (!(P.vpath = plot3d_sibling_q(xyz_path)).empty()) P.vkind = Kind::q;
    if (P.vkind == Kind::xyz) return P;
    P.vb = read_file_bytes(P.vpath);
    const bool vascii = !P.vb.empty() && looks_ascii(P.vb);
    if (ascii && vascii) P.vt = ascii_tokens(P.vb, P.vpath);
    P.V = parse_values_file(P.vb, vascii ? &P.vt : nullptr, P.vkind, P.X, P.vpath, xyz_path, o, notes);
    if (P.vkind == Kind::q) {
        P.comp = q_component(o, P.vpath);
        P.value_name = kQNames[P.comp];
    } else {
        P.comp = o.value_index.value_or(0);
        for (std::size_t g = 0; g < P.V.nvars.size(); ++g)
            if (P.comp < 0 || P.comp >= P.V.nvars[g])
                throw FormatError(P.vpath + ": function variable " + std::to_string(P.comp) + " out of range (grid " +
                                  std::to_string(g + 1) + " has " + std::to_string(P.V.nvars[g]) + ")");
        P.value_name = "function " + std::to_string(P.comp);
    }
    if (notes) notes->push_back(std::string(kind_name(P.vkind)) + " file: " + P.vpath);
    return P;
}

std::uint64_t grid_nodes(const Layout& L, std::size_t g) {
    return static_cast<std::uint64_t>(L.dims[g][0]) * L.dims[g][1] * L.dims[g][2];
}

// Calls f(i, blanked, x, y, z, v) for every node i of grid g in file order (i fastest). The layout
// check (expected size == file size) has proven every offset read here.
template <class F>
void for_each_node(const Parsed& P, std::size_t g, F&& f) {
    const Layout& X = P.X;
    const Bin xbin{P.xb.data(), P.xb.size(), X.big == host_is_little_endian()};
    const Bin vbin{P.vb.data(), P.vb.size(), X.big == host_is_little_endian()};
    auto real = [&](bool values, std::uint64_t base, std::uint64_t k) {
        if (X.ascii) return values ? P.vt[base + k] : P.xt[base + k];
        return values ? vbin.real(base + k * X.prec, X.prec) : xbin.real(base + k * X.prec, X.prec);
    };
    const std::uint64_t N = grid_nodes(X, g);
    const std::uint64_t xb0 = X.base[g];
    for (std::uint64_t i = 0; i < N; ++i) {
        bool blanked = false;
        if (X.iblank) {
            const double ib = X.ascii ? P.xt[xb0 + 3 * N + i] : static_cast<double>(xbin.i32(xb0 + 3 * N * X.prec + 4 * i));
            blanked = ib == 0;
        }
        double v = 0;
        if (P.vkind == Kind::q) {
            const std::uint64_t vb0 = P.V.base[g];
            if (P.comp < 5) {
                v = real(true, vb0, static_cast<std::uint64_t>(P.comp) * N + i);
            } else {
                const double rho = real(true, vb0, i);
                const double mu = real(true, vb0, N + i), mv = real(true, vb0, 2 * N + i), mw = real(true, vb0, 3 * N + i);
                v = std::sqrt(mu * mu + mv * mv + mw * mw) / rho;
            }
        } else if (P.vkind == Kind::func) {
            v = real(true, P.V.base[g], static_cast<std::uint64_t>(P.comp) * N + i);
        }
        f(i, blanked, real(false, xb0, i), real(false, xb0, N + i), real(false, xb0, 2 * N + i), v);
    }
}

std::string grid_name(const Parsed& P, std::size_t g) {
    return P.X.dims.size() > 1 ? "grid " + std::to_string(g + 1) : file_name(P.xyz_path);
}

// The .p3d meta file's first entry: the xyz path and the options it implies.
std::string resolve_meta(const std::string& p3d_path, const PointSetOptions& o, PointSetOptions& opt,
                         std::vector<std::string>* notes) {
    const auto bytes = read_file_bytes(p3d_path);
    if (bytes.empty()) throw FormatError(p3d_path + ": empty file");
    const Json j = parse_json(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), p3d_path);
    const Json* files = j.find("filenames");
    if (!files || !files->is_array() || files->arr.empty())
        throw FormatError(p3d_path + ": PLOT3D meta file has no \"filenames\" entries");
    const Json& f0 = files->arr.front();
    const Json* xyz = f0.find("xyz");
    if (!xyz || !xyz->is_string()) throw FormatError(p3d_path + ": the first \"filenames\" entry has no \"xyz\" file");
    opt = o;
    const Json* auto_detect = j.find("auto-detect-format");
    const Json* bo = j.find("byte-order");
    if (opt.byte_order == ByteOrder::detect && bo && bo->is_string() && !(auto_detect && auto_detect->b)) {
        if (to_lower(bo->str) == "big") opt.byte_order = ByteOrder::big;
        else if (to_lower(bo->str) == "little") opt.byte_order = ByteOrder::little;
        else throw FormatError(p3d_path + ": bad \"byte-order\" '" + ply_escape(bo->str) + "'");
    }
    if (const Json* q = f0.find("q"); q && q->is_string() && opt.q_file.empty() && opt.function_file.empty())
        opt.q_file = resolve_relative(p3d_path, q->str);
    if (const Json* fn = f0.find("function"); fn && fn->is_string() && opt.q_file.empty() && opt.function_file.empty())
        opt.function_file = resolve_relative(p3d_path, fn->str);
    if (notes && files->arr.size() > 1)
        notes->push_back(std::to_string(files->arr.size()) + " time steps in the meta file; reading the first");
    return resolve_relative(p3d_path, xyz->str);
}

}  // namespace

PointSet read_plot3d(const std::string& xyz_path, const PointSetOptions& o, std::vector<std::string>* notes) {
    const Parsed P = parse_plot3d(xyz_path, o, notes);
    PointSetBuilder b(xyz_path, o);
    std::uint64_t total = 0;
    for (std::size_t g = 0; g < P.X.dims.size(); ++g) total += grid_nodes(P.X, g);
    b.reserve(static_cast<std::size_t>(total));
    for (std::size_t g = 0; g < P.X.dims.size(); ++g) {
        b.begin_block(grid_name(P, g), P.X.dims[g]);
        const std::string where = "grid " + std::to_string(g + 1) + " point";
        for_each_node(P, g, [&](std::uint64_t i, bool blanked, double x, double y, double z, double v) {
            if (blanked) b.add_blanked();
            else b.add(x, y, z, v, where.c_str(), i);
        });
    }
    return b.finish(P.value_name, P.vkind != Kind::xyz);
}

PointSet read_plot3d_meta(const std::string& p3d_path, const PointSetOptions& o, std::vector<std::string>* notes) {
    PointSetOptions opt;
    const std::string xyz = resolve_meta(p3d_path, o, opt, notes);
    return with_error_prefix(p3d_path, p3d_path + ": ", [&] { return read_plot3d(xyz, opt, notes); });
}

Multiblock read_plot3d_blocks(const std::string& xyz_path, const PointSetOptions& o, std::vector<std::string>* notes) {
    const Parsed P = parse_plot3d(xyz_path, o, notes);
    if (P.vkind == Kind::xyz)
        throw FormatError(xyz_path + ": no values: no q file beside it and no --q/--function file (a block input needs a scalar)");
    Multiblock mb;
    mb.format = "plot3d";
    mb.value_name = P.value_name;
    for (std::size_t g = 0; g < P.X.dims.size(); ++g) {
        StructuredBlock sb;
        sb.name = grid_name(P, g);
        sb.dims = P.X.dims[g];
        const std::uint64_t N = grid_nodes(P.X, g);
        sb.node.resize(static_cast<std::size_t>(N));
        sb.value.resize(static_cast<std::size_t>(N));
        sb.valid.assign(static_cast<std::size_t>(N), 1);
        std::uint64_t invalid = 0;
        for_each_node(P, g, [&](std::uint64_t i, bool blanked, double x, double y, double z, double v) {
            sb.node[i] = Vec3{x, y, z};
            sb.value[i] = v;
            if (blanked) {
                sb.valid[i] = 0, ++mb.blanked, ++invalid;
            } else if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z) || !std::isfinite(v)) {
                if (o.strict)
                    throw FormatError(xyz_path + ": grid " + std::to_string(g + 1) + " point " + std::to_string(i) +
                                      ": non-finite " +
                                      (std::isfinite(x) && std::isfinite(y) && std::isfinite(z) ? "value" : "coordinate") +
                                      " (NaN/Inf are refused in strict mode)");
                sb.valid[i] = 0, ++mb.nonfinite, ++invalid;
            }
        });
        if (invalid == N)
            throw FormatError(xyz_path + ": grid " + std::to_string(g + 1) + " (" + dims_text({P.X.dims[g]}) +
                              "): every node is blanked (IBLANK 0) or non-finite");
        if (invalid == 0) sb.valid.clear();
        mb.blocks.push_back(std::move(sb));
    }
    return mb;
}

Multiblock read_plot3d_meta_blocks(const std::string& p3d_path, const PointSetOptions& o, std::vector<std::string>* notes) {
    PointSetOptions opt;
    const std::string xyz = resolve_meta(p3d_path, o, opt, notes);
    return with_error_prefix(p3d_path, p3d_path + ": ", [&] { return read_plot3d_blocks(xyz, opt, notes); });
}

}  // namespace meshless
