// Colour by another array (`meshless isosurface VOLUME --iso V --color-by NAME`, ParaView's "Color
// By" of a contour): each point's value becomes the trilinear value of another array of the same
// volume at the point's position (kernels/multiblock_split.hpp sample_trilinear, clamped into the
// volume's box), so the point set carries, and the picture maps, say the temperature on a density
// surface. The isovalue stays in the metadata (`iso`); `value_name` names the array.
// Units: world positions; the array's values. Thread-safety: process() is (the volume is read only).
// Throws nothing. Dissertation: none (an output attribute; chapter 3's points are the surface).
#pragma once
#include "kernels/grid.hpp"
#include "stream/stage.hpp"

namespace meshless {

class ColorByStage final : public Stage {
public:
    /// `array` must outlive the stage.
    explicit ColorByStage(VolumeView array) : array_(array) {}
    void process(Batch& b) const override;
    PayloadSet takes() const override { return Payload::points; }
    Payload gives(Payload) const override { return Payload::points; }

private:
    VolumeView array_;
};

}  // namespace meshless
