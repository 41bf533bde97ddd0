// Tests for kernels/amr_cover.hpp: box extents of cell-centred blocks, covered coarse cells of a
// two-level hierarchy (the finest data wins: to_point_set leaves them out), and the padded seed
// lattices (faces reached, linear data extrapolated exactly, all-covered cells counted once).
#include <catch2/catch.hpp>

#include "kernels/amr_cover.hpp"

using namespace meshless;

namespace {

double linear(const Vec3& p) { return 1 + 2 * p.x - 3 * p.y + 0.5 * p.z; }

/// Cell centres of the box [lo, lo + cells*h]^3, level `level`, value linear().
StructuredBlock box(double lo, std::int64_t cells, double h, int level) {
    StructuredBlock b;
    b.dims = {cells, cells, cells};
    b.level = level;
    b.cell_centred = true;
    for (std::int64_t k = 0; k < cells; ++k)
        for (std::int64_t j = 0; j < cells; ++j)
            for (std::int64_t i = 0; i < cells; ++i) {
                const Vec3 p{lo + (i + 0.5) * h, lo + (j + 0.5) * h, lo + (k + 0.5) * h};
                b.node.push_back(p);
                b.value.push_back(linear(p));
            }
    return b;
}

Multiblock two_levels() {
    Multiblock mb;
    mb.blocks.push_back(box(0.0, 4, 1.0, 0));  // [0,4]^3, centres 0.5 .. 3.5
    mb.blocks.push_back(box(1.0, 4, 0.5, 1));  // [1,3]^3, centres 1.25 .. 2.75
    return mb;
}

}  // namespace

TEST_CASE("amr cover: the extent of a cell-centred block is its box", "[amr_cover]") {
    const auto e = block_extent(box(1.0, 4, 0.5, 1));
    CHECK(e[0].x == Approx(1.0));
    CHECK(e[1].z == Approx(3.0));
    StructuredBlock one = box(2.0, 1, 0.25, 2);  // a single cell: half the smallest spacing -> none known, 0
    CHECK(block_extent(one)[0].x == Approx(2.125));
}

TEST_CASE("amr cover: coarse centres under a finer box are covered and left out of the field data", "[amr_cover]") {
    Multiblock mb = two_levels();
    CHECK(mark_amr_covered(mb) == 8);  // centres 1.5, 2.5 along each axis
    CHECK(mb.covered == 8);
    CHECK(mb.blocks[1].covered.empty());  // the finest level covers nothing
    const PointSet ps = to_point_set(mb);
    CHECK(ps.size() == 64 - 8 + 64);
    for (const Vec3& p : ps.pos)
        if (p.x > 1 && p.x < 3 && p.y > 1 && p.y < 3 && p.z > 1 && p.z < 3) CHECK((p.x - 1.25) / 0.5 == Approx(std::round((p.x - 1.25) / 0.5)));
    Multiblock flat;
    flat.blocks.push_back(box(0.0, 3, 1.0, 0));
    CHECK(mark_amr_covered(flat) == 0);
    CHECK(flat.blocks[0].covered.empty());
}

TEST_CASE("amr cover: seed lattices reach the box faces with linear data exact and all-covered cells are known", "[amr_cover]") {
    Multiblock mb = two_levels();
    mark_amr_covered(mb);
    const Multiblock s = amr_seed_blocks(mb);
    REQUIRE(s.blocks.size() == 2);
    const StructuredBlock& c = s.blocks[0];
    CHECK(c.dims == std::array<std::int64_t, 3>{6, 6, 6});
    CHECK(c.node.front().x == Approx(0.0));
    CHECK(c.node.back().z == Approx(4.0));
    for (std::size_t n = 0; n < c.node.size(); ++n) CHECK(c.value[n] == Approx(linear(c.node[n])));
    // covered padded coarse nodes: 1.5, 2.5 per axis (0 and 4 are faces, 0.5 and 3.5 outside [1,3])
    std::int64_t covered = 0;
    for (std::int64_t n = 0; n < c.node_count(); ++n) covered += c.is_covered(n);
    CHECK(covered == 8);
    const StructuredBlock& f = s.blocks[1];
    CHECK(f.dims == std::array<std::int64_t, 3>{6, 6, 6});
    CHECK(f.node.front().x == Approx(1.0));
    CHECK(f.node.back().x == Approx(3.0));
    CHECK(f.covered.empty());
    // node-centred blocks are not padded
    Multiblock nodes;
    StructuredBlock b = box(0.0, 3, 1.0, 0);
    b.cell_centred = false;
    nodes.blocks.push_back(b);
    CHECK_FALSE(has_cell_centred_blocks(nodes));
    CHECK(amr_seed_blocks(nodes).blocks[0].dims == b.dims);
}
