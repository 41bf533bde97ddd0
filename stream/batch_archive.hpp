// The inputs of the batch job (stream/batch_job.hpp, `meshless batch`), the volumes of an archive
// directory or of a manifest file.
//
// Directory: every entry for which looks_like_volume() is true (files, and vtk-js directories),
// hidden names skipped, sorted by relative path (byte order); with recursive, subdirectories that
// are not volumes themselves are walked too (the output folder is never walked). Payload files
// named by a header in the same folder (x.nhdr -> x.raw, x.mhd -> x.raw) are not listed again.
// Manifest: one volume per line, relative paths resolved against the manifest's folder, '#' starts
// a comment, blank lines ignored; after the path, raw-volume options as on the command line:
//   vol.raw --dims 64,64,64 --type uint8 [--endian big] [--spacing 1,1,2]
// which the caller's RawOptionsParser reads (the CLI parses them as its own options). Paths with
// spaces may be double-quoted. A malformed line becomes an item with `error` set (the run reports
// it and goes on), not an exception.
// Confinement: every item's RawOptions::references is confined (formats/reference_policy.hpp) to its
// archive folder: ARCHIVE_DIR (directory mode); the manifest's folder, or for a volume listed outside
// it that volume's own folder (manifest mode). The readers then refuse (ReferenceRefused) an input,
// or a file its header names, that resolves outside it (`..`, absolute paths, symbolic links).
// Output name: the path relative to the archive (directory mode) or the file name (manifest)
// without its volume extension (".raw", ".nii.gz", ...; vtk-js "dir/index.json" -> "dir").
// Throws IoError when the directory or manifest cannot be read. Reentrant.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "formats/volume_reader.hpp"

namespace meshless {

struct BatchItem {
    std::string name;      ///< output stem relative to OUT_DIR ("fuel_64x64x64_uint8", "sub/a")
    std::string path;      ///< input path as it will be opened
    RawOptions raw;        ///< per-item raw options (manifest) and the archive folder the item is confined to
    std::string raw_text;  ///< canonical text of `raw` for the sidecars ("" when none given)
    std::string error;     ///< non-empty: the item is already known to be bad (malformed manifest line)
};

/// Reads the raw-volume options that follow a path on a manifest line (the words after it, quotes
/// removed); throws InvalidArgument, whose message becomes the item's error, for a malformed one.
/// References are set by the caller afterwards.
using RawOptionsParser = std::function<RawOptions(const std::vector<std::string>& words)>;

std::vector<BatchItem> list_archive_dir(const std::string& dir, bool recursive, const std::string& out_dir);
/// A line with options when parse_raw is empty gets an error (nothing reads them).
std::vector<BatchItem> read_manifest(const std::string& manifest, const RawOptionsParser& parse_raw);

/// "fuel_64x64x64_uint8.raw" -> "fuel_64x64x64_uint8"; "a.nii.gz" -> "a"; "d/index.json" -> "d".
std::string volume_stem(const std::string& path);

}  // namespace meshless
