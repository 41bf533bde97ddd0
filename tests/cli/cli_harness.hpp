// Running the built `meshless` executable from tests: shell command lines (pipes included), exit
// codes, captured stderr, file contents.
#pragma once
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "kernels/analytic_volumes.hpp"
#include "test_paths.hpp"

namespace meshless::test {

inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

struct RunResult {
    int code = -1;
    std::string err;
    std::string out;
};

/// Runs `bash -o pipefail -c CMD` with stderr captured; "MESHLESS" in CMD is replaced by the binary.
inline RunResult sh(std::string cmd, const TempDir& dir) {
    for (std::size_t p; (p = cmd.find("MESHLESS")) != std::string::npos;) cmd.replace(p, 8, meshless_exe());
    const std::string errfile = (dir.path / "stderr.txt").string();
    const std::string outfile = (dir.path / "stdout.txt").string();
    const std::string full = "bash -o pipefail -c '" + cmd + "' </dev/null >" + outfile + " 2>" + errfile;
    const int status = std::system(full.c_str());
    RunResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    std::ifstream in(errfile);
    std::stringstream ss;
    ss << in.rdbuf();
    r.err = ss.str();
    r.out = slurp(outfile);
    return r;
}

/// `bytes` without the lines (newline-terminated, or the last one) that contain `needle`: outputs
/// compared across inputs of other names, less the lines that record the input's name.
/// Whether a program is on the PATH (`command -v NAME`): tests of terminals (script) and MPI (mpirun) skip without it.
inline bool have_command(const std::string& name, const TempDir& dir) { return sh("command -v " + name + " >/dev/null", dir).code == 0; }

/// The prefix that runs a command on `ranks` MPI ranks ("mpirun ... -np N "), or "" when mpirun is not
/// installed (the caller skips). Sanitizer tier: the ranks run without leak detection (ASan and UBSan
/// stay on): OpenMPI dlcloses its components at MPI_Finalize, so their exit-time allocations are
/// reported from "<unknown module>", which no suppression (tests/lsan_suppressions.txt) can name.
inline std::string mpirun_prefix(const TempDir& dir, int ranks = 2) {
    if (!have_command("mpirun", dir)) return "";
#ifdef MESHLESS_SANITIZED
    const std::string env = "LSAN_OPTIONS=detect_leaks=0 ";
#else
    const std::string env;
#endif
    return env + "mpirun --allow-run-as-root --oversubscribe -np " + std::to_string(ranks) + " ";
}

inline std::string lines_without(const std::string& bytes, const std::string& needle) {
    std::string out;
    for (std::size_t at = 0; at < bytes.size();) {
        const std::size_t nl = bytes.find('\n', at);
        const std::size_t end = nl == std::string::npos ? bytes.size() : nl + 1;
        if (bytes.substr(at, end - at).find(needle) == std::string::npos) out.append(bytes, at, end - at);
        at = end;
    }
    return out;
}

/// The tooth CT of ../shared/data (103 x 94 x 161 uint8): the volume the format tests write in other
/// formats and compare against.
inline const std::string kToothRaw = std::string(MESHLESS_SHARED_DATA) + "/tooth/tooth_103x94x161_uint8.raw";

/// A PLY's bytes less its comments and the lines naming the tooth: outputs of the same samples read
/// from files of other names and formats, compared.
inline std::string without_tooth_names(const std::string& bytes) { return lines_without(lines_without(bytes, "tooth"), "comment"); }

inline void spit(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream out(p, std::ios::binary);
    out << bytes;
}

/// An analytic field sampled on an n^3 grid, quantised to uint8 as round(value * scale + offset),
/// written as NAME_NxNxN_uint8.raw (the name convention) in dir; returns the path.
inline std::string write_uint8_analytic_volume(const TempDir& dir, const std::string& name, AnalyticField field,
                                               std::int64_t n, double scale, double offset) {
    const Volume v = make_analytic_volume(field, n);
    const float* f = reinterpret_cast<const float*>(v.bytes.data());
    std::string bytes(static_cast<std::size_t>(v.grid.voxel_count()), '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i)
        bytes[i] = static_cast<char>(static_cast<unsigned char>(std::clamp(std::lround(f[i] * scale + offset), 0L, 255L)));
    const std::string dims = std::to_string(n) + "x" + std::to_string(n) + "x" + std::to_string(n);
    const auto p = dir / (name + "_" + dims + "_uint8.raw");
    spit(p, bytes);
    return p.string();
}

}  // namespace meshless::test
