// What a volume's header says about the patient's axes (the default camera of `isosurface --png`
// and `render` puts the head up and the face towards the viewer, kernels/camera.hpp
// anatomical_view). Conventions: directions are unit vectors in LPS (+x toward the patient's
// left, +y posterior, +z superior: DICOM's patient coordinates); one per world axis of the volume
// as read (x, y, z; an axis the reader reversed for a negative spacing has its direction negated).
// Sources, per format (what the header says, where it says it):
//   NIfTI-1: sform (sform_code > 0) else qform (qform_code > 0: quaternion and qfac), in RAS;
//            both codes 0 ("method 1", ANALYZE) say nothing.
//   NRRD:    an anatomical `space` (RAS, LAS, LPS, their long names and -time variants) with
//            `space directions` (or the identity without them); `space: 3D-right-handed` or
//            `3D-left-handed` (no anatomical names) is read in DICOM's axial-slice convention:
//            x toward the patient's left, y posterior, z superior in a right-handed space and
//            inferior in a left-handed one (VTK's headsq CT says 3D-left-handed: its slice 1 is the
//            top of the head).
//   MetaImage: TransformMatrix (ITK direction cosines in LPS, row i = axis i), else
//            AnatomicalOrientation (ITK's three letters naming where each axis comes from: RAI is the
//            identity), else the identity (ITK reads every MetaImage in LPS).
//   Other formats (raw, VTK, VTI, vtk.js, SLC, Voreen): none; the generic default camera applies.
// Throws nothing: an unreadable or degenerate frame is no frame. Thread-safety: pure functions.
// Dissertation: none (presentation).
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "kernels/vec3.hpp"

namespace meshless {

struct AnatomicalFrame {
    std::array<Vec3, 3> axis{};  ///< LPS unit direction of world +x, +y, +z
    std::string source;          ///< the header field(s) it came from, for `info`
};

/// NRRD: `space` (lower case) and the `space directions` of the kept axes (empty: none given).
std::optional<AnatomicalFrame> nrrd_frame(const std::string& space, const std::vector<Vec3>& directions);
/// MetaImage: TransformMatrix (9 numbers, or empty) and AnatomicalOrientation (or empty).
std::optional<AnatomicalFrame> metaimage_frame(const std::vector<double>& transform, const std::string& orientation);
/// NIfTI-1: the RAS matrix columns of the index axes (from sform or qform).
std::optional<AnatomicalFrame> ras_frame(const std::array<Vec3, 3>& ras_columns, const std::string& source);
/// Negates the axes whose samples the reader reversed (negative spacing).
void flip_frame(std::optional<AnatomicalFrame>& f, const std::array<bool, 3>& flip);
/// The signs of a direction matrix whose index axis i runs along world axis i, forward or back
/// (columns[i]: index axis i in world coordinates, any length; the other two components within
/// 1e-3 of its length, the slight obliquity scanners leave: positions are then off by at most 1e-3
/// of the volume's extent): the reader takes them as signed spacings, reverses the samples of the
/// backward axes (kernels/flip_axes.hpp) and so writes world coordinates (an FSL "LAS" NIfTI, an
/// NRRD `space directions (-2,0,0) ...`). nullopt when the matrix rotates or permutes the axes more:
/// positions then stay in the volume's index frame (origin + index x spacing), and only the
/// picture's view follows the matrix (mirrored when the matrix's determinant is negative).
std::optional<std::array<double, 3>> axis_aligned_signs(const std::array<Vec3, 3>& columns);
/// The frame's axes as plain numbers (a brick store's header keeps them, ooc/brick_store.hpp), and back.
std::array<std::array<double, 3>, 3> frame_axes(const AnatomicalFrame& f);
AnatomicalFrame frame_of_axes(const std::array<std::array<double, 3>, 3>& axes, std::string source);
/// "x L, y P, z S" (each axis's dominant direction), for `info`.
std::string describe_frame(const AnatomicalFrame& f);

}  // namespace meshless
