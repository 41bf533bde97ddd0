// What a front end asks of a chapter-4 or chapter-5 isosurface run (dissertation sections 4.4 and
// 5.6), once its options are checked: the isovalue, the barycentric lattice, the Newton projection,
// the outputs (stream/point_outputs.hpp: a point set and/or a PNG), the threads, a progress counter
// and where the --stats block goes. The runs that take it: stream/block_isosurface_job.hpp and
// stream/scattered_isosurface_job.hpp. Units: isovalue in the data's value units; times in seconds
// since `started`. A plain struct: nothing here throws.
#pragma once
#include <chrono>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

#include "stream/field_project_stage.hpp"
#include "stream/point_outputs.hpp"
#include "stream/progress_stage.hpp"
#include "stream/render_settings.hpp"

namespace meshless {

struct IsosurfaceJob {
    double iso = 0;
    int n = 0;                 ///< the barycentric lattice parameter (1..kMaxLatticeN): N(N+1)/2 seeds a triangle
    FieldProjectParams np;     ///< Newton onto the field
    RenderSettings rs;         ///< the picture's camera, kernel, shading and colours
    int threads = 1;
    std::optional<GeometryOutput> out;  ///< -o: the oriented point set
    std::optional<std::string> png;     ///< --png: the picture
    ProgressCounter progress;           ///< may be empty: no progress counted (stream/progress_stage.hpp)
    std::FILE* stats = nullptr;         ///< --stats: the statistics block is written here (null: none)
    std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();  ///< the command's start
};

}  // namespace meshless
