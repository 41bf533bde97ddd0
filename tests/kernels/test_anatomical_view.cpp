// kernels/anatomical_view.hpp: the default camera of a volume whose header gives the patient's
// axes. Decisions checked against their definition, not pixels: at the frontal angles (the rule's
// azimuth - 30, elevation - 20) the picture's up is the world direction of superior and the eye sits
// on the anterior side; the default then turns by the generic 30 / 20 degrees.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>

#include "kernels/anatomical_view.hpp"

using namespace meshless;

namespace {
Vec3 row(const ViewTransform& v, int r) { return {v.rot[r][0], v.rot[r][1], v.rot[r][2]}; }

// The world direction whose LPS direction is `lps_dir`, for an axis-aligned frame.
Vec3 world_of(const std::array<Vec3, 3>& lps, const Vec3& lps_dir) {
    return {dot(lps[0], lps_dir), dot(lps[1], lps_dir), dot(lps[2], lps_dir)};
}

void check_frontal(const std::array<Vec3, 3>& lps) {
    const AnatomicalView v = anatomical_view(lps);
    Camera c;
    apply_view(v, c);
    c.azimuth_deg = v.azimuth_deg - 30;
    c.elevation_deg = v.elevation_deg - 20;
    const ViewTransform f = make_view(c, {0, 0, 0}, {1, 1, 1});
    const Vec3 superior = world_of(lps, {0, 0, 1}), anterior = world_of(lps, {0, -1, 0});
    CHECK(dot(row(f, 1), superior) == Approx(1).margin(1e-6));  // up in the picture
    CHECK(dot(row(f, 2), anterior) == Approx(1).margin(1e-6));  // towards the viewer: the face
    // the default view: the generic turn from that front
    apply_view(v, c);
    const ViewTransform d = make_view(c, {0, 0, 0}, {1, 1, 1});
    const double deg = M_PI / 180;
    CHECK(dot(row(d, 2), anterior) == Approx(std::cos(30 * deg) * std::cos(20 * deg)).margin(1e-6));
    CHECK(dot(row(d, 2), superior) == Approx(std::sin(20 * deg)).margin(1e-6));  // seen from a little above
}
}  // namespace

TEST_CASE("anatomical view: head up, face towards the viewer, for the frames the headers give", "[camera]") {
    // VTK's headsq CT (NRRD space 3D-left-handed: x L, y P, z I): up -z, camera on -y, as VTK's
    // Medical examples show it (view up 0,0,-1, camera at 0,-1,0)
    const std::array<Vec3, 3> headsq{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, -1}};
    const AnatomicalView h = anatomical_view(headsq);
    CHECK(h.up_axis == 2);
    CHECK(h.up_negative);
    CHECK(h.front_axis == 1);
    CHECK(h.front_negative);
    check_frontal(headsq);
    // MetaImage's LPS identity (HeadMRVolume): up +z, anterior -y
    const std::array<Vec3, 3> lps{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
    const AnatomicalView m = anatomical_view(lps);
    CHECK(m.up_axis == 2);
    CHECK(!m.up_negative);
    CHECK(m.front_axis == 1);
    CHECK(m.front_negative);
    check_frontal(lps);
    // NIfTI RAS identity (the MNI template's sform): up +z, anterior +y
    const std::array<Vec3, 3> ras{Vec3{-1, 0, 0}, Vec3{0, -1, 0}, Vec3{0, 0, 1}};
    const AnatomicalView n = anatomical_view(ras);
    CHECK(n.up_axis == 2);
    CHECK(!n.up_negative);
    CHECK(n.front_axis == 1);
    CHECK(!n.front_negative);
    check_frontal(ras);
    // a sagittal stack: x runs inferior to superior, z right to left
    const std::array<Vec3, 3> sagittal{Vec3{0, 0, 1}, Vec3{0, 1, 0}, Vec3{-1, 0, 0}};
    const AnatomicalView s = anatomical_view(sagittal);
    CHECK(s.up_axis == 0);
    CHECK(!s.up_negative);
    CHECK(s.front_axis == 1);
    check_frontal(sagittal);
    // a coronal stack (y runs superior to inferior, z posterior to anterior): up -y, front +z
    const std::array<Vec3, 3> coronal{Vec3{1, 0, 0}, Vec3{0, 0, -1}, Vec3{0, -1, 0}};
    const AnatomicalView c = anatomical_view(coronal);
    CHECK(c.up_axis == 1);
    CHECK(c.up_negative);
    CHECK(c.front_axis == 2);
    CHECK(!c.front_negative);
    check_frontal(coronal);
    // an oblique frame (15 degrees about x): the nearest axes win
    const double t = 15 * M_PI / 180;
    const std::array<Vec3, 3> oblique{Vec3{1, 0, 0}, Vec3{0, std::cos(t), std::sin(t)}, Vec3{0, -std::sin(t), std::cos(t)}};
    const AnatomicalView o = anatomical_view(oblique);
    CHECK(o.up_axis == 2);
    CHECK(o.front_axis == 1);
    CHECK(o.front_negative);
}
