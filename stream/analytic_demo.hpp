// The demo of the main job on an embedded default (`meshless demo`, and any other front end): an
// analytic volume (kernels/analytic_volumes.hpp) iso-splatted by paradigm (C) with the approximate
// projection (dissertation sections 3.3-3.6) into DIR/demo.ply and DIR/demo.png through the graph
// and outputs of `meshless isosurface` (stream/isosplat_pipeline.hpp, stream/point_outputs.hpp):
// the same points and picture as `meshless isosurface` on the same volume, framed on the surface;
// nothing is collected. Throws what the graph and the outputs throw; the folder must exist.
#pragma once
#include <cstdio>
#include <string>

#include "kernels/analytic_volumes.hpp"
#include "stream/isosplat_pipeline.hpp"
#include "stream/render_settings.hpp"

namespace meshless {

struct AnalyticDemo {
    AnalyticField field = AnalyticField::torus;
    long long n = 128;         ///< grid resolution n^3
    RenderSettings rs;         ///< the picture's settings
    bool zoom_given = false;   ///< else the torus and the sphere are zoomed in (their 32-cell frame is mostly empty)
    int threads = 1;
    std::string producer;      ///< the command line, recorded in the outputs
};

/// Runs the demo into `dir` and writes its report (points, active cells, time, the files) to `report`.
void run_analytic_demo(const AnalyticDemo& d, const std::string& dir, std::FILE* report = stdout);

}  // namespace meshless
