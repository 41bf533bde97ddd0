#include "stream/color_by_stage.hpp"

#include "kernels/multiblock_split.hpp"

namespace meshless {

void ColorByStage::process(Batch& b) const {
    for (PointRecord& p : b.points)
        p.value = static_cast<float>(sample_trilinear(array_, Vec3{p.pos[0], p.pos[1], p.pos[2]}));
}

}  // namespace meshless
