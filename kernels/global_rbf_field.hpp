// Hardy's global multiquadric interpolant over all points plus a linear polynomial (dissertation
// section 2.1.1), the accuracy reference for the local fields. Near-duplicates are merged first
// (kernels/merge_near_duplicates.hpp). One dense solve: O(n^3) time, O(n^2) memory while building
// (two n x n doubles), O(n) per evaluation; sets with more than params.global_max_points distinct
// points (default 4000: ~0.25 GB and seconds to build) are refused.
// Defined everywhere (extrapolates: the multiquadric grows linearly far away); bounds() is the
// bounding box of the points. Thread-safe (const) after construction.
// Throws InvalidArgument when the set is larger than the limit or empty, FormatError for non-finite input.
// save_state/load_state carry the fitted state (kernels/field_state.hpp) to and from a .mlf file.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "kernels/field.hpp"
#include "kernels/field_params.hpp"
#include "kernels/field_state.hpp"
#include "kernels/multiquadric.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

class GlobalRbfField final : public Field {
public:
    GlobalRbfField(const PointSet& points, const FieldParams& params, FieldBuildStats* stats = nullptr);
    void evaluate(std::span<const Vec3> p, std::span<double> value, std::span<Vec3> grad) const override;
    std::array<Vec3, 2> bounds() const override { return bounds_; }
    std::string name() const override { return "global-rbf"; }
    MultiquadricOutcome outcome() const { return outcome_; }

    /// The fitted state (kernels/field_state.hpp): merged points, lambdas, the polynomial part.
    void save_state(FieldStateWriter& w) const;
    /// A field from a saved state, validated; evaluates bit-identically to the saved one.
    /// FormatError through FieldState::fail.
    static std::unique_ptr<GlobalRbfField> load_state(FieldState& s);

private:
    GlobalRbfField() = default;
    Vec3 origin_, scale_{1, 1, 1};  // frame = (world - origin_) * scale_
    std::array<Vec3, 2> bounds_;
    std::vector<Vec3> pos_;
    std::vector<std::uint32_t> idx_;
    std::vector<double> lambda_;
    MultiquadricLocal h_;
    MultiquadricOutcome outcome_ = MultiquadricOutcome::interpolated;
};

}  // namespace meshless
