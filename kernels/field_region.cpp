#include "kernels/field_region.hpp"

#include <algorithm>

namespace meshless {

void FieldFrameBuilder::add(std::span<const Vec3> pos) {
    for (const Vec3& p : pos) {
        if (n_ == 0) {
            bounds_ = {p, p};
            moments_.ref = p;  // (a data point: exact zeros along a plane of the data)
        }
        bounds_[0] = {std::min(bounds_[0].x, p.x), std::min(bounds_[0].y, p.y), std::min(bounds_[0].z, p.z)};
        bounds_[1] = {std::max(bounds_[1].x, p.x), std::max(bounds_[1].y, p.y), std::max(bounds_[1].z, p.z)};
        moments_.add(p - moments_.ref);
        ++n_;
    }
}

FieldFrame FieldFrameBuilder::finish() const {
    FieldFrame f;
    f.bounds = bounds_;
    f.points = n_;
    f.data_flat = n_ > 0 && flat_hull(moments_).has_value();
    return f;
}

FieldFrame field_frame_of(std::span<const Vec3> pos) {
    FieldFrameBuilder b;
    b.add(pos);
    return b.finish();
}

}  // namespace meshless
