// Paradigm (C) iso-splatting as one job of a front end (dissertation chapter 3, sections 3.3-3.6):
// a volume (in memory, slab-streamed or a brick store: stream/volume_input.hpp), a paradigm (A)
// sample store (section 3.5, Table 3.1) or a brick store split over the ranks of mpirun
// (stream/isosplat_mpi.hpp), run into the outputs (stream/point_outputs.hpp: a PLY/VTP and/or a PNG)
// with the picture framed and coloured from the metadata (the surface bounds, the patient's axes, the
// value range), the warning of an isovalue outside the data, the progress of the cell rows and the
// --stats line. What `meshless isosurface VOLUME` runs once its options are checked (and any other
// front end). Units: isovalue in the volume's value units. Throws what the recipes and the outputs
// throw.
#pragma once
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "formats/anatomical_frame.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "stream/isosplat_mpi.hpp"
#include "stream/point_outputs.hpp"
#include "stream/progress_stage.hpp"
#include "stream/volume_input.hpp"

namespace meshless {

/// Another array of the job's volume, by name (`--color-by NAME`).
struct ColorByArray {
    std::string name;
    Volume volume;
};

struct IsosplatJob {
    double iso = 0;             ///< the isovalue (the first of `isos` when several are given)
    /// Several isovalues (`isosurface --iso V1,V2,...`), in order; empty: `iso` alone. Their surfaces
    /// run one after another into the same outputs: the points are those of one run per value,
    /// concatenated in this order (each point's value is its isovalue); the metadata records
    /// `isovalues V1,V2,...` instead of `iso`, and the frame is the union of the surfaces' bounds.
    /// A volume or a sample store; not under mpirun (run_isosplat_mpi_job throws InvalidArgument).
    std::vector<double> isos;
    Projection mode = Projection::approx;
    SamplingParams sp;
    RenderSettings rs;          ///< camera, kernel, shading, colours; the value range is set here unless range_given
    bool range_given = false;   ///< the colour map's range was given (else the volume's, as recorded)
    int threads = 1;
    std::string producer;       ///< the command line, recorded in the metadata
    /// The outputs, made when the graph is about to run (after the input's warnings): -o, if any.
    std::function<std::optional<GeometryOutput>()> out;
    std::optional<std::string> png;
    /// Turns the camera for data whose patient's axes are known (kernels/anatomical_view.hpp); may be
    /// empty. up_given: the front end's up axis was given (a volume's own axes then leave the camera alone).
    std::function<void(const AnatomicalFrame&, Camera&)> anatomical_camera;
    bool up_given = false;
    /// Called once when a picture is made of a volume whose header says nothing of the patient's
    /// axes (and no up axis was given): the front end may say how to turn the camera. May be empty.
    std::function<void(const std::string& volume)> no_axes_hint;
    /// --color-by: each point's value becomes this array's at the point (stream/color_by_stage.hpp);
    /// its grid must be the volume's. The metadata then records `value_name` and the array's value
    /// range (the picture's colour range unless range_given). A volume only: the sample-store and MPI
    /// jobs throw InvalidArgument.
    std::shared_ptr<const ColorByArray> color_by;
    ProgressCounter progress;   ///< may be empty
    std::FILE* stats = nullptr; ///< --stats: the line is written here (null: none)
    bool* warned = nullptr;     ///< when given: set to whether the run warned that its outputs will be empty
};

/// A volume of any kind: framed on its surface bounds, coloured within its value range. Returns the
/// points written.
std::size_t run_isosplat_job(const IsosplatJob& j, VolumeInput& in);

/// A sample store (.mls, ooc/sample_store.hpp): its candidate rows recomputed from its .mlb; the same
/// points and picture as the .mlb gives. Returns the points written.
std::size_t run_isosplat_sample_store_job(const IsosplatJob& j, const std::string& path);

/// Under mpirun (collective): the active bricks of the store `in` split over the ranks, rank 0
/// writing j's outputs; the --stats line on rank 0.
void run_isosplat_mpi_job(const IsosplatJob& j, MpiSession& mpi, VolumeInput& in);

}  // namespace meshless
