#include "stream/projection_meta.hpp"

#include <cmath>

#include "stream/stream_metadata.hpp"

namespace meshless {

void add_projection_meta(StreamMeta& m, const std::string& field, const FieldProjectParams& p) {
    m.set("projection", "newton");
    m.set("field", field);
    m.set("tolerance", p.seed_tolerance);
}

void widen_frame_for_travel(StreamMeta& m, double max_travel) {
    const auto travel = m.get_finite("frame_travel"), diagonal = m.get_finite("frame_cell_diagonal");
    const auto box = meta_bounds(m);
    if (!travel || !diagonal || !box || !std::isfinite(max_travel)) return;
    const double t = *travel, g = *diagonal;
    if (!(max_travel > t) || !(g > 0)) return;
    const double pad = (max_travel - t) * g * (1 + 1e-6);
    m.set("bounds_lo", triple((*box)[0] - Vec3{pad, pad, pad}));
    m.set("bounds_hi", triple((*box)[1] + Vec3{pad, pad, pad}));
    m.set("frame_travel", max_travel);
}

}  // namespace meshless
