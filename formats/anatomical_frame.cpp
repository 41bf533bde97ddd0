#include "formats/anatomical_frame.hpp"

#include <cctype>
#include <cmath>

namespace meshless {

namespace {

std::optional<AnatomicalFrame> normalised(std::array<Vec3, 3> axis, std::string source) {
    for (auto& v : axis) {
        const double n = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
        if (!(n > 0) || !std::isfinite(n)) return std::nullopt;
        v = Vec3{v.x / n, v.y / n, v.z / n};
    }
    return AnatomicalFrame{axis, std::move(source)};
}

// LPS signs of a NRRD anatomical space's axes (RAS: +x right = -L, +y anterior = -P).
std::optional<Vec3> space_signs(const std::string& s) {
    if (s == "right-anterior-superior" || s == "ras" || s == "right-anterior-superior-time" || s == "rast") return Vec3{-1, -1, 1};
    if (s == "left-anterior-superior" || s == "las" || s == "left-anterior-superior-time" || s == "last") return Vec3{1, -1, 1};
    if (s == "left-posterior-superior" || s == "lps" || s == "left-posterior-superior-time" || s == "lpst") return Vec3{1, 1, 1};
    return std::nullopt;
}

}  // namespace

std::optional<AnatomicalFrame> nrrd_frame(const std::string& space, const std::vector<Vec3>& directions) {
    if (space == "3d-right-handed" || space == "3d-left-handed" || space == "3d-right-handed-time" ||
        space == "3d-left-handed-time") {
        const bool left = space.rfind("3d-left", 0) == 0;
        return normalised({Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, left ? -1.0 : 1.0}},
                          "NRRD space " + space + " (DICOM axial convention)");
    }
    const auto signs = space_signs(space);
    if (!signs) return std::nullopt;
    std::array<Vec3, 3> axis{Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};
    if (directions.size() == 3)
        for (int a = 0; a < 3; ++a) axis[a] = directions[a];
    for (auto& v : axis) v = Vec3{v.x * signs->x, v.y * signs->y, v.z * signs->z};
    return normalised(axis, "NRRD space " + space + (directions.size() == 3 ? " and space directions" : ""));
}

std::optional<AnatomicalFrame> metaimage_frame(const std::vector<double>& t, const std::string& orientation) {
    if (t.size() == 9)
        return normalised({Vec3{t[0], t[1], t[2]}, Vec3{t[3], t[4], t[5]}, Vec3{t[6], t[7], t[8]}}, "MetaImage TransformMatrix");
    if (orientation.size() == 3) {
        std::array<Vec3, 3> axis{};
        for (int a = 0; a < 3; ++a) {
            // the letter names where the axis comes from: it points the other way
            switch (std::toupper(static_cast<unsigned char>(orientation[a]))) {
                case 'R': axis[a] = Vec3{1, 0, 0}; break;
                case 'L': axis[a] = Vec3{-1, 0, 0}; break;
                case 'A': axis[a] = Vec3{0, 1, 0}; break;
                case 'P': axis[a] = Vec3{0, -1, 0}; break;
                case 'I': axis[a] = Vec3{0, 0, 1}; break;
                case 'S': axis[a] = Vec3{0, 0, -1}; break;
                default: return std::nullopt;
            }
        }
        return normalised(axis, "MetaImage AnatomicalOrientation");
    }
    return normalised({Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, "MetaImage (ITK's LPS identity)");
}

std::optional<AnatomicalFrame> ras_frame(const std::array<Vec3, 3>& c, const std::string& source) {
    return normalised({Vec3{-c[0].x, -c[0].y, c[0].z}, Vec3{-c[1].x, -c[1].y, c[1].z}, Vec3{-c[2].x, -c[2].y, c[2].z}}, source);
}

void flip_frame(std::optional<AnatomicalFrame>& f, const std::array<bool, 3>& flip) {
    if (!f) return;
    for (int a = 0; a < 3; ++a)
        if (flip[a]) f->axis[a] = Vec3{-f->axis[a].x, -f->axis[a].y, -f->axis[a].z};
}

std::optional<std::array<double, 3>> axis_aligned_signs(const std::array<Vec3, 3>& columns) {
    std::array<double, 3> sign{1, 1, 1};
    for (int i = 0; i < 3; ++i) {
        const Vec3& c = columns[static_cast<std::size_t>(i)];
        const double len = norm(c);
        if (!(len > 0) || !std::isfinite(len)) return std::nullopt;
        for (int j = 0; j < 3; ++j)
            if (j != i && std::fabs(c[j]) > 1e-3 * len) return std::nullopt;
        sign[static_cast<std::size_t>(i)] = c[i] < 0 ? -1.0 : 1.0;
    }
    return sign;
}

std::array<std::array<double, 3>, 3> frame_axes(const AnatomicalFrame& f) {
    std::array<std::array<double, 3>, 3> ax{};
    for (std::size_t i = 0; i < 3; ++i) ax[i] = {f.axis[i].x, f.axis[i].y, f.axis[i].z};
    return ax;
}

AnatomicalFrame frame_of_axes(const std::array<std::array<double, 3>, 3>& axes, std::string source) {
    AnatomicalFrame f;
    for (std::size_t i = 0; i < 3; ++i) f.axis[i] = Vec3{axes[i][0], axes[i][1], axes[i][2]};
    f.source = std::move(source);
    return f;
}

std::string describe_frame(const AnatomicalFrame& f) {
    static const char kPos[3] = {'L', 'P', 'S'}, kNeg[3] = {'R', 'A', 'I'};
    std::string s;
    for (int a = 0; a < 3; ++a) {
        const Vec3& v = f.axis[a];
        int best = 0;
        for (int k = 1; k < 3; ++k)
            if (std::fabs(v[k]) > std::fabs(v[best])) best = k;
        if (a) s += ", ";
        s += static_cast<char>('x' + a);
        s += ' ';
        s += v[best] >= 0 ? kPos[best] : kNeg[best];
    }
    return s;
}

}  // namespace meshless
