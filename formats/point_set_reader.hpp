// Scattered and multiblock point sets with one scalar each (dissertation chapters 4-5 inputs):
// one entry point that dispatches on extension and content to the per-format readers
// (points_text, points_ply, points_vtp, points_vts, points_vtu, points_raw (+ .npy), plot3d), plus regular
// volumes read as one point per voxel.
//
// Dispatch: .csv .tsv .txt .dat(text) .pts .asc -> text; .ply -> PLY; .vtp -> VTK PolyData;
// .vts -> VTK StructuredGrid; .vtu -> the nodes of a VTK UnstructuredGrid (cells not used);
// .npy -> NumPy (a 2-D array; a 3-D one is a volume, formats/npy_volume.hpp); .p3d (JSON meta) .xyz .x .bin(PLOT3D) .q? -> PLOT3D;
// .mlh: a level of detail of a cluster tree (point_set_from_cluster_tree); .mlc (or the point store
// magic): a point store, every brick (formats/point_store.hpp);
// .raw: a regular volume when the volume readers can describe it, else float32 records; other
// files the volume readers claim -> one point per voxel (block dims = volume dims).
// Units: positions and values as the file stores them, kept in double precision.
// Bad input: FormatError/IoError, one line starting with the path (empty files, fewer than 4
// valid points, missing columns, malformed headers, implausible byte order, disagreeing PLOT3D
// dims, trailing bytes unless allow_trailing). NaN/Inf samples are dropped and counted unless
// options.strict. Thread-safety: reentrant, no shared state.
#pragma once
#include "formats/volume_reader.hpp"
#include <array>
#include <string>
#include <vector>

#include "formats/point_set_options.hpp"
#include "kernels/cluster_lod.hpp"
#include "kernels/cluster_tree.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

/// The minimum number of valid points a reader returns (FormatError below it).
inline constexpr std::size_t kMinPointSetPoints = 4;

/// Reads one file as a point set (see the dispatch above).
PointSet read_point_set(const std::string& path, const PointSetOptions& options = {});
/// Several files as one set: each file's blocks are appended (e.g. multicomb_0..2.vts = 3 blocks).
/// Value names must agree (FormatError otherwise); dropped counts add up. InvalidArgument when
/// `paths` is empty.
PointSet read_point_set(const std::vector<std::string>& paths, const PointSetOptions& options = {});

/// What `meshless info` prints: the format, notes (files paired, bytes ignored) and the whole set's
/// statistics. Reads the data (the statistics need it).
struct PointSetInfo {
    std::string format;                 ///< "text", "ply", "vtp", "vts", "vtu", "raw-float32", "npy", "plot3d", "volume", "point-store"
    std::vector<std::string> notes;     ///< e.g. "q file: combq.bin", "484 trailing bytes ignored"
    PointSet set;
};
PointSetInfo probe_point_set(const std::string& path, const PointSetOptions& options = {});

/// The format the dispatch above picks for `path` (a name of PointSetInfo::format), without reading
/// the data; FormatError/IoError as the readers for files of no known format.
std::string point_set_format(const std::string& path);

/// True for files the point-set readers handle and the volume readers do not (by extension; a .raw
/// only when the volume readers cannot describe it; a .bin only when it has a PLOT3D header).
bool looks_like_point_set(const std::string& path);

/// Every voxel of a regular volume as a point (value = sample, block dims = volume dims); raw gives
/// the dims, type, byte order and spacing of a raw file that does not describe itself.
PointSet point_set_from_volume(const std::string& path, const PointSetOptions& options = {}, const RawOptions& raw = {});

/// A level of detail of a cluster tree (.mlh, formats/cluster_tree_file.hpp) as a point set: the
/// cluster centres and values of the LOD that options.lod_level / lod_error choose (the finest
/// without either). notes (if given) gets a line when the request was beyond the tree.
PointSet point_set_from_cluster_tree(const std::string& path, const PointSetOptions& options = {},
                                     std::vector<std::string>* notes = nullptr);

/// The traversal that options choose for tree t (InvalidArgument for both or a bad error).
struct ClusterTreeLodRequest {
    LodMode mode = LodMode::level;
    double threshold = 0;
    bool clamped = false;     ///< beyond the tree: the finest LOD
    std::string description;  ///< "level 15", "error 4.5", "finest"
    std::string note;         ///< the warning when clamped
};
ClusterTreeLodRequest cluster_tree_lod_request(const ClusterTree& t, const PointSetOptions& options);

}  // namespace meshless
