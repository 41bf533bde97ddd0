#include "formats/cluster_tree_file.hpp"

#include <bit>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <vector>

#include "formats/atomic_file.hpp"
#include "formats/binary_file.hpp"
#include "formats/crc32.hpp"
#include "kernels/errors.hpp"

namespace meshless {

static_assert(std::endian::native == std::endian::little, "the .mlh codec assumes a little-endian host");

namespace {

constexpr std::size_t kMaxNameBytes = 1024;


template <class T>
void put(std::string& s, T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
}

template <class T>
T get(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));
    return v;
}

std::string meta_bytes(const ClusterTree& t) {
    std::string m;
    const CbtStats& s = t.stats;
    const CbtParams& p = t.params;
    put<std::uint64_t>(m, s.samples);
    put<std::uint64_t>(m, s.dropped_nonfinite);
    put<std::uint64_t>(m, s.splits);
    put<std::uint64_t>(m, s.skipped);
    put<std::uint32_t>(m, s.depth);
    put<std::uint32_t>(m, p.neighbours);
    put<std::uint32_t>(m, p.min_cluster);
    put<std::uint32_t>(m, static_cast<std::uint32_t>(p.scaling));
    put<std::uint64_t>(m, p.max_splits);
    put<double>(m, p.max_error);
    put<double>(m, p.hardy_c_rel);
    put<double>(m, p.hardy_c_world);
    put<double>(m, s.hardy_c_world);
    put<double>(m, s.error_reached);
    for (const Vec3& b : t.bounds) {
        put<double>(m, b.x);
        put<double>(m, b.y);
        put<double>(m, b.z);
    }
    put<double>(m, t.value_range[0]);
    put<double>(m, t.value_range[1]);
    put<std::uint32_t>(m, static_cast<std::uint32_t>(p.order));
    put<std::uint32_t>(m, static_cast<std::uint32_t>(p.value));
    put<double>(m, p.size_term);
    const std::string name = t.value_name.substr(0, kMaxNameBytes);
    put<std::uint32_t>(m, static_cast<std::uint32_t>(name.size()));
    m += name;
    if (t.certified.size() > kMaxCertifiedErrors)
        throw InvalidArgument("cluster tree: " + std::to_string(t.certified.size()) + " certified errors, at most " +
                              std::to_string(kMaxCertifiedErrors));
    put<std::uint32_t>(m, static_cast<std::uint32_t>(t.certified.size()));
    for (const CertifiedError& c : t.certified) {
        put<std::uint64_t>(m, c.count);
        put<double>(m, c.max_error);
        put<double>(m, c.hardy_c_rel);
    }
    put<std::uint64_t>(m, t.samples_hash);
    return m;
}

/// The version a tree is written in (what the writer writes: the newest).
std::uint32_t version_of(const ClusterTree&) { return kClusterTreeFileVersion; }

/// The certified errors of a version 3 or 4 meta, `at` bytes into it (after the name), checked;
/// `tail` meta bytes follow them (version 4: the samples' hash).
std::vector<CertifiedError> parse_certified(const unsigned char* m, std::uint64_t at, std::uint64_t meta, std::uint64_t tail,
                                            std::uint64_t leaves, const std::function<FormatError(std::uint64_t, const std::string&)>& fail) {
    if (meta - at < 4 + tail) throw fail(kClusterTreeHeaderBytes + at, "meta without its certified error count" + std::string(tail ? " and samples hash" : ""));
    meta -= tail;
    const std::uint32_t k = get<std::uint32_t>(m + at);
    if (k > kMaxCertifiedErrors)
        throw fail(kClusterTreeHeaderBytes + at, std::to_string(k) + " certified errors, at most " + std::to_string(kMaxCertifiedErrors));
    if (meta - at - 4 != std::uint64_t{k} * kClusterTreeCertifiedBytes)
        throw fail(kClusterTreeHeaderBytes + at, std::to_string(k) + " certified errors do not fill the " + std::to_string(meta - at - 4) +
                                                     " meta bytes after the count");
    std::vector<CertifiedError> out(k);
    for (std::uint32_t i = 0; i < k; ++i) {
        const std::uint64_t o = at + 4 + std::uint64_t{i} * kClusterTreeCertifiedBytes;
        CertifiedError& c = out[i];
        c.count = get<std::uint64_t>(m + o);
        c.max_error = get<double>(m + o + 8);
        c.hardy_c_rel = get<double>(m + o + 16);
        const std::string which = "certified error " + std::to_string(i) + ": ";
        if (c.count < 1 || c.count > leaves)
            throw fail(kClusterTreeHeaderBytes + o, which + "count " + std::to_string(c.count) + " outside 1.." + std::to_string(leaves));
        if (i > 0 && c.count <= out[i - 1].count) throw fail(kClusterTreeHeaderBytes + o, which + "counts not ascending");
        if (std::isnan(c.max_error) || c.max_error < 0) throw fail(kClusterTreeHeaderBytes + o + 8, which + "error negative or NaN");
        if (!(c.hardy_c_rel > 0 && c.hardy_c_rel <= 100)) throw fail(kClusterTreeHeaderBytes + o + 16, which + "Hardy c outside (0, 100]");
    }
    return out;
}

std::string header_bytes(std::uint32_t version, std::uint64_t file_bytes, std::uint64_t meta, std::uint64_t nodes) {
    std::string h(kClusterTreeMagic, 8);
    put<std::uint32_t>(h, version);
    put<std::uint32_t>(h, static_cast<std::uint32_t>(kClusterTreeHeaderBytes));
    put<std::uint64_t>(h, file_bytes);
    put<std::uint64_t>(h, meta);
    put<std::uint64_t>(h, nodes);
    h.resize(60, '\0');
    put<std::uint32_t>(h, crc32_ieee(0, h.data(), 60));
    return h;
}

}  // namespace

std::string cluster_tree_bytes(const ClusterTree& tree) {
    const std::string meta = meta_bytes(tree);
    const std::uint64_t n = tree.nodes.size();
    const std::uint64_t total = kClusterTreeHeaderBytes + meta.size() + 4 + n * kClusterTreeNodeBytes + 4;
    std::string out = header_bytes(version_of(tree), total, meta.size(), n);
    out += meta;
    put<std::uint32_t>(out, crc32_ieee(0, meta.data(), meta.size()));
    const std::size_t at = out.size();
    out.append(reinterpret_cast<const char*>(tree.nodes.data()), n * kClusterTreeNodeBytes);
    put<std::uint32_t>(out, crc32_ieee(0, out.data() + at, n * kClusterTreeNodeBytes));
    return out;
}

void write_cluster_tree_file(const std::string& path, const ClusterTree& tree) {
    if (is_streaming_output(path))
        throw InvalidArgument(path + ": a cluster tree is written to a regular file (.mlh), not a stream");
    static_assert(sizeof(CbtNode) == kClusterTreeNodeBytes);
    const std::string meta = meta_bytes(tree);
    const std::uint64_t n = tree.nodes.size();
    const std::uint64_t total = kClusterTreeHeaderBytes + meta.size() + 4 + n * kClusterTreeNodeBytes + 4;
    AtomicFile f(path, Durability::fsync);
    f.write(header_bytes(version_of(tree), total, meta.size(), n));
    f.write(meta);
    std::string crc;
    put<std::uint32_t>(crc, crc32_ieee(0, meta.data(), meta.size()));
    f.write(crc);
    std::uint32_t c = 0;
    constexpr std::size_t kStep = 1 << 16;  // nodes per write
    for (std::size_t i = 0; i < n; i += kStep) {
        const std::size_t m = std::min<std::size_t>(kStep, n - i) * kClusterTreeNodeBytes;
        const void* p = tree.nodes.data() + i;
        c = crc32_ieee(c, p, m);
        f.write(p, m);
    }
    crc.clear();
    put<std::uint32_t>(crc, c);
    f.write(crc);
    f.commit();
}

ClusterTree parse_cluster_tree_bytes(std::span<const unsigned char> b, const std::string& name) {
    auto fail = [&](std::uint64_t offset, const std::string& what) -> FormatError {
        return FormatError(name + ": offset " + std::to_string(offset) + ": " + what);
    };
    const std::uint64_t size = b.size();
    if (size < 8 || std::memcmp(b.data(), kClusterTreeMagic, 8) != 0)
        throw fail(0, "not a cluster tree file (.mlh magic expected)");
    if (size < kClusterTreeHeaderBytes)
        throw fail(size, "truncated: the header needs " + std::to_string(kClusterTreeHeaderBytes) + " bytes, the file has " +
                             std::to_string(size));
    const std::uint32_t version = get<std::uint32_t>(b.data() + 8);
    if (version < 1 || version > kClusterTreeFileVersion)
        throw fail(8, "version " + std::to_string(version) + ": made by a " +
                          (version > kClusterTreeFileVersion ? "newer" : "older") + " version of meshless (this one reads versions 1 to " +
                          std::to_string(kClusterTreeFileVersion) + ")");
    // version 1 has no split order, cluster value kind or size term: the dissertation's (max error, fit)
    const std::size_t fixed_meta = version == 1 ? kClusterTreeMetaFixedBytesV1 : kClusterTreeMetaFixedBytes;
    if (!crc_matches(get<std::uint32_t>(b.data() + 60), crc32_ieee(0, b.data(), 60))) throw fail(60, "header checksum mismatch");
    if (get<std::uint32_t>(b.data() + 12) != kClusterTreeHeaderBytes) throw fail(12, "header size is not 64");
    for (std::size_t i = 40; i < 60; ++i)
        if (b[i] != 0) throw fail(i, "non-zero header padding");
    const std::uint64_t declared = get<std::uint64_t>(b.data() + 16);
    const std::uint64_t meta = get<std::uint64_t>(b.data() + 24);
    const std::uint64_t n = get<std::uint64_t>(b.data() + 32);
    if (declared != size)
        throw fail(16, declared > size ? "truncated: the header declares " + std::to_string(declared) + " bytes, the file has " +
                                             std::to_string(size)
                                       : std::to_string(size - declared) + " bytes after the declared end (" +
                                             std::to_string(declared) + " bytes)");
    const std::uint64_t max_meta = fixed_meta + kMaxNameBytes + (version >= 3 ? 4 + kMaxCertifiedErrors * kClusterTreeCertifiedBytes : 0) +
                                   (version >= 4 ? 8 : 0);
    if (meta < fixed_meta || meta > max_meta)
        throw fail(24, "meta size " + std::to_string(meta) + " outside " + std::to_string(fixed_meta) + ".." + std::to_string(max_meta));
    const std::uint64_t fixed = kClusterTreeHeaderBytes + meta + 8;
    if (n == 0 || n > (size - std::min(size, fixed)) / kClusterTreeNodeBytes || fixed + n * kClusterTreeNodeBytes != size)
        throw fail(32, std::to_string(n) + " nodes do not fill the file's " + std::to_string(size) + " bytes (" +
                           std::to_string(kClusterTreeNodeBytes) + " bytes each after " + std::to_string(fixed) + ")");
    const unsigned char* m = b.data() + kClusterTreeHeaderBytes;
    const std::uint64_t meta_crc_at = kClusterTreeHeaderBytes + meta;
    if (!crc_matches(get<std::uint32_t>(b.data() + meta_crc_at), crc32_ieee(0, m, meta))) throw fail(meta_crc_at, "meta checksum mismatch");
    const std::uint64_t nodes_at = meta_crc_at + 4, nodes_crc_at = nodes_at + n * kClusterTreeNodeBytes;
    if (!crc_matches(get<std::uint32_t>(b.data() + nodes_crc_at), crc32_ieee(0, b.data() + nodes_at, n * kClusterTreeNodeBytes)))
        throw fail(nodes_crc_at, "node checksum mismatch");

    ClusterTree t;
    CbtStats& s = t.stats;
    CbtParams& p = t.params;
    auto off = [&](std::size_t o) { return kClusterTreeHeaderBytes + o; };
    s.samples = get<std::uint64_t>(m + 0);
    s.dropped_nonfinite = get<std::uint64_t>(m + 8);
    s.splits = get<std::uint64_t>(m + 16);
    s.skipped = get<std::uint64_t>(m + 24);
    s.depth = get<std::uint32_t>(m + 32);
    p.neighbours = get<std::uint32_t>(m + 36);
    p.min_cluster = get<std::uint32_t>(m + 40);
    const std::uint32_t scaling = get<std::uint32_t>(m + 44);
    p.max_splits = get<std::uint64_t>(m + 48);
    p.max_error = get<double>(m + 56);
    p.hardy_c_rel = get<double>(m + 64);
    p.hardy_c_world = get<double>(m + 72);
    s.hardy_c_world = get<double>(m + 80);
    s.error_reached = get<double>(m + 88);
    double f[8];
    for (int i = 0; i < 8; ++i) f[i] = get<double>(m + 96 + 8 * i);
    t.bounds = {Vec3{f[0], f[1], f[2]}, Vec3{f[3], f[4], f[5]}};
    t.value_range = {f[6], f[7]};
    const std::size_t name_at = fixed_meta - 4;
    const std::uint32_t name_bytes = get<std::uint32_t>(m + name_at);
    if (version < 3 ? name_bytes != meta - fixed_meta : name_bytes > std::min<std::uint64_t>(kMaxNameBytes, meta - fixed_meta))
        throw fail(off(name_at), "name of " + std::to_string(name_bytes) + " bytes in a meta of " + std::to_string(meta));
    t.value_name.assign(reinterpret_cast<const char*>(m + fixed_meta), name_bytes);
    p.order = CbtSplitOrder::max_error;
    p.value = CbtValueKind::fit;
    p.size_term = 0;
    if (version >= 2) {
        const std::uint32_t order = get<std::uint32_t>(m + 160), kind = get<std::uint32_t>(m + 164);
        if (order > 1) throw fail(off(160), "unknown split order " + std::to_string(order));
        if (kind > 1) throw fail(off(164), "unknown cluster value kind " + std::to_string(kind));
        p.order = static_cast<CbtSplitOrder>(order);
        p.value = static_cast<CbtValueKind>(kind);
        p.size_term = get<double>(m + 168);
        if (!(p.size_term >= 0 && p.size_term <= 100)) throw fail(off(168), "size term outside [0, 100]");
    }
    if (scaling > 1) throw fail(off(44), "unknown PCA scaling " + std::to_string(scaling));
    p.scaling = static_cast<PcaScaling>(scaling);
    if (p.neighbours < 1) throw fail(off(36), "neighbours 0");
    if (p.min_cluster < 2) throw fail(off(40), "minimum cluster size below 2");
    if (!std::isfinite(p.max_error) || p.max_error < 0 || !std::isfinite(p.hardy_c_rel) || p.hardy_c_rel < 0 ||
        !std::isfinite(p.hardy_c_world) || p.hardy_c_world < 0 || !std::isfinite(s.hardy_c_world) || s.hardy_c_world < 0)
        throw fail(off(56), "a parameter is negative or not finite");
    for (double v : f)
        if (!std::isfinite(v)) throw fail(off(96), "non-finite bounds or value range");
    if (s.samples < 2 || s.samples >= 0xFFFFFFFFull) throw fail(off(0), std::to_string(s.samples) + " samples (2 .. 2^32 - 2 expected)");
    if (n != 2 * s.splits + 1)
        throw fail(off(16), std::to_string(s.splits) + " splits claimed, " + std::to_string(n) + " nodes (2 x splits + 1 expected)");
    if (version >= 3) t.certified = parse_certified(m, fixed_meta + name_bytes, meta, version >= 4 ? 8 : 0, s.splits + 1, fail);
    if (version >= 4) t.samples_hash = get<std::uint64_t>(m + meta - 8);  // (0: a tree first read from an older file)

    t.nodes.resize(n);
    std::memcpy(t.nodes.data(), b.data() + nodes_at, n * kClusterTreeNodeBytes);
    const std::string bad = validate_cluster_tree(t.nodes, s.samples);
    if (!bad.empty()) throw FormatError(name + ": " + bad);
    const CbtStats c = cluster_tree_stats(t.nodes);
    if (c.skipped != s.skipped)
        throw fail(off(24), std::to_string(s.skipped) + " skipped splits claimed, the nodes flag " + std::to_string(c.skipped));
    if (c.depth != s.depth) throw fail(off(32), "depth " + std::to_string(s.depth) + " claimed, the nodes reach " + std::to_string(c.depth));
    if (c.error_reached != s.error_reached) throw fail(off(88), "the error reached differs from the leaves' largest error");
    return t;
}

ClusterTree read_cluster_tree_file(const std::string& path) {
    const std::vector<std::byte> bytes = read_file_bytes(path);
    return parse_cluster_tree_bytes(std::span<const unsigned char>(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size()),
                                    path);
}

std::optional<CbtSplitOrder> cluster_tree_split_order(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return std::nullopt;
    unsigned char b[kClusterTreeHeaderBytes + kClusterTreeMetaFixedBytes];
    const std::size_t got = std::fread(b, 1, sizeof b, f);
    std::fclose(f);
    if (got < kClusterTreeHeaderBytes || std::memcmp(b, kClusterTreeMagic, 8) != 0) return std::nullopt;
    const std::uint32_t version = get<std::uint32_t>(b + 8);
    if (version == 1) return CbtSplitOrder::max_error;
    if (version < 2 || version > kClusterTreeFileVersion || got < sizeof b) return std::nullopt;
    const std::uint32_t order = get<std::uint32_t>(b + kClusterTreeHeaderBytes + 160);
    if (order > 1) return std::nullopt;
    return static_cast<CbtSplitOrder>(order);
}

std::uint32_t cluster_tree_file_version(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return 0;
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return 0;
    unsigned char b[12];
    const bool ok = std::fread(b, 1, sizeof b, f) == sizeof b && std::memcmp(b, kClusterTreeMagic, 8) == 0;
    std::fclose(f);
    return ok ? get<std::uint32_t>(b + 8) : 0;
}

bool is_cluster_tree_file(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return false;  // a FIFO would block the open
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) return false;
    char m[8];
    const bool ok = std::fread(m, 1, 8, f) == 8 && std::memcmp(m, kClusterTreeMagic, 8) == 0;
    std::fclose(f);
    return ok;
}

}  // namespace meshless
