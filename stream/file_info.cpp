#include "stream/file_info.hpp"

#include <cstring>
#include <filesystem>
#include <vector>

#include "formats/cluster_tree_file.hpp"
#include "formats/field_file.hpp"
#include "formats/file_names.hpp"
#include "formats/input_file.hpp"
#include "formats/point_set_reader.hpp"
#include "formats/point_stream.hpp"
#include "formats/terminal_safe.hpp"
#include "kernels/errors.hpp"
#include "formats/hdf5_volume.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/sample_store.hpp"
#include "stream/built_file_info.hpp"
#include "stream/point_set_info.hpp"
#include "stream/volume_info.hpp"

namespace meshless {

namespace {

void describe_stream(const std::string& path, std::FILE* out) {
    InputFile in(path);
    StreamReader r(in.f, in.name);
    r.stop_at_segments();
    r.read_meta();
    std::vector<char> buf;
    std::uint64_t frames = 0;
    std::string segments;  // "; V: N records" for each segment of a stream of several isovalues
    for (std::optional<StreamMeta> seg;;) {
        const std::uint64_t before = r.total();
        for (;;) {
            buf.clear();
            if (!r.next_data(buf)) break;
            ++frames;
        }
        if (seg) segments += (segments.empty() ? "" : ", ") + seg->get("iso").value_or("?") + ": " + std::to_string(r.total() - before);
        if (!(seg = r.next_segment())) break;
    }
    std::fprintf(out, "%s: meshless %s stream%s, version %u, %zu-byte records\n", terminal_safe(path).c_str(),
                 r.kind() == RecordKind::point ? "point" : (r.kind() == RecordKind::seed ? "seed" : "sample"),
                 r.has_blocks() ? " with block ids" : "", kStreamVersion, r.record_bytes());
    std::fprintf(out, "  records: %llu in %llu DATA frames, END frame present\n", static_cast<unsigned long long>(r.total()),
                 static_cast<unsigned long long>(frames));
    if (r.total() > 0) {
        std::fprintf(out, "  payload: %llu bytes, %.1f per record", static_cast<unsigned long long>(r.data_bytes()),
                     static_cast<double>(r.data_bytes()) / static_cast<double>(r.total()));
        if (r.kind() == RecordKind::sample)  // only sample frames can be cell-indexed
            std::fprintf(out, " (%llu cell-indexed frames)", static_cast<unsigned long long>(r.cell_frames()));
        std::fprintf(out, "\n");
    }
    if (r.segments() > 0)
        std::fprintf(out, "  segments: %llu (records per isovalue: %s)\n", static_cast<unsigned long long>(r.segments()),
                     terminal_safe(segments).c_str());
    for (const auto& [k, v] : r.meta().kv) std::fprintf(out, "  %s: %s\n", terminal_safe(k).c_str(), terminal_safe(v).c_str());
}

/// The first bytes of `path` (none for "-" or a directory: a vtk-js image is a directory).
std::size_t read_head(const std::string& path, unsigned char (&h)[32]) {
    std::error_code ec;
    if (path == "-" || std::filesystem::is_directory(path, ec)) return 0;
    InputFile in(path);
    return std::fread(h, 1, sizeof h, in.f);
}

void describe_png(const std::string& path, std::FILE* out) {
    unsigned char h[32] = {};
    const std::size_t n = read_head(path, h);
    if (n < 24) throw FormatError(path + ": truncated PNG header");
    auto be32 = [&](int o) { return (unsigned(h[o]) << 24) | (unsigned(h[o + 1]) << 16) | (unsigned(h[o + 2]) << 8) | h[o + 3]; };
    std::fprintf(out, "%s: PNG image, %u x %u\n", terminal_safe(path).c_str(), be32(16), be32(20));
}

// Collections, and a RectilinearGrid (.vtr): read as blocks, as isosurface and mc read them.
bool is_collection(const std::string& path) {
    const std::string e = lower_extension(path);
    return e == ".vtm" || e == ".vthb" || e == ".vtr";
}

}  // namespace

FileKind file_kind(const std::string& path, bool raw_dims) {
    if (is_hdf5_input(path)) return FileKind::volume;  // FILE.h5 or FILE.h5:/DATASET
    unsigned char h[32] = {};
    const std::size_t n = read_head(path, h);
    if (path == "-" || (n >= 8 && std::memcmp(h, "\x89MLS", 4) == 0)) return FileKind::stream;
    if (n >= 4 && std::memcmp(h, "ply", 3) == 0 && (h[3] == '\n' || h[3] == '\r')) return FileKind::ply;
    if (n >= 8 && std::memcmp(h, kBrickStoreMagic, 8) == 0) return FileKind::brick_store;
    if (n >= 8 && is_sample_store(path)) return FileKind::sample_store;
    if (n >= 8 && std::memcmp(h, kFieldFileMagic, 8) == 0) return FileKind::field_file;
    if (n >= 8 && std::memcmp(h, kClusterTreeMagic, 8) == 0) return FileKind::cluster_tree;
    if (n >= 8 && std::memcmp(h, "\x89PNG", 4) == 0) return FileKind::png;
    if (is_collection(path)) return FileKind::multiblock;
    // a .raw given dims is a volume, as the volume commands read it
    if (!(raw_dims && lower_extension(path) == ".raw") && looks_like_point_set(path)) return FileKind::point_set;
    return FileKind::volume;
}

void describe_file(const std::string& path, FileKind kind, const FileInfoOptions& options, std::FILE* out) {
    switch (kind) {
        case FileKind::stream: describe_stream(path, out); break;
        case FileKind::ply: describe_ply(path, out); break;
        case FileKind::brick_store: describe_brick_store(path, out); break;
        case FileKind::sample_store: describe_sample_store(path, out); break;
        case FileKind::field_file: describe_field_file(path, out); break;
        case FileKind::cluster_tree: describe_cluster_tree(path, out); break;
        case FileKind::png: describe_png(path, out); break;
        case FileKind::multiblock: describe_multiblock(path, options.point_set, out); break;
        case FileKind::point_set: describe_point_set(path, options.point_set, out); break;
        case FileKind::volume: describe_volume(path, options.raw, options.value_range, out); break;
    }
}

void describe_file(const std::string& path, const FileInfoOptions& options, std::FILE* out) {
    describe_file(path, file_kind(path, options.raw.dims.has_value()), options, out);
}

}  // namespace meshless
