// Shared pieces of the meshless subcommands: volume input options, camera options, stream metadata
// and PLY comments, input/output stream opening ("-" = stdin/stdout), and progress reporting on
// stderr (only when stderr is a terminal).
#pragma once
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "stream/camera_request.hpp"
#include "stream/render_settings.hpp"
#include "formats/file_names.hpp"
#include "formats/input_file.hpp"
#include "formats/stdin_spool.hpp"
#include "formats/anatomical_frame.hpp"
#include "formats/geometry_format.hpp"
#include "formats/output_names.hpp"
#include "formats/vtp_writer.hpp"
#include "formats/point_stream.hpp"
#include "kernels/block_minmax.hpp"
#include "kernels/cell_sampling.hpp"
#include "kernels/grid.hpp"
#include "kernels/project_sample.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "ooc/brick_cache.hpp"
#include "ooc/brick_index.hpp"
#include "ooc/slice_source.hpp"
#include "stream/iso_range_warning.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/point_outputs.hpp"
#include "stream/stream_metadata.hpp"
#include "stream/volume_input.hpp"
#include "formats/byte_size_text.hpp"

namespace meshless::cli {

/// --dims --type --endian --spacing for raw volumes, --series (DICOM), --resolution-level (OME-Zarr),
/// --array (add_array_option).
void add_volume_options(Args& a);
/// The help of --array NAME.
inline constexpr const char* kArrayOptionHelp =
    "VTK volumes (.vti, legacy .vtk, vtk.js): the point array to read, by name (default: the active "
    "scalars, else the first; meshless info lists them); HDF5 files: the dataset (/group/name; default: "
    "the file's only 3-D dataset); refused (exit 1) by the formats of one unnamed array: raw, NRRD, NIfTI, .mlb, ...";
/// --crop X0,Y0,Z0,X1,Y1,Z1: the box of samples a volume command works on (VolumeOpenOptions::crop,
/// read by volume_open_options; six finite numbers checked at parse).
void add_crop_option(Args& a);
/// --array NAME: the point array of a multi-array volume (RawOptions::array, read by raw_options).
void add_array_option(Args& a);
/// The raw-volume options given on the command line.
RawOptions raw_options(const Args& a);
/// Loads the volume named by the first positional argument (throws UsageError if none).
Volume load_volume(const Args& a);

/// --memory BYTES: the brick cache budget when VOLUME is a brick store (.mlb), and the most a volume
/// read whole into memory may take (check_volume_fits).
void add_memory_option(Args& a);
/// check_volume_fits (stream/volume_input.hpp) with the budget of --memory when the command
/// declares it and the user gave it.
void check_volume_fits(const Args& a, const std::string& path, const VolumeInfo& vi, bool map);
/// Refuses, before any work, an option whose value implies more memory than this process may use
/// (available_memory(): physical memory, cgroup limit, ulimit -v; not --memory, which budgets the
/// brick cache): UsageError (exit 1) "OPTION VALUE: WHAT would take N, more than the BUDGET this
/// process may use (...); HINT". `need` is what the option makes the command allocate at least
/// (estimates say so in `what`).
void check_option_fits(const Args& a, const std::string& option, const std::string& what, std::uint64_t need,
                       const std::string& hint = "");
/// Bytes of the image buffers of a WxH picture at `bytes_per_pixel` (checked: no overflow for 16384^2).
std::uint64_t image_bytes(int width, int height, std::uint64_t bytes_per_pixel);

/// The options of a VOLUME argument (stream/volume_input.hpp): the raw-volume options, --memory
/// when declared and given, --threads; warnings go to stderr as "meshless COMMAND: warning: ...".
/// stream = true for commands that make one pass in cell-row order (isosurface, generate).
VolumeOpenOptions volume_open_options(const Args& a, bool stream);
/// open_volume_input of the first positional argument (UsageError when there is none).
VolumeInput open_volume_input(const Args& a, bool stream = false);

/// --radius-scale
void add_sampling_options(Args& a);
SamplingParams sampling_params(const Args& a);
/// --threads
void add_thread_option(Args& a);
int threads(const Args& a);

/// --size WxH --azimuth --elevation --up --view --zoom --ortho: where the camera looks from.
void add_orbit_options(Args& a, const char* default_size);
/// The camera of add_orbit_options (stream/camera_request.hpp: UsageError or InvalidArgument for bad
/// values, --view with --azimuth/--elevation; a --size whose buffers would not fit in memory).
Camera camera_from(const Args& a, const char* default_size);
/// add_orbit_options' values as stream/camera_request.hpp takes them.
CameraRequest camera_request(const Args& a, const char* default_size);
/// The default camera of data whose patient's axes are known (kernels/anatomical_view.hpp): as
/// apply_anatomical_default, for a frame from elsewhere (the `patient_axes` a PLY or stream records).
void apply_anatomical_frame(const Args& a, const AnatomicalFrame& f, Camera& c);
/// The default camera of a volume (kernels/anatomical_view.hpp): when --up was not given and the
/// volume's header gives the patient's axes (formats/anatomical_frame.hpp: NIfTI sform/qform, NRRD
/// space, MetaImage; a brick store records them), the head goes up and, without --view, the face
/// towards the viewer, turned by --azimuth / --elevation (30 and 20 unless given); with --view the
/// camera looks along the named direction with superior up. Otherwise (formats that say nothing) the
/// camera is left as it is. Returns the frame used, if any.
std::optional<AnatomicalFrame> apply_anatomical_default(const Args& a, const VolumeInput& in, Camera& c);
/// One note on stderr, when it is a terminal and --view was not given, that `volume` gives no
/// patient's axes and how to turn the camera (pictures of such a volume may show it on its side).
void no_patient_axes_hint(const Args& a, const std::string& volume);
/// add_orbit_options (800x800) and --kernel quad|ewa --shading: the splat pictures' options.
void add_camera_options(Args& a);
/// Camera, kernel and shading from the camera options.
RenderSettings render_settings(const Args& a);
/// --axes / --no-axes (add_color_options, render's): on, off, or (neither, the default) when the
/// world's length unit is known; off when the command has no such option. UsageError for both.
AxesChoice axes_choice(const Args& a);

/// --color value|block|normal|none (default auto), --colormap, --range LO,HI, --colorbar: the
/// splat colours of `meshless splat` and `meshless isosurface --png`.
void add_color_options(Args& a);
ColorChoice color_choice(const Args& a);
/// apply_color (stream/render_settings.hpp) with its warning on stderr.
void apply_color(RenderSettings& rs, ColorBy by, const ColorChoice& c, const std::array<double, 2>& range);

/// The isovalue for a stage reading a stream: --iso if given (with a warning when it differs from
/// the stream's, whose active cells were chosen for that value), else the stream's; UsageError
/// when neither exists.
double stream_iso(const Args& a, const StreamMeta& m);

/// --projection: "none" | "approx" | "exact" (kernels/project_sample.hpp); UsageError otherwise.
Projection parse_projection(const std::string& s);

/// --iso V or V1,V2,... (at most 256 values): the isovalues of a volume's isosurface or mesh, in order.
std::vector<double> isovalue_list(const Args& a);
/// --iso of an input that takes one isovalue a run (`what`: "multiblock grids", "scattered points",
/// "mpirun"); UsageError for a list (several isovalues are for volumes and stores in one process).
double single_iso(const Args& a, const std::string& what);

/// --fail-empty: an empty result (no point, triangle or sample) exits kExitEmpty (cli/errors.hpp).
void add_fail_empty_option(Args& a);
/// After a command made `count` `what`s ("points", "triangles", "samples") at `iso` from `source`:
/// when none, one warning line on stderr naming the source (unless `warned`: an earlier line said
/// the outputs will be empty), and kExitEmpty with --fail-empty; otherwise 0.
int empty_result_exit(const Args& a, std::uint64_t count, const char* what, double iso, const std::string& source,
                      bool warned);
/// What an isosurface's point output is, in the messages of geometry_output.
inline constexpr const char* kPointsWhat = "an oriented point set";
/// --format ply|vtp: the geometry format of -o when its name does not say it (stdout, odd names).
void add_geometry_format_option(Args& a);
/// formats/output_names.hpp geometry_output_format of `path` with --format.
GeometryFormat geometry_output_format(const Args& a, const std::string& path, const char* what);
/// --ply-color value|block|normal (point outputs): colours in the PLY for readers that keep only
/// x y z, normals and red green blue (vtkPLYReader; MeshLab shows them too).
void add_ply_color_option(Args& a);
/// --vtp-compression zlib|none (add_geometry_format_option adds it) as VTP writer settings with
/// `threads` compressing threads. UsageError for other values.
VtpOptions vtp_options(const Args& a, int threads);
/// -o (when given) with its format from geometry_output_format.
std::optional<GeometryOutput> geometry_output(const Args& a, const char* what);
/// True when stderr is a terminal (progress and timing chatter go there only then, or with --stats).
bool stderr_is_tty();

}  // namespace meshless::cli
