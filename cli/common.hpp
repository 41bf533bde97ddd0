// Shared pieces of the meshless subcommands: volume input options, camera options, stream metadata
// and PLY comments, input/output stream opening ("-" = stdin/stdout), and progress reporting on
// stderr (only when stderr is a terminal).
#pragma once
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/args.hpp"
#include "formats/point_stream.hpp"
#include "kernels/cell_sampling.hpp"
#include "kernels/grid.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/splat_rasterizer.hpp"

namespace meshless::cli {

/// --dims --type --endian --spacing for raw volumes.
void add_volume_options(Args& a);
/// The raw-volume options given on the command line.
RawOptions raw_options(const Args& a);
/// Loads the volume named by the first positional argument (throws UsageError if none).
Volume load_volume(const Args& a);
/// --radius-scale
void add_sampling_options(Args& a);
SamplingParams sampling_params(const Args& a);
/// --threads
void add_thread_option(Args& a);
int threads(const Args& a);

/// --size WxH --azimuth --elevation --zoom --kernel quad|ewa --ortho
void add_camera_options(Args& a);
Camera camera_from(const Args& a);
SplatKernel kernel_from(const Args& a);

/// Metadata describing a volume and the isovalue (keys: source, iso, grid_dims, grid_origin,
/// grid_spacing, bounds_lo, bounds_hi, value_min, value_max, producer).
StreamMeta volume_meta(const std::string& source, const Volume& v, double iso, const std::string& producer);
/// The PLY comment lines derived from metadata (same for the in-process and piped paths).
std::vector<std::string> ply_comments(const StreamMeta& m);
/// Bounds recorded in the metadata, if any.
std::optional<std::array<Vec3, 2>> meta_bounds(const StreamMeta& m);

/// Warns on stderr when iso lies outside [lo, hi] (the outputs will be empty but valid).
void warn_if_iso_outside(double iso, const std::array<double, 2>& range, const std::string& source);

/// A FILE* for reading: stdin for "-", else fopen (IoError naming the path; directories refused).
struct InputFile {
    std::FILE* f = nullptr;
    std::string name;
    explicit InputFile(const std::string& path);
    ~InputFile();
    InputFile(const InputFile&) = delete;
    InputFile& operator=(const InputFile&) = delete;
};

/// True when stderr is a terminal (progress and timing chatter go there only then, or with --stats).
bool stderr_is_tty();

}  // namespace meshless::cli
