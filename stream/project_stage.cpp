#include "stream/project_stage.hpp"

#include "kernels/errors.hpp"

namespace meshless {

void ProjectStage::process(Batch& b) const {
    ProjectionStats s;
    b.points.clear();
    b.points.reserve(b.samples.size());
    PointRecord p;
    for (const SampleRecord& r : b.samples)
        if (project_sample(r, iso_, mode_, p, s)) b.points.push_back(p);
    b.samples.clear();
    // capacity kept: the runner or the stream source hands the array to a later batch
    b.kind = RecordKind::point;
    stats_.add(s);
}

}  // namespace meshless
