#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>

#include "cli/commands.hpp"
#include "cli/errors.hpp"
#include "cli/signals.hpp"
#include "formats/atomic_file.hpp"
#include "stream/mpi_session.hpp"

namespace meshless::cli {

namespace {

struct Command {
    const char* name;
    int (*run)(int, char**);
    const char* summary;
};

constexpr Command kCommands[] = {
    {"demo", cmd_demo, "extract and render an embedded analytic volume (no input needed)"},
    {"isosurface", cmd_isosurface, "volume -> projected oriented point set (PLY) and picture (PNG)"},
    {"generate", cmd_generate, "volume -> one sample per active cell, as a binary stream"},
    {"project", cmd_project, "sample stream -> points projected onto the isosurface"},
    {"write", cmd_write, "point stream -> PLY or VTP (by extension)"},
    {"extract", cmd_extract, "sample store (.mls, paradigm A) -> samples of the active cells of one isovalue"},
    {"splat", cmd_splat, "point stream or PLY -> surface-splatted PNG (quad or EWA kernels)"},
    {"render", cmd_render, "volume, brick store or scattered points -> direct volume rendering by ray casting (PNG)"},
    {"mc", cmd_mc, "volume -> marching-cubes triangle mesh (PLY), the baseline"},
    {"convert", cmd_convert, "volume -> Morton-ordered zstd brick store (.mlb) for out-of-core work"},
    {"verify", cmd_verify, "check every brick of a brick store; names the first bad one"},
    {"synth", cmd_synth, "upsample a real volume into a big brick store (test volumes of any size)"},
    {"split", cmd_split, "volume -> multiblock (.vtm) or AMR (.vthb) pieces: the layouts of chapter 4's test sets"},
    {"sample", cmd_sample, "volume -> scattered points (uniform random positions, trilinear values; .ply/.csv)"},
    {"fit", cmd_fit, "scattered points or multiblock grids -> a fitted meshless field saved once (.mlf)"},
    {"probe", cmd_probe, "scattered points -> value and gradient of a meshless field at positions (CSV)"},
    {"slice", cmd_slice, "scattered points -> colour-mapped slice of a meshless field (PNG)"},
    {"resample", cmd_resample, "scattered points -> a meshless field on a regular grid (NRRD)"},
    {"hierarchy", cmd_hierarchy, "volume or scattered data -> cluster binary tree (.mlh, chapter 6 multiresolution)"},
    {"lod", cmd_lod, "cluster tree (.mlh) -> a level of detail as scattered points (.ply/.csv/.vtp)"},
    {"info", cmd_info, "describe any file meshless reads or writes"},
    {"batch", cmd_batch, "nightly job: archive of volumes -> brick stores + point sets, skipping what is up to date"},
};

void print_usage(std::FILE* out) {
    std::fputs("usage: meshless COMMAND [options]   (meshless COMMAND --help for details)\n\n"
               "Point-based isosurfaces and pictures from volume data, without meshing\n"
               "(C. S. Co, Meshless Methods for Volume Visualization, 2006).\n\ncommands:\n", out);
    for (const auto& c : kCommands) std::fprintf(out, "  %-12s %s\n", c.name, c.summary);
    std::fputs("\nPipes: meshless generate VOL --iso V | meshless project | meshless splat -o img.png\n"
               "exit codes: 0 success, 1 usage error, 2 bad input data or I/O failure, 3 internal error,\n"
               "4 empty result with --fail-empty or an unreached lod --max-error, 128 + signal when interrupted.\n",
               out);
}

int run_command(int argc, char** argv);

/// True when standard output is a pipe or socket whose reading end has been closed.
bool stdout_reader_gone() {
    struct stat st {};
    if (::fstat(STDOUT_FILENO, &st) != 0 || !(S_ISFIFO(st.st_mode) || S_ISSOCK(st.st_mode))) return false;
    pollfd p{STDOUT_FILENO, POLLOUT, 0};
    return ::poll(&p, 1, 0) == 1 && (p.revents & (POLLERR | POLLHUP)) != 0;
}

/// Flushes and closes standard output; a write error that nothing reported yet (a full device,
/// an I/O error) turns a successful exit into exit code 2 with a message. A reader that has gone
/// (EPIPE) stays the quiet exit it is for every other write.
int finish_stdout(int code, const char* name) {
    const bool failed = std::ferror(stdout) != 0;
    errno = 0;
    const bool flush_failed = std::fflush(stdout) != 0;
    int err = flush_failed ? errno : 0;
    // the error flag may stem from an earlier EPIPE whose bytes were dropped: ask the pipe itself
    const bool reader_gone = stdout_reader_gone();
    errno = 0;
    const bool close_failed = std::fclose(stdout) != 0;
    if (close_failed && err == 0) err = errno;
    if (!(failed || flush_failed || close_failed) || code != kExitOk || err == EPIPE || reader_gone) return code;
    std::fprintf(stderr, "meshless%s%s: cannot write standard output (%s)\n", name ? " " : "", name ? name : "",
                 err ? std::strerror(err) : "write error");
    return kExitData;
}

/// Standard input and output that are not terminals get stdio buffers of the size AtomicFile gives
/// the files it opens, 1 MiB (stdio's own is st_blksize, 4 KiB on a pipe): a stage of
/// `generate | project | write` moved its records in ~1,500 read and ~1,500 write calls, mostly of
/// 4 KiB, per 100 MB. Called before any I/O on them; the buffers have static storage, as stdout is
/// flushed after main returns.
void buffer_standard_streams() {
    static char in_buffer[AtomicFile::kBufferBytes], out_buffer[AtomicFile::kBufferBytes];
    if (::isatty(0) != 1) std::setvbuf(stdin, in_buffer, _IOFBF, sizeof in_buffer);
    if (::isatty(1) != 1) std::setvbuf(stdout, out_buffer, _IOFBF, sizeof out_buffer);
}

}  // namespace

int cli_main(int argc, char** argv) {
    buffer_standard_streams();
    // A closed downstream pipe surfaces as EPIPE from write(), mapped to a quiet exit.
    std::signal(SIGPIPE, SIG_IGN);
    // SIGINT, SIGTERM, SIGHUP, SIGXFSZ: remove this process's temporaries, exit 128 + signal.
    install_signal_cleanup();
    const char* name = argc >= 2 && argv[1][0] != '-' ? argv[1] : nullptr;
    return finish_stdout(run_command(argc, argv), name);
}

namespace {

/// Whether the command line asks for a command's help (--help or -h anywhere after the command).
bool asks_for_help(int argc, char** argv) {
    for (int i = 2; i < argc; ++i)
        if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) return true;
    return false;
}

int run_command(int argc, char** argv) {
    if (argc < 2) {
        print_usage(stderr);
        return 1;
    }
    const std::string name = argv[1];
    if (name == "--help" || name == "-h" || name == "help") {
        print_usage(stdout);
        return 0;
    }
    if (name == "--version") {
        std::puts("meshless " MESHLESS_VERSION);
        return 0;
    }
    for (const auto& c : kCommands) {
        if (name != c.name) continue;
        // Under mpirun only isosurface and batch share their work out; any other command would repeat
        // the whole job on every rank (and race for its outputs): refused, said once, by rank 0.
        if (launched_world_size() > 1 && name != "isosurface" && name != "batch" && !asks_for_help(argc, argv)) {
            if (launched_world_rank() == 0)
                std::fprintf(stderr, "meshless %s: runs in one process, not under mpirun (this launch has %d ranks; "
                             "isosurface and batch are the commands that share their work across ranks): run it without mpirun\n",
                             c.name, launched_world_size());
            return kExitUsage;
        }
        try {
            return c.run(argc, argv);
        } catch (const std::exception& e) {
            const int code = exit_code(e);
            // (under mpirun a usage error is every rank's alike: rank 0 says it)
            const bool quiet_rank = code == kExitUsage && launched_world_size() > 1 && launched_world_rank() != 0;
            if (code != kExitOk && !quiet_rank) std::fprintf(stderr, "meshless %s: %s\n", c.name, error_message(e).c_str());
            return code;
        }
    }
    std::fprintf(stderr, "meshless: unknown command '%s' (see meshless --help)\n", terminal_safe(name, 200).c_str());
    return 1;
}

}  // namespace

}  // namespace meshless::cli
