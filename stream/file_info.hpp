// The report of `meshless info` (and of any front end) on a file meshless reads or writes: what
// kind of file it is, told by its first bytes and its name, then a description read through as
// the reading commands would read it (so a bomb, a truncation or a corrupt body is reported as
// they report it). The kinds: point/sample/seed streams, PLY point sets and meshes, brick stores
// (.mlb), sample stores (.mls), fitted fields (.mlf), cluster trees (.mlh), PNG pictures, VTK
// multiblock/AMR collections (.vtm, .vthb), point sets (formats/point_set_reader.hpp, point stores
// .mlc among them) and volumes (formats/volume_reader.hpp). docs/architecture.md "Libraries" says
// why it sits in stream/ (it opens ooc/ stores).
// Writes text lines to `out` as it goes: a file that fails half-way leaves the lines written before.
// Throws what the readers throw (FormatError for bad data, IoError for an unreadable file or a
// volume too large to read whole for value_range, InvalidArgument for an option outside its domain).
// Thread-safety: reentrant (distinct `out`).
#pragma once
#include <cstdio>
#include <string>

#include "formats/point_set_options.hpp"
#include "formats/volume_reader.hpp"

namespace meshless {

/// What file_kind finds, in the order it tries them.
enum class FileKind {
    stream,        ///< "-" (standard input) or a meshless point/sample/seed stream
    ply,           ///< PLY point set or mesh
    brick_store,   ///< .mlb (ooc/brick_store.hpp)
    sample_store,  ///< .mls (ooc/sample_store.hpp)
    field_file,    ///< .mlf (formats/field_file.hpp)
    cluster_tree,  ///< .mlh (formats/cluster_tree_file.hpp)
    png,           ///< PNG picture
    multiblock,    ///< .vtm / .vthb collection (reads FileInfoOptions::point_set)
    point_set,     ///< any point set formats/point_set_reader.hpp takes (reads FileInfoOptions::point_set)
    volume,        ///< anything else: a volume (reads FileInfoOptions::raw and value_range)
};

struct FileInfoOptions {
    RawOptions raw;              ///< volumes: how to read a raw file (--dims --type --endian --spacing)
    PointSetOptions point_set;   ///< point sets and collections
    bool value_range = false;    ///< volumes: also read the samples whole and print their value range
};

/// The kind of `path` from its first 32 bytes (a directory: none; "-": a stream) and its name.
/// `raw_dims`: the reader was given a raw volume's dims, which make a .raw file a volume whatever
/// the point-set sniffing says. IoError when the file cannot be opened.
FileKind file_kind(const std::string& path, bool raw_dims);

/// Writes the description of `path`, read as `kind`, to `out`; only the options `kind` reads are used.
void describe_file(const std::string& path, FileKind kind, const FileInfoOptions& options, std::FILE* out);
/// describe_file(path, file_kind(path, options.raw.dims given), options, out).
void describe_file(const std::string& path, const FileInfoOptions& options, std::FILE* out);

}  // namespace meshless
