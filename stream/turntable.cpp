#include "stream/turntable.hpp"

#include <algorithm>
#include <chrono>

#include "stream/runner.hpp"
#include "stream/splat_sink.hpp"

namespace meshless {

TurntableStats render_turntable(PointSpool& spool, const std::array<Vec3, 2>& bounds, const Camera& cam,
                                SplatKernel kernel, const ShadingParams& shading, int frames, int threads,
                                const std::function<void(int, const Image&)>& emit) {
    TurntableStats t;
    t.frames = std::max(frames, 0);
    spool.flush();
    double sum = 0;
    for (int i = 0; i < t.frames; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        Camera c = cam;
        c.azimuth_deg = cam.azimuth_deg + 360.0 * i / frames;
        SplatSink sink(c, kernel, shading, bounds, threads, &spool);
        PointSpoolSource source(spool);
        const Stage* draw[] = {&sink.stage()};
        run_pipeline(source, draw, sink, {threads});
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        sum += s;
        t.min_seconds = i == 0 ? s : std::min(t.min_seconds, s);
        t.max_seconds = std::max(t.max_seconds, s);
        emit(i, sink.image());
    }
    t.mean_seconds = t.frames ? sum / t.frames : 0;
    return t;
}

}  // namespace meshless
