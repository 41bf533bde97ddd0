// The direct volume rendering recipe (dissertation section 6.6, Figure 6.6: LOD fields volume
// rendered and differenced against the original; section 7.4: volume rendering of scattered data):
// what a picture is ray cast from — a volume or brick store through its trilinear interpolant (a
// store through the brick cache), or scattered points and multiblock nodes through a meshless field
// — with its value range, natural spacing and empty-space boxes; the frame; and the picture. Nothing
// is resampled onto a grid first. The ray caster is kernels/ray_caster.hpp.
// Units: world units (the data's); pictures are 8-bit RGB, `width` x `height` of the camera.
// Throws FormatError for points that cannot be rendered (none, or all coincident), and what the
// readers and the brick cache throw. Thread-safety: one render at a time per RenderInput; the ray
// caster runs `threads` threads of its own and its picture does not depend on them.
#pragma once
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "kernels/camera.hpp"
#include "kernels/field.hpp"
#include "kernels/point_set.hpp"
#include "kernels/ray_caster.hpp"
#include "kernels/transfer_function.hpp"
#include "kernels/value_bounds_grid.hpp"
#include "stream/volume_input.hpp"

namespace meshless {

/// What a picture is ray cast from: a field over a box, its value range, its natural spacing, and
/// the empty-space boxes; plus whatever the field keeps alive (a points field is the caller's).
struct RenderInput {
    std::optional<VolumeInput> volume;
    std::unique_ptr<Field> owned;  ///< trilinear / brick-store field
    const Field* field = nullptr;
    std::array<Vec3, 2> box;
    std::array<double, 2> range{0, 1};
    double spacing = 1;  ///< default step = spacing / 2
    std::optional<ValueBoundsGrid> skip;
    std::string what;  ///< for a statistics line: "volume, trilinear 64x64x64", "1000 points, mpu field"
};

/// A volume (in memory) or brick store rendered through its trilinear interpolant: its empty-space
/// boxes are 8-cell blocks (a store: its bricks' exact intervals), the spacing its smallest voxel side.
RenderInput volume_render_input(VolumeInput volume);

/// Scattered data: empty-space boxes of this many mean point spacings, bounded by the points within
/// kPointPad spacings (the reach of the fields' local fits: an mpu leaf's sphere or an RBF-grid cell's
/// data sphere holds its few dozen nearest points, 2-3 spacings), widened by kPointMargin of the
/// data's value range (multiquadric interpolants overshoot their data a little).
inline constexpr double kPointMacroCell = 8, kPointPad = 3, kPointMargin = 0.05;

/// Points rendered through `field` (built over them, kept alive by the caller): empty-space boxes of
/// 8 mean point spacings bounded by the points within 3 spacings (the reach of the fields' local
/// fits), widened by 5 % of the value range (multiquadrics overshoot their data a little).
/// FormatError naming `name` when there are no points or they all coincide.
RenderInput points_render_input(const PointSet& points, const Field& field, const std::string& name);

/// The box the camera frames: the data's, or `bounds`; in.box becomes the part rendered (a grid's
/// samples within the box; a field's whole box, it extrapolates).
std::array<Vec3, 2> render_frame(RenderInput& in, const std::optional<std::array<Vec3, 2>>& bounds);

/// How a picture is made beyond the camera and the transfer function.
struct RenderOptions {
    std::optional<double> step;      ///< world units between samples (default: spacing / 2)
    std::optional<double> ref_step;  ///< the opacities' slab thickness (default: spacing / 2)
    bool shade = false;              ///< headlight Phong from the field's gradient
    bool no_skip = false;            ///< evaluate every box with data (no empty-space skipping)
    std::array<double, 3> background{0, 0, 0};  ///< RGB in [0, 1]
    std::optional<std::array<Vec3, 2>> bounds;   ///< the frame (render_frame)
    int threads = 1;
};

/// A rendered picture and what it took.
struct RenderResult {
    Image picture;
    RayCastStats stats;
    RayCastParams params;  ///< the step and reference step used
    double seconds = 0;    ///< the ray casting's wall time
};

/// The ray caster's parameters of a render: the options' step and reference step (default: half
/// the input's spacing), shading, background; a volume's shading by central differences over a voxel.
RayCastParams render_params(const RenderInput& in, const RenderOptions& o);
/// The camera's view of the frame (render_frame: in.box becomes the part rendered); with no_skip,
/// every empty-space box with data becomes one to evaluate.
ViewTransform render_view(RenderInput& in, const Camera& cam, const RenderOptions& o);

/// The transfer function of a render (`meshless render --tf NAME`): a preset (kernels/transfer_function.hpp)
/// spanning `range` (a constant range [v, v] becomes [v, v + 1], a non-finite one [0, 1]), or a file of
/// 'value r g b a' rows (formats/transfer_function_file.hpp), which brings its own values. Throws
/// InvalidArgument when `range_given` (the user chose the range) with a file, or when `name` is neither a
/// preset nor an existing file; what the file reader throws (FormatError, IoError).
TransferFunction render_transfer_function(const std::string& name, std::array<double, 2> range, bool range_given);

/// Ray casts `in` as `cam` sees it (dissertation section 7.4); `progress` (may be empty) receives
/// the finished fraction of the rays, serialised.
RenderResult render_field(RenderInput& in, const Camera& cam, const TransferFunction& tf, const RenderOptions& o,
                          const std::function<void(double)>& progress = {});

}  // namespace meshless
