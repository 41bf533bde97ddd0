// A turntable (dissertation section 3.6): N frames of the same oriented points, 360/N degrees apart
// about the y axis (frame i at azimuth cam.azimuth_deg + 360 i / N), each drawn by replaying a point
// spool (stream/point_spool.hpp) through the streaming splat sink (stream/splat_sink.hpp): memory =
// one frame's buffers + the batches in flight, for any number of points; the EWA kernel's second
// pass reads the same spool (no second copy). Frame i is byte-identical to
// SplatRenderer::render(all points, kernel, azimuth_i) (kernels/splat_rasterizer.hpp) for any
// thread count.
// Throws what the spool and the sink throw (IoError naming the spool) and what `emit` throws.
// Not thread-safe (one turntable per spool at a time).
#pragma once
#include <array>
#include <functional>

#include "kernels/splat_rasterizer.hpp"
#include "stream/point_spool.hpp"

namespace meshless {

/// Seconds per frame: replay + draw + resolve (not `emit`).
struct TurntableStats {
    int frames = 0;
    double mean_seconds = 0, min_seconds = 0, max_seconds = 0;
};

/// Renders `frames` frames of the spool's points framed by `bounds`, handing frame i to emit(i, image).
TurntableStats render_turntable(PointSpool& spool, const std::array<Vec3, 2>& bounds, const Camera& cam,
                                SplatKernel kernel, const ShadingParams& shading, int frames, int threads,
                                const std::function<void(int, const Image&)>& emit);

}  // namespace meshless
