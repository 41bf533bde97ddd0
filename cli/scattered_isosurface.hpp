// The isosurface straight from scattered data (dissertation chapter 5, sections 5.3-5.6) on the
// command line:
//   meshless isosurface POINTS --iso V -o out.ply|out.vtp [--png out.png] [--field KIND|F.mlf] ...
//   meshless generate POINTS --iso V [--samples N]            (a seed stream)
//   meshless project --field F.mlf|KIND [POINTS] [< seeds]    (seed stream -> points; the multiblock
//                                                              command, cli/multiblock_isosurface.hpp)
// option parsing over the recipes of stream/scattered_isosurface.hpp and stream/scattered_isosurface_job.hpp (the binning grid -> marching
// stencils, each regularised on the fly, tetrahedralised by CGAL and contoured by marching
// tetrahedra, seeded on the barycentric lattice -> Newton onto the meshless field) -> PLY/VTP
// and/or PNG; under mpirun the stencil rows are dealt to the ranks (stream/scattered_isosurface_mpi.hpp; the
// job's abort stays here, cli/errors.hpp end_mpi_job). The pipe gives the same
// bytes as the in-process command for any --threads. POINTS: any point set meshless reads (CSV/TSV,
// PLY, VTP, raw float32 records, .npy; formats/point_set_reader.hpp).
// Throws UsageError for bad options, FormatError for unusable data (fewer than 4 distinct points),
// what the readers and stages throw otherwise (cli/app.cpp maps them to exit codes).
#pragma once
#include <string>
#include <vector>

namespace meshless::cli {

/// True when the positionals name one scattered point set (not blocks, not a volume; a .raw given
/// with --dims in argv is a volume).
bool scattered_invocation(const std::vector<std::string>& positionals, int argc, char** argv);

int isosurface_scattered(int argc, char** argv);
int generate_scattered(int argc, char** argv);

}  // namespace meshless::cli
