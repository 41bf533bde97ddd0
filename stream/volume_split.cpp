#include "stream/volume_split.hpp"

#include "formats/terminal_safe.hpp"
#include "formats/vthb_writer.hpp"
#include "formats/vtm_writer.hpp"

namespace meshless {

void write_volume_split(const Volume& v, const VolumeSplitOptions& o, const std::string& out, std::FILE* report) {
    if (o.layout == SplitLayout::amr) {
        const AmrHierarchy h = split_amr(v.view(), o.amr, o.name);
        const auto pieces = write_vthb(out, h);
        long long cells[3] = {0, 0, 0}, boxes[3] = {0, 0, 0};
        for (const AmrBox& b : h.boxes) {
            const auto c = b.cells();
            cells[b.level] += c[0] * c[1] * c[2];
            ++boxes[b.level];
        }
        for (int l = 0; l < 3; ++l)
            std::fprintf(report, "  level %d: %lld boxes, %lld cells, spacing %g\n", l, boxes[l], cells[l], h.spacing(l)[0]);
        std::fprintf(report, "wrote %s and %zu pieces (%lld cells in all)\n", terminal_safe(out).c_str(), pieces.size(),
                     cells[0] + cells[1] + cells[2]);
        return;
    }
    const Multiblock mb = split_volume(v.view(), o.layout, o.split, o.name);
    const auto pieces = write_vtm(out, mb);
    long long total = 0;
    for (const auto& b : mb.blocks) {
        std::fprintf(report, "  %s: %lldx%lldx%lld nodes\n", terminal_safe(b.name).c_str(), static_cast<long long>(b.dims[0]),
                     static_cast<long long>(b.dims[1]), static_cast<long long>(b.dims[2]));
        total += b.node_count();
    }
    std::fprintf(report, "wrote %s and %zu pieces (%lld nodes in all)\n", terminal_safe(out).c_str(), pieces.size(), total);
}

}  // namespace meshless
