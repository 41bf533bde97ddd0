// Stream metadata (formats/point_stream.hpp's StreamMeta, "key value" pairs) as the graphs write
// and read it: what a volume and its isovalue are, the frame a picture takes (dissertation section
// 3.6: the surface's bounds known before extraction), the patient's axes, and the same keys as PLY
// comments (so the in-process and piped paths write the same bytes). Used by the recipes and by
// every front end. Throws FormatError (naming the stream) for a recorded triple that is not three
// numbers; the rest does not throw.
#pragma once
#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "formats/anatomical_frame.hpp"
#include "formats/point_stream.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/grid.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/brick_store.hpp"
#include "ooc/sample_store.hpp"

namespace meshless {

/// "x,y,z" with 9 significant digits (stream metadata: bounds, spacing).
std::string triple(double a, double b, double c);
std::string triple(const Vec3& v);

/// `patient_axes` metadata: the LPS directions of world +x, +y, +z, nine numbers; nullopt when absent
/// or malformed (then the pictures take the generic camera).
std::optional<AnatomicalFrame> meta_patient_axes(const StreamMeta& m);
/// The patient's axes a brick store records (convert and synth copy them from the volume's header).
std::optional<AnatomicalFrame> store_frame(const BrickStoreInfo& info);
/// Sets `patient_axes` from f (nothing when f is empty).
void set_patient_axes(StreamMeta& m, const std::optional<AnatomicalFrame>& f);
/// Sets `length_unit` (formats/length_unit.hpp; nothing when `unit` is empty).
void set_length_unit(StreamMeta& m, const std::string& unit);
/// The recorded `length_unit` when it is one formats/length_unit.hpp knows, else "".
std::string meta_length_unit(const StreamMeta& m);

/// Metadata describing a volume and the isovalue (keys: source, iso, grid_dims, grid_origin,
/// grid_spacing, bounds_lo, bounds_hi, value_min, value_max, producer).
/// value_min/value_max are left out when `range` is nullopt.
StreamMeta volume_meta(const std::string& source, const GridSpec& g, SampleType type,
                       const std::optional<std::array<double, 2>>& range, double iso, const std::string& producer);
inline StreamMeta volume_meta(const std::string& source, const GridSpec& g, SampleType type,
                              const std::array<double, 2>& range, double iso, const std::string& producer) {
    return volume_meta(source, g, type, std::optional<std::array<double, 2>>(range), iso, producer);
}
inline StreamMeta volume_meta(const std::string& source, const Volume& v, double iso, const std::string& producer) {
    return volume_meta(source, v.grid, v.type, v.value_range(), iso, producer);
}

/// The bounds of the isosurface a brick store knows before extraction (dissertation section 3.6
/// framing): the union of the voxel boxes of the bricks active for iso (BrickIndex::active); nullopt
/// when nothing is active.
std::optional<std::array<Vec3, 2>> store_surface_bounds(const BrickStore& store, const BrickIndex& index, double iso);
/// The metadata of paradigm (A) over a sample store (dissertation section 3.5, Table 3.1): volume_meta
/// of the store's .mlb plus paradigm=A, framed on the surface bounds and patient axes the .mlb
/// records, so both paradigms give the same PLY comments and pictures.
StreamMeta sample_store_meta(const SampleStore& store, double iso, const std::string& producer);
/// Moves bounds_lo/hi (the volume's, from volume_meta) to volume_bounds_lo/hi and records the
/// surface's as bounds_lo/hi; nullopt (nothing active) keeps the volume's as the frame.
void set_surface_bounds(StreamMeta& m, const std::optional<std::array<Vec3, 2>>& surface);
/// Records the isovalues of a run of several (2 or more; fewer: nothing) in `meta` as
/// `isovalues=V1,V2,...` instead of `iso` (the points do not lie on one surface) and frames the union
/// of their surfaces: `bounds(iso)` gives one surface's (nullopt: nothing there).
void set_isovalues(StreamMeta& meta, const std::vector<double>& isos,
                   const std::function<std::optional<std::array<Vec3, 2>>(double)>& bounds);
/// The isovalues a run of several recorded (set_isovalues); nullopt without the key. FormatError
/// (naming the stream) for a list that is not finite numbers separated by commas.
std::optional<std::vector<double>> meta_isovalues(const StreamMeta& m);
/// The PLY comment lines derived from metadata (same for the in-process and piped paths).
std::vector<std::string> ply_comments(const StreamMeta& m);
/// Bounds recorded in PLY comments written by ply_comments ("bounds_lo x,y,z", "bounds_hi ..."), if any.
std::optional<std::array<Vec3, 2>> ply_bounds(const std::vector<std::string>& comments);
/// Bounds recorded in the metadata, if any.
std::optional<std::array<Vec3, 2>> meta_bounds(const StreamMeta& m);
/// The frame of a picture of these points: the recorded bounds, or nullopt when there are none or
/// when the metadata says `frame points` (the scattered-data surface: its recorded bounds only
/// hold every point, a box four times the surface's width; the picture then frames the points
/// themselves, spooled first). PLY comments: the same, read from ply_comments' lines.
std::optional<std::array<Vec3, 2>> picture_bounds(const StreamMeta& m);
std::optional<std::array<Vec3, 2>> ply_picture_bounds(const std::vector<std::string>& comments);
/// The PLY comments ply_comments() wrote, read back as the metadata they came from ("key value").
StreamMeta ply_comments_meta(const std::vector<std::string>& comments);

}  // namespace meshless
