// The fitted state of the meshless fields (kernels/field_state.hpp): a state handed from a field
// to a new one evaluates bit-identically, and every inconsistency a damaged or forged state can
// carry (an index out of range, a broken octree, sizes that disagree, derived scalars that do not
// match, missing, surplus or mistyped arrays) is a FormatError naming the array.
#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>

#include "error_of.hpp"
#include "kernels/field_state.hpp"
#include "kernels/errors.hpp"
#include "kernels/make_field.hpp"
#include "kernels/mpu_field.hpp"
#include "kernels/splitmix.hpp"

using namespace meshless;
using namespace meshless::test;

namespace {

/// Collects a field's arrays (as a .mlf would hold them), editable before loading.
struct Collector final : FieldStateWriter {
    std::vector<std::pair<std::string, StateArray>> arrays;
    void put(std::string_view name, StateType type, const void* data, std::size_t count) override {
        auto copy = [&](auto vec) {
            using T = typename decltype(vec)::value_type;
            vec.resize(count);
            if (count) std::memcpy(vec.data(), data, count * sizeof(T));
            return StateArray(std::move(vec));
        };
        switch (type) {
            case StateType::f64: arrays.emplace_back(name, copy(std::vector<double>())); break;
            case StateType::i64: arrays.emplace_back(name, copy(std::vector<std::int64_t>())); break;
            case StateType::u32: arrays.emplace_back(name, copy(std::vector<std::uint32_t>())); break;
            case StateType::i32: arrays.emplace_back(name, copy(std::vector<std::int32_t>())); break;
        }
    }
    template <class T>
    std::vector<T>& get(const std::string& name) {
        for (auto& [n, a] : arrays)
            if (n == name) return std::get<std::vector<T>>(a);
        throw std::logic_error("no array " + name);
    }
    FieldState state() const {
        FieldState s("f.mlf: ", "offset 999");
        for (std::size_t i = 0; i < arrays.size(); ++i) s.add(arrays[i].first, arrays[i].second, "section '" + arrays[i].first + "'");
        return s;
    }
};

PointSet points(std::size_t n) {
    PointSet ps;
    SplitMix r{42};
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 p{r.unit(), 2 * r.unit(), r.unit()};
        ps.pos.push_back(p);
        ps.value.push_back(p.x * p.y + std::sin(4 * p.z));
    }
    ps.blocks.push_back({"p", {static_cast<std::int64_t>(n), 1, 1}, 0, n});
    return ps;
}

struct Saved {
    std::unique_ptr<Field> field;
    Collector c;
};

Saved saved(FieldKind k, std::size_t n = 2000) {
    FieldParams p;
    p.kind = k;
    p.mpu_max_points = 30;
    p.mpu_min_points = 12;
    Saved s;
    s.field = make_field(points(n), p);
    save_field_state(*s.field, s.c);
    return s;
}

std::string load_error(FieldKind k, const Collector& c) {
    return error_of([&] {
        FieldState s = c.state();
        load_field_state(k, s);
    });
}

}  // namespace

TEST_CASE("a field rebuilt from its state evaluates bit-identically", "[kernels][field_state]") {
    for (FieldKind k : {FieldKind::rbf_grid, FieldKind::mpu, FieldKind::global_rbf}) {
        INFO(field_kind_name(k));
        const Saved s = saved(k, k == FieldKind::global_rbf ? 300 : 2000);
        CHECK(fitted_field_kind(*s.field) == k);
        FieldState st = s.c.state();
        const auto g = load_field_state(k, st);
        SplitMix r{5};
        std::vector<Vec3> q(5000);
        for (auto& p : q) p = {1.2 * r.unit() - 0.1, 2.2 * r.unit() - 0.1, 1.2 * r.unit() - 0.1};
        std::vector<double> va(q.size()), vb(q.size());
        std::vector<Vec3> ga(q.size()), gb(q.size());
        s.field->evaluate(q, va, ga);
        g->evaluate(q, vb, gb);
        for (std::size_t i = 0; i < q.size(); ++i) {
            REQUIRE(std::bit_cast<std::uint64_t>(va[i]) == std::bit_cast<std::uint64_t>(vb[i]));
            REQUIRE(std::bit_cast<std::uint64_t>(ga[i].y) == std::bit_cast<std::uint64_t>(gb[i].y));
        }
        // the state of the loaded field is the same state
        Collector again;
        save_field_state(*g, again);
        REQUIRE(again.arrays.size() == s.c.arrays.size());
        for (std::size_t i = 0; i < again.arrays.size(); ++i) CHECK(again.arrays[i] == s.c.arrays[i]);
    }
}

TEST_CASE("missing, surplus and mistyped state arrays are refused", "[kernels][field_state][mustfail]") {
    Saved s = saved(FieldKind::rbf_grid);
    Collector c = s.c;
    c.arrays.erase(c.arrays.begin() + 3);
    CHECK_THAT(load_error(FieldKind::rbf_grid, c), Catch::StartsWith("f.mlf: offset 999: no array '"));
    c = s.c;
    c.arrays.emplace_back("extra", StateArray(std::vector<double>{1.0}));
    CHECK(load_error(FieldKind::rbf_grid, c) == "f.mlf: section 'extra': array 'extra' is not part of this field");
    c = s.c;
    c.arrays[0].second = std::vector<std::int64_t>(12, 0);
    CHECK(load_error(FieldKind::rbf_grid, c) == "f.mlf: section 'frame': array 'frame' holds i64, expected f64");
    // a state of another kind
    CHECK_THAT(load_error(FieldKind::mpu, s.c), Catch::StartsWith("f.mlf: "));
    CHECK_THAT(load_error(FieldKind::global_rbf, s.c), Catch::StartsWith("f.mlf: "));
    c = s.c;
    c.get<double>("frame")[3] = 0;  // axis scale
    CHECK_THAT(load_error(FieldKind::rbf_grid, c), Catch::Contains("section 'frame': axis scale not > 0"));
    c = s.c;
    c.get<double>("locals")[7] = std::nan("");
    CHECK_THAT(load_error(FieldKind::rbf_grid, c), Catch::Contains("section 'locals': local 0: non-finite coefficient"));
}

TEST_CASE("an RBF-grid state with an index out of range or inconsistent sizes is refused", "[kernels][field_state][mustfail]") {
    const Saved s = saved(FieldKind::rbf_grid);
    const std::size_t nl = s.c.arrays.size() ? const_cast<Collector&>(s.c).get<double>("locals").size() / 8 : 0;
    const std::size_t np = const_cast<Collector&>(s.c).get<double>("px").size();
    auto with = [&](auto&& edit) {
        Collector c = s.c;
        edit(c);
        return load_error(FieldKind::rbf_grid, c);
    };
    CHECK_THAT(with([&](Collector& c) { c.get<std::int32_t>("cell_local")[7] = static_cast<std::int32_t>(nl); }),
               Catch::Contains("section 'cell_local': cell 7 names local"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::int32_t>("cell_local")[0] = -2; }), Catch::Contains("section 'cell_local'"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::uint32_t>("runs")[0] = static_cast<std::uint32_t>(np); }),
               Catch::Contains("section 'runs': run 0 ends at point"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::uint32_t>("runs")[1] = 0xFFFFFFFFu; }), Catch::Contains("section 'runs'"));
    CHECK_THAT(with([&](Collector& c) { auto& r = c.get<std::uint32_t>("run_first"); std::swap(r[1], r[2]); r[1] += 1000; }),
               Catch::StartsWith("f.mlf: section '"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::uint32_t>("run_first").back() += 1; }), Catch::Contains("run table does not span"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::uint32_t>("run_first")[1] = 0x7FFFFFFF; }),  // found by fuzz_field_file
               Catch::Contains("section 'run_first': run table not ascending at local 1"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::int64_t>("dims")[0] += 1; }), Catch::Contains("section 'cell_local'"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::int64_t>("dims")[1] = 0; }), Catch::Contains("section 'dims'"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::int64_t>("dims")[2] = std::int64_t{1} << 40; }), Catch::Contains("section 'dims'"));
    CHECK_THAT(with([&](Collector& c) { c.get<double>("grid")[6] *= 2; }), Catch::Contains("1/cell edge does not match"));
    CHECK_THAT(with([&](Collector& c) { c.get<double>("grid")[9] *= 1.5; }), Catch::Contains("reach does not match"));
    CHECK_THAT(with([&](Collector& c) { c.get<double>("grid")[13] *= 1e6; }), Catch::Contains("weight radius outside"));
    CHECK_THAT(with([&](Collector& c) { c.get<double>("grid")[12] = std::nan(""); }), Catch::Contains("non-finite grid value"));
    CHECK_THAT(with([&](Collector& c) { c.get<double>("py").pop_back(); }), Catch::Contains("section 'py'"));
    CHECK_THAT(with([&](Collector& c) { c.get<double>("lambda").resize(10); }), Catch::Contains("section 'local_ranges'"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::uint32_t>("local_ranges")[1] += 1; }),
               Catch::Contains("section 'local_ranges': local 0 has"));
}

TEST_CASE("an RBF-grid state whose weight radius spans too many cells is refused", "[kernels][field_state][mustfail]") {
    // Built grids of any shape (boxes of every aspect, a slab, a line, both supports) load: their
    // queries visit at most 3375 cells (kernels/rbf_grid_field.cpp load_state).
    for (const RbfGridSupport sup : {RbfGridSupport::neighbours27, RbfGridSupport::paper_radius})
        for (const Vec3 box : {Vec3{1, 1, 1}, Vec3{1, 0.3, 0.01}, Vec3{1, 1e-3, 1e-3}, Vec3{1, 0, 0}, Vec3{1, 3, 0.6}}) {
            INFO(box.x << " " << box.y << " " << box.z);
            PointSet ps;
            SplitMix r{9};
            for (int i = 0; i < 3000; ++i) {
                const Vec3 p{box.x * r.unit(), box.y * r.unit(), box.z * r.unit()};
                ps.pos.push_back(p);
                ps.value.push_back(p.x + 2 * p.y - p.z);
            }
            ps.blocks.push_back({"p", {3000, 1, 1}, 0, 3000});
            FieldParams p;
            p.kind = FieldKind::rbf_grid;
            p.rbf_grid_support = sup;
            const auto f = make_field(ps, p);
            Collector c;
            save_field_state(*f, c);
            FieldState st = c.state();
            CHECK_NOTHROW(load_field_state(FieldKind::rbf_grid, st));
        }
    // A forged grid: 200x the cells along x with a tiny edge there, every derived scalar consistent.
    // A query would scan all of x's cells (the whole axis); before the bound it loaded and every
    // evaluation slowed by the axis's length.
    const Saved s = saved(FieldKind::rbf_grid);
    Collector c = s.c;
    auto& dims = c.get<std::int64_t>("dims");
    auto& g = c.get<double>("grid");
    dims[0] *= 200;
    c.get<std::int32_t>("cell_local").assign(static_cast<std::size_t>(dims[0] * dims[1] * dims[2]), -1);
    g[3] = 1e-6;
    g[6] = 1 / g[3];
    g[12] = 2 * std::sqrt(g[3] * g[3] + g[4] * g[4] + g[5] * g[5]);
    g[13] = std::min(g[13], g[12]);
    for (int a = 0; a < 3; ++a) g[9 + a] = dims[a] < 2 ? 0.0 : g[13] / g[3 + a];
    CHECK_THAT(load_error(FieldKind::rbf_grid, c), Catch::Contains("section 'grid': weight radius spans") &&
                                                       Catch::Contains("cells per query (a built grid spans at most 3375)"));
}

TEST_CASE("an MPU state with a broken octree or an index out of range is refused", "[kernels][field_state][mustfail]") {
    const Saved s = saved(FieldKind::mpu);
    auto with = [&](auto&& edit) {
        Collector c = s.c;
        edit(c);
        return load_error(FieldKind::mpu, c);
    };
    auto& links0 = const_cast<Collector&>(s.c).get<std::int32_t>("node_links");
    REQUIRE(links0[0] == 1);  // the root has children 1..8
    const std::size_t nn = links0.size() / 2;
    std::size_t inner = 0;  // an inner node below the root
    for (std::size_t i = 1; i < nn && !inner; ++i)
        if (links0[2 * i] > 0) inner = i;
    REQUIRE(inner > 0);
    CHECK_THAT(with([](Collector& c) { c.get<std::int32_t>("node_links")[0] = 0; }), Catch::Contains("section 'node_links': node 0: children at 0"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::int32_t>("node_links")[2 * inner] = 1; }),
               Catch::Contains("section 'node_links'"));  // a cycle back up the tree
    CHECK_THAT(with([&](Collector& c) { c.get<std::int32_t>("node_links")[0] = static_cast<std::int32_t>(nn - 4); }),
               Catch::Contains("section 'node_links'"));
    CHECK_THAT(with([&](Collector& c) { c.get<std::int32_t>("node_links")[2 * inner + 1] = 0; }),
               Catch::Contains("has children and a local"));
    std::size_t leaf = 0;
    for (std::size_t i = 1; i < nn && !leaf; ++i)
        if (links0[2 * i] < 0) leaf = i;
    CHECK_THAT(with([&](Collector& c) { c.get<std::int32_t>("node_links")[2 * leaf + 1] = 1 << 30; }),
               Catch::Contains("section 'node_links': node " + std::to_string(leaf) + ": local"));
    CHECK_THAT(with([&](Collector& c) {
                   auto& l = c.get<std::int32_t>("node_links");
                   for (std::size_t i = 1; i < nn; ++i)
                       if (l[2 * i] < 0 && i != leaf) { l[2 * i + 1] = l[2 * leaf + 1]; break; }
               }),
               Catch::Contains("used twice"));
    CHECK_THAT(with([](Collector& c) { c.get<double>("nodes")[3] = -1; }), Catch::Contains("section 'nodes': node 0: half edge"));
    CHECK_THAT(with([](Collector& c) { c.get<std::uint32_t>("lookup_leaves")[5] = 1u << 31; }),
               Catch::Contains("section 'lookup_leaves': entry 5 names leaf"));
    CHECK_THAT(with([](Collector& c) { auto& f = c.get<std::uint32_t>("lookup_first"); f[1] = f.back() + 1; }),
               Catch::Contains("section 'lookup_first'"));
    CHECK_THAT(with([](Collector& c) { c.get<std::uint32_t>("lookup_first").pop_back(); }), Catch::Contains("section 'lookup_first'"));
    CHECK_THAT(with([](Collector& c) { c.get<std::uint32_t>("local_ranges")[1] += 100000; }),
               Catch::Contains("section 'local_ranges': local 0 reads terms"));
    CHECK_THAT(with([](Collector& c) { c.get<double>("lambda").pop_back(); }), Catch::Contains("section 'lambda'"));
    CHECK_THAT(with([](Collector& c) { c.get<std::uint32_t>("centre_index")[3] = 1u << 30; }),
               Catch::Contains("section 'centre_index': entry 3 names centre 1073741824 of "));
    CHECK_THAT(with([](Collector& c) { c.get<double>("centres").pop_back(); }), Catch::Contains("section 'centres'"));
    CHECK_THAT(with([](Collector& c) { c.get<std::uint32_t>("centre_index").pop_back(); }), Catch::Contains("section 'lambda'"));
    // the centres are stored once each: far fewer than the entries
    auto& c0 = const_cast<Collector&>(s.c);
    CHECK(c0.get<double>("centres").size() / 3 <= 2000);
    CHECK(c0.get<std::uint32_t>("centre_index").size() > 3 * 2000);
}

TEST_CASE("an MPU state deeper than 60 levels is refused (the evaluation stack is bounded)", "[kernels][field_state][mustfail]") {
    const Saved s = saved(FieldKind::mpu);
    Collector c = s.c;
    // A chain: node 8d+1 .. 8d+8 are the children of node 8(d-1)+1 (the first child of the level above).
    const int depth = 61;
    std::vector<double> nodes;
    std::vector<std::int32_t> links;
    const std::size_t nn = 1 + 8 * depth;
    std::int32_t local = 0;
    for (std::size_t i = 0; i < nn; ++i) {
        nodes.insert(nodes.end(), {0.5, 1.0, 0.5, 1.0, 1.5});
        const bool chained = i == 0 || (i % 8 == 1 && i + 8 < nn);
        links.push_back(chained ? static_cast<std::int32_t>(i == 0 ? 1 : i + 8) : -1);
        links.push_back(chained ? -1 : local++);
    }
    c.get<double>("nodes") = nodes;
    c.get<std::int32_t>("node_links") = links;
    CHECK_THAT(load_error(FieldKind::mpu, c), Catch::Contains("octree deeper than 60 levels"));
}

TEST_CASE("a global RBF state is checked too", "[kernels][field_state][mustfail]") {
    const Saved s = saved(FieldKind::global_rbf, 200);
    auto with = [&](auto&& edit) {
        Collector c = s.c;
        edit(c);
        return load_error(FieldKind::global_rbf, c);
    };
    CHECK_THAT(with([](Collector& c) { c.get<double>("lambda").pop_back(); }), Catch::Contains("section 'lambda'"));
    CHECK_THAT(with([](Collector& c) { c.get<std::uint32_t>("local_ranges")[1] = 7; }),
               Catch::Contains("the interpolant does not span the points"));
    CHECK_THAT(with([](Collector& c) { c.get<std::uint32_t>("outcome")[0] = 9; }), Catch::Contains("unknown fit outcome"));
    CHECK_THAT(with([](Collector& c) { c.get<double>("points").pop_back(); }), Catch::Contains("section 'points'"));
}

TEST_CASE("an MPU state whose leaf spheres are huge loads with a coarse lookup grid and bounded work", "[kernels][field_state][mustfail]") {
    // A hostile .mlf: every leaf's blend radius 1e150 (finite and within the bound, so accepted). The lookup lists the
    // field evaluates with are built from these spheres: without a bound they would list every leaf
    // in every cell of a fine grid (and overflow 32-bit offsets on large fields).
    const Saved s = saved(FieldKind::mpu, 6000);
    Collector c = s.c;
    auto& nodes = c.get<double>("nodes");
    const auto& links = c.get<std::int32_t>("node_links");
    std::size_t leaves = 0;
    for (std::size_t i = 0; i < nodes.size() / 5; ++i)
        if (links[2 * i] < 0) {
            nodes[5 * i + 4] = 1e150;
            ++leaves;
        }
    REQUIRE(leaves > 100);
    FieldState st = c.state();
    const auto f = load_field_state(FieldKind::mpu, st);
    const auto& mpu = dynamic_cast<const MpuField&>(*f);
    // every leaf blends everywhere now: the lookup (or the tree) finds them all, in order
    for (const Vec3& x : {Vec3{0.5, 1, 0.5}, Vec3{0.01, 0.02, 0.99}, Vec3{5, -3, 2}}) {
        const auto got = mpu.blended_leaves(x);
        CHECK(got.size() == leaves);
        CHECK(std::is_sorted(got.begin(), got.end()));
    }
    CHECK(std::isfinite(f->value({0.5, 1, 0.5})));
    // saving it again would need the fine lists of version 1's grid: refused, not attempted
    Collector again;
    CHECK_THROWS_AS(save_field_state(*f, again), InvalidArgument);
}

TEST_CASE("an MPU state whose node values could overflow is refused", "[kernels][field_state][mustfail]") {
    // Found by fuzz_field_file: finite node values whose sums overflow (root half edge 1e308: the
    // lookup grid started at -inf or its inverse cell size was 0, so a leaf's cell range was
    // inf - inf or inf * 0 = NaN), which std::clamp passed on to an integer conversion (undefined;
    // UBSan aborted in the sanitizer tier). The octree lives in the unit-sized fitting frame: node
    // values beyond +-1e150 are refused (no sum or square of them overflows), and a NaN lookup
    // range would list the leaf on the whole axis.
    const Saved s = saved(FieldKind::mpu, 3000);
    for (const std::size_t k : {std::size_t{0}, std::size_t{3}, std::size_t{5 * 9 + 4}}) {
        for (const double v : {1e308, -2e150}) {
            INFO("nodes[" << k << "] = " << v);
            Collector c = s.c;
            c.get<double>("nodes")[k] = v;
            FieldState st = c.state();
            const std::string err = error_of([&] { (void)load_field_state(FieldKind::mpu, st); });
            CHECK_THAT(err, Catch::Contains("f.mlf: section 'nodes': node ") && Catch::Contains("beyond +-1e150"));
        }
    }
}
