// `meshless-bench hierarchy`: the numbers for the cluster binary tree (dissertation chapter 6,
// Tables 6.1-6.2), measured in process on the library (kernels/cluster_binary_tree.hpp) except the
// peak memory, which is the `meshless hierarchy` process's own (run_sh: its ru_maxrss, measured from a
// fresh wrapper process; a child forked from the bench itself would inherit the bench's resident set
// as its high-water mark — the 61-66 bytes/sample reported before were the bench's own ~180 MiB):
//   (a) silicium 98x34x34 (113,288 samples): full refinement on 1 thread (splits, skipped, depth,
//       wall and CPU time, best of --reps), level-based LOD sizes at 15 and 16 (Table 6.2: 18.52%,
//       34.71%).
//   (b) the head: vtk_headsq upsampled x2 with `meshless synth` (127x127x185 = 2,983,865 samples),
//       read brick by brick, refined to 300,000 splits on 1 thread and on 2, alternating, --reps
//       pairs (at most 7) (speed-up: best of each, and the median of the pairs' ratios; identical nodes), error-based LOD sizes at 60 and 4.5 in the data's units (0..3926) and at the same
//       thresholds scaled to a 0..255 range (the dissertation's head was 0..255).
//       --quick: the head x1 (380,928 samples) to 30,000 splits.
//   (c) LOD extraction rate: the finest level- and error-based LODs of the head tree, nodes visited
//       per second (best of 5).
//   (d) peak RSS of `meshless hierarchy` on the head store, bytes per input sample.
//   (e) at 1%, 2%, 5% and 15% of the samples (m points): the default tree's LOD of m points (the
//       leaves after its first m - 1 splits, `lod --count m`), a uniform random subsample and a
//       regular decimation (every (n/m)-th voxel in file order) of the same count; the mpu field
//       (section 5.5, defaults or --hardy-c) of each evaluated at the original voxels, RMSE and max
//       error against the voxel values, over the voxels where all fields are finite (the others
//       counted). Silicium and the head x1 at every voxel; the tooth at every 4th, LIDC2 (8.7 M
//       voxels) at every 8th voxel (the evaluation is subsampled, the tree and the fields use every
//       sample). The trees are refined to 16% of the samples (--max-splits) so the 15% LOD exists.
//       Two more columns: the dissertation's tree (max-error order, fitted cluster values; its
//       error-based LOD closest to m points), and the first m points of the default tree's finest
//       LOD, which `lod` lists coarse to fine (a prefix read by a viewer that stops early); and the
//       PSNR of a picture of the CBT, random and decimated sets (their mpu fields ray cast in the
//       volume's frame, as `render --bounds --step --ref-step --range --compare` does) against the volume's.
//       --quick: silicium only.
#include <sys/resource.h>
#include <unistd.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include "bench/bench_common.hpp"
#include "formats/point_set_reader.hpp"
#include "kernels/cluster_binary_tree.hpp"
#include "kernels/cluster_lod.hpp"
#include "kernels/field_params.hpp"
#include "kernels/make_field.hpp"
#include "kernels/splitmix.hpp"
#include "kernels/image_compare.hpp"
#include "ooc/brick_store_point_set.hpp"
#include "stream/field_render.hpp"

namespace meshless::bench {

namespace {

namespace fs = std::filesystem;

double cpu_seconds() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
}

struct Timed {
    ClusterTree tree;
    double wall_s = 1e300, cpu_s = 1e300;
};

Timed build_timed(const PointSet& ps, const CbtParams& p, int threads, int reps) {
    Timed t;
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
    for (int i = 0; i < reps; ++i) {
        const double c0 = cpu_seconds();
        Stopwatch sw;
        ClusterTree tr = build_cluster_tree(ps.pos, ps.value, p);
        const double w = sw.ms() / 1000, c = cpu_seconds() - c0;
        t.wall_s = std::min(t.wall_s, w);
        t.cpu_s = std::min(t.cpu_s, c);
        t.tree = std::move(tr);
    }
    return t;
}

std::string pct_of(std::uint64_t a, std::uint64_t n) { return fmt("%.2f%%", 100.0 * a / n); }

/// The error threshold whose error-based LOD is closest to m points (bisection).
double error_for_size(const ClusterTree& t, std::uint64_t m) {
    double lo = 0, hi = t.nodes[0].error;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (lod_size_at_error(t.nodes, mid) > m) lo = mid;
        else hi = mid;
    }
    return hi;
}

PointSet subset(const PointSet& ps, const std::vector<std::size_t>& ids) {
    PointSet s;
    for (std::size_t i : ids) {
        s.pos.push_back(ps.pos[i]);
        s.value.push_back(ps.value[i]);
    }
    s.value_name = ps.value_name;
    s.blocks.push_back(PointSetBlock{"subset", {static_cast<std::int64_t>(ids.size()), 1, 1}, 0, ids.size()});
    return s;
}

struct Rmse {
    double rmse = 0, max = 0;
    std::size_t nan = 0;
};

/// The volume's own picture, as `meshless render VOLUME` makes it (the default grey transfer
/// function over its value range, no shading), and the settings every point set is rendered with:
/// the volume's frame, step and opacity unit (half its smallest spacing), `side` pixels square.
struct LodPicture {
    Camera cam;
    TransferFunction tf;
    RenderOptions ro;
    Image reference;
};

LodPicture volume_picture(const std::string& path, int side) {
    RenderInput in = volume_render_input(open_volume_input(path, VolumeOpenOptions{}));
    LodPicture p{Camera{}, render_transfer_function("grey", in.range, false), RenderOptions{}, Image{}};
    p.cam.width = p.cam.height = side;
    p.ro.step = p.ro.ref_step = 0.5 * in.spacing;
    p.ro.bounds = in.box;
    p.ro.threads = 2;
    p.reference = render_field(in, p.cam, p.tf, p.ro).picture;
    return p;
}

/// PSNR (dB) of the picture of `points` through `field` against the volume's.
double picture_psnr(const LodPicture& pic, const PointSet& points, const Field& field) {
    RenderInput in = points_render_input(points, field, "lod");
    return compare_images(render_field(in, pic.cam, pic.tf, pic.ro).picture, pic.reference).psnr;
}

void compare_row(const std::string& name, const PointSet& all, const ClusterTree& tree, const ClusterTree& paper_tree, double frac,
                 std::size_t eval_stride, double hardy_c_rel, const LodPicture* pic, Table& t) {
    const std::size_t n = all.size();
    const std::uint64_t m = static_cast<std::uint64_t>(std::llround(frac * n));
    // the default tree's LOD of m points: the leaves after its first m - 1 splits (LodMode::count)
    const PointSet cbt = lod_point_set(tree.nodes, LodMode::count, static_cast<double>(m), all.value_name);
    std::vector<std::size_t> ids(n);
    std::iota(ids.begin(), ids.end(), std::size_t{0});
    SplitMix rng{12345};
    for (std::size_t i = 0; i < m; ++i) std::swap(ids[i], ids[i + rng.next() % (n - i)]);  // partial Fisher-Yates
    std::vector<std::size_t> rnd(ids.begin(), ids.begin() + static_cast<std::ptrdiff_t>(m));
    std::sort(rnd.begin(), rnd.end());
    std::vector<std::size_t> dec(m);
    for (std::size_t i = 0; i < m; ++i) dec[i] = static_cast<std::size_t>((static_cast<unsigned __int128>(i) * n) / m);
    // the dissertation's tree (max-error order, fitted values): its error-based LOD closest to m points
    const double e = error_for_size(paper_tree, m);
    const PointSet paper = lod_point_set(paper_tree.nodes, LodMode::error, e, all.value_name);
    // the first m points of the default tree's finest LOD, which lod lists coarse to fine (kernels/cluster_lod.hpp)
    PointSet prefix = lod_point_set(tree.nodes, LodMode::level, 1e9, all.value_name);
    std::vector<std::size_t> first(std::min<std::size_t>(m, prefix.size()));
    std::iota(first.begin(), first.end(), std::size_t{0});
    prefix = subset(prefix, first);
    const PointSet sets[5] = {cbt, subset(all, rnd), subset(all, dec), paper, prefix};
    std::vector<Vec3> q;
    std::vector<double> ref;
    for (std::size_t i = 0; i < n; i += eval_stride) {
        q.push_back(all.pos[i]);
        ref.push_back(all.value[i]);
    }
    std::vector<std::vector<double>> val(5, std::vector<double>(q.size()));
    double build_s = 0;
    double psnr[3] = {NAN, NAN, NAN};  // CBT, random, decimation
    for (int s = 0; s < 5; ++s) {
        FieldParams fp;
        fp.kind = FieldKind::mpu;
        if (hardy_c_rel > 0) fp.hardy_c_rel = hardy_c_rel;
        Stopwatch sw;
        auto f = make_field(sets[s], fp);
        build_s += sw.ms() / 1000;
        f->evaluate(q, val[s], {});
        if (pic && s < 3) psnr[s] = picture_psnr(*pic, sets[s], *f);
    }
    Rmse r[5];
    std::size_t used = 0, skipped = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
        bool finite = true;
        for (int s = 0; s < 5; ++s) finite = finite && std::isfinite(val[s][i]);
        if (!finite) {
            ++skipped;
            continue;
        }
        ++used;
        for (int s = 0; s < 5; ++s) {
            const double d = val[s][i] - ref[i];
            r[s].rmse += d * d;
            r[s].max = std::max(r[s].max, std::abs(d));
        }
    }
    for (auto& x : r) x.rmse = used ? std::sqrt(x.rmse / used) : NAN;
    const char* best = r[0].rmse <= std::min(r[1].rmse, r[2].rmse) ? "CBT" : (r[1].rmse <= r[2].rmse ? "random" : "decimation");
    t.add({name, fmt("%.0f%%", frac * 100), fmt("%llu", static_cast<unsigned long long>(m)), fmt("%.3f", r[0].rmse),
           fmt("%.3f", r[1].rmse), fmt("%.3f", r[2].rmse), fmt("%.2f / %.2f", r[0].rmse / r[1].rmse, r[0].rmse / r[2].rmse),
           fmt("%.1f / %.1f / %.1f", r[0].max, r[1].max, r[2].max), best, fmt("%zu: %.3f", paper.size(), r[3].rmse),
           fmt("%.3f", r[4].rmse),
           pic ? fmt("%.2f / %.2f / %.2f", psnr[0], psnr[1], psnr[2]) : std::string("-"),
           fmt("%zu (%zu non-finite left out)", used, skipped)});
}

}  // namespace

void run_hierarchy(const BenchOptions& o, Report& r) {
    r.section("Hierarchy: cluster binary trees, dissertation chapter 6");
    const fs::path data(o.data_dir);
    const int reps = o.quick ? 1 : std::max(1, std::min(o.reps, 3));
    const fs::path si = data / "silicium" / "silicium_98x34x34_uint8.raw";
    const fs::path head = data / "vtk_headsq" / "quarter.nhdr";
    const fs::path lidc = data / "vtkjs_LIDC2" / "LIDC2.vti";
    const fs::path work = fs::temp_directory_path() / ("meshless-bench-hier-" + std::to_string(getpid()));
    fs::create_directories(work);

    // (a) silicium, Tables 6.1-6.2
    PointSet sil;
    ClusterTree sil_tree;
    if (fs::exists(si)) {
        sil = point_set_from_volume(si.string());
        const Timed t = build_timed(sil, CbtParams{}, 1, reps);
        sil_tree = t.tree;
        const auto lv = lod_sizes_per_level(t.tree.nodes);
        auto at = [&](std::size_t L) { return L < lv.size() ? lv[L] : lv.back(); };
        Table tab;
        tab.header = {"data", "samples", "splits", "skipped", "depth", "wall s (1 thread)", "CPU s", "level 15", "level 16",
                      "dissertation"};
        tab.add({"silicium 98x34x34", fmt("%zu", sil.size()), fmt("%llu", (unsigned long long)t.tree.stats.splits),
                 fmt("%llu", (unsigned long long)t.tree.stats.skipped), fmt("%u", t.tree.stats.depth), fmt("%.3f", t.wall_s),
                 fmt("%.3f", t.cpu_s), fmt("%llu (%s)", (unsigned long long)at(15), pct_of(at(15), sil.size()).c_str()),
                 fmt("%llu (%s)", (unsigned long long)at(16), pct_of(at(16), sil.size()).c_str()),
                 "64,084 splits, 2 skipped, depth 19, 50 s; L15 20,982 (18.52%), L16 39,324 (34.71%)"});
        r.table(tab);
    } else {
        r.note("silicium not found under " + o.data_dir + ": (a) skipped");
    }

    // (b)-(d) the head
    if (fs::exists(head)) {
        std::string store = (work / "head2.mlb").string();
        PointSet hp;
        std::string what;
        if (o.quick) {
            hp = point_set_from_volume(head.string());
            what = "head x1 (64x64x93)";
        } else {
            const std::string cmd = shell_quote(o.meshless) + " synth --upsample 2 " + shell_quote(head.string()) + " -o " +
                                    shell_quote(store) + " 2>/dev/null";
            if (std::system(cmd.c_str()) != 0) throw std::runtime_error("meshless synth failed: " + cmd);
            hp = point_set_from_brick_store(store);
            what = "head x2 (127x127x185, meshless synth)";
        }
        CbtParams p;
        p.max_splits = o.quick ? 30000 : 300000;
        // alternating 1- and 2-thread builds: this kind of VM drifts by +-30 % between identical runs,
        // so the speed-up is the median of the pairs' ratios (best-of times beside it)
        Timed t1, t2;
        std::vector<double> pair_ratio;
        const int pairs = o.quick ? 1 : std::clamp(o.reps, 1, 7);
        for (int i = 0; i < pairs; ++i) {
            Timed a = build_timed(hp, p, 1, 1), b = build_timed(hp, p, 2, 1);
            pair_ratio.push_back(a.wall_s / b.wall_s);
            t1.wall_s = std::min(t1.wall_s, a.wall_s);
            t1.cpu_s = std::min(t1.cpu_s, a.cpu_s);
            t2.wall_s = std::min(t2.wall_s, b.wall_s);
            t2.cpu_s = std::min(t2.cpu_s, b.cpu_s);
            t1.tree = std::move(a.tree);
            t2.tree = std::move(b.tree);
        }
        std::sort(pair_ratio.begin(), pair_ratio.end());
        const double median_ratio = pair_ratio.size() % 2 ? pair_ratio[pair_ratio.size() / 2]
                                                          : 0.5 * (pair_ratio[pair_ratio.size() / 2 - 1] + pair_ratio[pair_ratio.size() / 2]);
        const bool same = t1.tree.nodes.size() == t2.tree.nodes.size() &&
                          std::memcmp(t1.tree.nodes.data(), t2.tree.nodes.data(), t1.tree.nodes.size() * sizeof(CbtNode)) == 0;
        const double range = hp.value_range()[1] - hp.value_range()[0];
        auto lod_e = [&](double e) {
            const auto m = lod_size_at_error(t2.tree.nodes, e);
            return fmt("%llu (%s)", (unsigned long long)m, pct_of(m, hp.size()).c_str());
        };
        Table tab;
        tab.header = {"data", "samples", "splits", "skipped", "depth", "error reached", "wall s 2 threads", "wall s 1 thread",
                      "speed-up (best of)", "speed-up (median of pairs)", "CPU s (2 thr)", "same nodes"};
        tab.add({what, fmt("%zu", hp.size()), fmt("%llu", (unsigned long long)t2.tree.stats.splits),
                 fmt("%llu", (unsigned long long)t2.tree.stats.skipped), fmt("%u", t2.tree.stats.depth),
                 fmt("%.4g", t2.tree.stats.error_reached), fmt("%.2f", t2.wall_s), fmt("%.2f", t1.wall_s),
                 fmt("%.2fx", t1.wall_s / t2.wall_s), fmt("%.2fx (%zu pairs, %.2f-%.2f)", median_ratio, pair_ratio.size(), pair_ratio.front(), pair_ratio.back()),
                 fmt("%.2f", t2.cpu_s), same ? "yes" : "NO"});
        r.table(tab);
        Table lt;
        lt.header = {"error threshold", "LOD points (data units 0..3926)", "threshold x range/255", "LOD points (scaled)",
                     "dissertation (head 0..255)"};
        lt.add({"60", lod_e(60), fmt("%.1f", 60 * range / 255), lod_e(60 * range / 255), "17,528 (0.84%)"});
        lt.add({"4.5", lod_e(4.5), fmt("%.1f", 4.5 * range / 255), lod_e(4.5 * range / 255), "300,648 (14.34%)"});
        r.table(lt);

        // (c) LOD extraction rate
        Table xt;
        xt.header = {"LOD", "points", "nodes", "best of 5 wall ms", "M nodes/s (wall)", "CPU ms", "M nodes/s (CPU)"};
        for (int mode = 0; mode < 2; ++mode) {
            double best = 1e300, best_cpu = 1e300;
            std::size_t pts = 0;
            for (int i = 0; i < 5; ++i) {
                const double c0 = cpu_seconds();
                Stopwatch sw;
                const auto ids = mode == 0 ? lod_nodes(t2.tree.nodes, LodMode::level, t2.tree.stats.depth)
                                           : lod_nodes(t2.tree.nodes, LodMode::error, 0);
                best = std::min(best, sw.ms());
                best_cpu = std::min(best_cpu, 1000 * (cpu_seconds() - c0));
                pts = ids.size();
            }
            const std::size_t visited = 2 * pts - 1;  // the finest LOD visits every node
            xt.add({mode == 0 ? "level = depth (finest)" : "error 0 (finest)", fmt("%zu", pts), fmt("%zu", visited), fmt("%.2f", best),
                    fmt("%.1f", visited / best / 1000), fmt("%.2f", best_cpu), fmt("%.1f", visited / std::max(best_cpu, 1e-3) / 1000)});
        }
        r.table(xt);

        // (d) peak RSS of the process
        if (!o.quick) {
            const std::string out = (work / "head.mlh").string();
            const Run run = run_sh(shell_quote(o.meshless) + " hierarchy " + shell_quote(store) + " -o " + shell_quote(out) +
                                       " --max-splits 300000 --threads 2",
                                   work / "hierarchy.err");
            const int code = run.code;
            const double rss = 1024.0 * static_cast<double>(run.maxrss_kib);
            Table mt;
            mt.header = {"process", "exit", "peak RSS", "bytes / sample", "target"};
            mt.add({"meshless hierarchy head2.mlb --max-splits 300000 --threads 2", fmt("%d", code), bytes_str(rss),
                    fmt("%.1f", rss / hp.size()), "<= 64"});
            r.table(mt);
        }
    } else {
        r.note("vtk_headsq not found: (b)-(d) skipped");
    }

    std::error_code ec;
    fs::remove_all(work, ec);
    run_hierarchy_rmse(o, r, sil);
}

void run_hierarchy_rmse(const BenchOptions& o, Report& r, const PointSet& sil_given) {
    const fs::path data(o.data_dir);
    const fs::path si = data / "silicium" / "silicium_98x34x34_uint8.raw";
    const fs::path head = data / "vtk_headsq" / "quarter.nhdr";
    const fs::path lidc = data / "vtkjs_LIDC2" / "LIDC2.vti";
    const fs::path tooth = data / "tooth" / "tooth_103x94x161_uint8.raw";
    const PointSet sil = !sil_given.pos.empty() || !fs::exists(si) ? sil_given : point_set_from_volume(si.string());
    // (e) reconstruction error at equal point counts
    std::vector<double> cs;
    if (!o.hardy_c.empty())
        for (const std::string& w : split_list(o.hardy_c)) {
            const double c = std::stod(w);
            if (!(c > 0) || !std::isfinite(c)) throw std::runtime_error("--hardy-c: '" + w + "' is not a positive number");
            cs.push_back(c);
        }
    if (cs.empty()) cs.push_back(0);  // the field's default
    r.note("(e) mpu field of each point set evaluated at the original voxels; RMSE in data units; equal point counts "
           "(the CBT LOD's size); one table per data set and Hardy c (relative to the point set's bounding-box diagonal; "
           "the same c for all five sets of a row).");
    Table ct;
    ct.header = {"data", "points", "count", "RMSE CBT", "RMSE random", "RMSE decimation", "CBT / random / decimation",
                 "max err C/R/D", "best", "dissertation's CBT: count: RMSE", "RMSE finest LOD's prefix",
                 "picture PSNR dB C/R/D", "voxels evaluated"};
    const int side = o.quick ? 128 : 256;
    r.note(fmt("picture PSNR: each set's mpu field ray cast (%dx%d, the `render` defaults: grey transfer function over "
               "the volume's value range, no shading) in the volume's frame with its step and opacity unit (half the "
               "smallest spacing), against the volume's own trilinear picture; `meshless render LOD.ply --bounds "
               "BOX --step S --ref-step S --range LO,HI --compare volume.png` computes the same.",
               side, side));
    auto compare = [&](const std::string& name, const fs::path& path, const PointSet& ps, std::size_t stride) {
        CbtParams p;  // the defaults (weighted order, cluster means)
        p.max_splits = static_cast<std::uint64_t>(0.16 * ps.size());
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
        const ClusterTree t = build_cluster_tree(ps.pos, ps.value, p);
        p.order = CbtSplitOrder::max_error;  // the dissertation's: section 6.3
        p.value = CbtValueKind::fit;
        const ClusterTree paper = build_cluster_tree(ps.pos, ps.value, p);
        const LodPicture pic = volume_picture(path.string(), side);
        for (double c : cs) {
            r.note(name + ", mpu Hardy c = " + (c > 0 ? fmt("%g", c) : fmt("%g (default)", FieldParams{}.hardy_c_rel)) +
                   " x bounding-box diagonal");
            for (double f : {0.01, 0.02, 0.05, 0.15}) compare_row(name, ps, t, paper, f, stride, c, &pic, ct);
            r.table(ct);
            ct.rows.clear();
        }
    };
    if (!sil.pos.empty()) compare("silicium", si, sil, 1);
    if (!o.quick && fs::exists(head)) compare("head x1 (64x64x93)", head, point_set_from_volume(head.string()), 1);
    if (!o.quick && fs::exists(tooth)) compare("tooth (103x94x161)", tooth, point_set_from_volume(tooth.string()), 4);
    if (!o.quick && fs::exists(lidc)) compare("LIDC2 chest CT (256x256x133)", lidc, point_set_from_volume(lidc.string()), 8);
}

}  // namespace meshless::bench
