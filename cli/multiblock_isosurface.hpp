// The multiblock/AMR isosurface (dissertation chapter 4, sections 4.3-4.6) on the command line:
//   meshless isosurface BLOCKS... --iso V -o out.ply [--png out.png] [--field KIND] [--samples N] ...
//   meshless generate BLOCKS... --iso V [--samples N]            (a seed stream)
//   meshless project --field KIND DATA... [< seeds]              (seed stream -> points with blocks)
// as one graph: block cells -> marching-cubes seeds on the barycentric lattice -> Newton onto one
// continuous meshless field built from every block's valid nodes -> PLY (with a `block` property)
// and/or PNG. The piped stages give the same bytes as the in-process command for any --threads
// (same batches, same field from the same data).
// cmd_isosurface / cmd_generate / cmd_project hand their arguments here when blocks_invocation() /
// project_seeds_invocation() say so. Throws UsageError for bad options, what the readers and
// stages throw otherwise (cli/app.cpp maps them to exit codes).
#pragma once
#include <cstdio>
#include <initializer_list>
#include <memory>
#include <string>

#include "cli/args.hpp"
#include "formats/atomic_file.hpp"
#include "formats/point_stream.hpp"
#include "kernels/field_newton_projection.hpp"
#include "stream/field_project_stage.hpp"

namespace meshless::cli {

/// The default lattice parameter n of --samples (n(n+1)/2 seeds per triangle), chosen by measurement
/// (combustor combxyz.bin + combq.bin density and multicomb_0..2.vts, iso 0.4, mpu field,
/// one thread; reference = the same surface at n = 8; tolerance = 0.01 x the mean cell diagonal,
/// 0.0058 and 0.0166):
///   n  points (comb / multicomb)  Newton s/core (comb)  splat-plane deviation p99 / tolerance
///   1   10,720 /  1,132           0.085                 3.1 / 4.9
///   2   32,156 /  3,396           0.116                 1.3 / 1.9
///   3   64,313 /  6,792           0.219                 0.93 / 1.1
///   4  107,189 / 11,320           0.349                 0.78 / 0.84
/// Every n covers >= 99.9% of the reference within one splat radius (the radius grows as n
/// shrinks), so coverage does not decide; flatness does: n = 3 is the smallest n whose discs stay
/// within about the Newton tolerance of the surface they stand for (99th percentile), for ~0.1 s
/// more than n = 2 on the combustor (~10% of the whole process, the field build dominating); n = 4
/// costs 67% more points for 15-25% less deviation.
inline constexpr int kDefaultLatticeN = 3;

// Shared with the scattered-data isosurface (cli/scattered_isosurface.hpp), which seeds and
// projects the same way:
/// --samples N (the barycentric lattice parameter, default kDefaultLatticeN) and its value.
void add_samples_option(Args& a, int default_n = kDefaultLatticeN);
int lattice_n(const Args& a, int default_n = kDefaultLatticeN);
/// --tolerance --max-iterations --max-travel (Newton onto the field, relative to each seed's cell).
/// --max-travel's default: a seed moves at most this many cell diagonals (section 4.4).
inline constexpr double kDefaultMaxTravel = 2;
void add_newton_options(Args& a);
/// A seed stream whose frame (bounds_lo/hi) was widened for Newton moving its seeds up to
/// frame_travel cell diagonals of frame_cell_diagonal (scattered seeds, cli/scattered_isosurface):
/// widened further for a larger max_travel, so that the projected points stay inside it. An
/// unlimited travel (infinity) leaves it: its points may lie beyond.
void widen_frame_for_travel(StreamMeta& m, double max_travel);
FieldProjectParams newton_params(const Args& a);
/// The --stats line of the Newton projection.
void print_newton_stats(const char* cmd, const std::string& field, const FieldProjectParams& p, const FieldNewtonStats& s,
                        double busy_seconds);

/// The positional arguments of argv[first..argc) under the option declarations of `parsers`
/// (an option that takes a value in any of them consumes the next argument).
std::vector<std::string> scan_positionals(int argc, char** argv, int first, std::initializer_list<const Args*> parsers);

/// True when the positionals name blocks: one that looks like a multiblock file
/// (formats/multiblock_reader.hpp looks_like_multiblock), or several inputs the first of which is
/// not a volume (formats/volume_reader.hpp looks_like_volume).
bool blocks_invocation(const std::vector<std::string>& positionals);

int isosurface_blocks(int argc, char** argv);
int generate_blocks(int argc, char** argv);
/// `meshless project` given --field: a seed stream projected onto the field of DATA...
int project_seeds(int argc, char** argv);
/// True when argv (from index 2) has a --field option (project then reads seeds).
bool project_seeds_invocation(int argc, char** argv);

}  // namespace meshless::cli
