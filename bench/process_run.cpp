// Running the measured processes of the benchmarks: run_sh (a command line's exit status, wall time,
// stderr and its own peak RSS) and the rusage wrapper behind it (bench/bench_common.hpp).
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "bench/bench_common.hpp"

namespace meshless::bench {

namespace fs = std::filesystem;

namespace {

std::string first_line(const std::string& s) {
    std::string t = s;
    while (!t.empty() && (t.back() == '\n' || t.back() == '\r')) t.pop_back();
    const auto nl = t.find('\n');
    return nl == std::string::npos ? t : t.substr(0, nl);
}

/// This executable (the rusage wrapper below is this program re-executed), empty when unknown.
const std::string& self_exe() {
    static const std::string path = [] {
        std::error_code ec;
        const fs::path p = fs::read_symlink("/proc/self/exe", ec);
        return ec ? std::string() : p.string();
    }();
    return path;
}

}  // namespace

std::string Run::why(const std::string& work) const {
    std::string e = first_line(err);
    if (e.rfind("meshless ", 0) == 0)
        if (const auto colon = e.find(": "); colon != std::string::npos && colon < 40) e = e.substr(colon + 2);
    if (const auto see = e.find(" (see meshless"); see != std::string::npos) e = e.substr(0, see);
    if (!work.empty())
        for (std::size_t p; (p = e.find(work + "/")) != std::string::npos;) e.replace(p, work.size() + 1, "WORK/");
    if (e.size() > 64) e = e.substr(0, 61) + "...";
    return (code >= 128 ? fmt("signal %d", code - 128) : fmt("exit %d", code)) + (e.empty() ? "" : ": " + e);
}

/// Runs `/bin/sh -c cmd` with stdin on /dev/null, stdout into out_file (or /dev/null), stderr into
/// err_file; wall time from before fork() to after wait4(). Peak RSS: a process forked from this one
/// starts with this process's resident set as its high-water mark (Linux copies it at fork and keeps
/// it across exec), so the shell runs under a freshly executed copy of this program
/// (run_rusage_wrapper, a few MiB) that forks it, waits and reports the shell's ru_maxrss (which
/// includes the shell's children). Without /proc/self/exe: wait4's own figure, an upper bound.
Run run_sh(const std::string& cmd, const fs::path& err_file, const fs::path& out_file, double limit_s) {
    Run r;
    const std::string rss_file = err_file.string() + ".rss";
    std::error_code ec;
    fs::remove(rss_file, ec);
    const std::string& self = self_exe();
    const auto t0 = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid < 0) {
        r.err = std::string("fork failed: ") + std::strerror(errno);
        return r;
    }
    if (pid == 0) {
        if (limit_s > 0) ::setpgid(0, 0);  // a group of its own, killed whole at the limit
        const int in = ::open("/dev/null", O_RDONLY);
        const int out = ::open(out_file.empty() ? "/dev/null" : out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        const int err = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (in < 0 || out < 0 || err < 0) ::_exit(126);
        ::dup2(in, 0);
        ::dup2(out, 1);
        ::dup2(err, 2);
        if (!self.empty())
            ::execl(self.c_str(), self.c_str(), kRusageWrapperFlag, rss_file.c_str(), "/bin/sh", "-c", cmd.c_str(),
                    static_cast<char*>(nullptr));
        ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    int st = 0;
    struct rusage ru {};
    if (limit_s > 0) {
        ::setpgid(pid, pid);
        for (;;) {
            const pid_t w = ::wait4(pid, &st, WNOHANG, &ru);
            if (w == pid) break;
            if (w < 0 && errno != EINTR) break;
            const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (!r.timed_out && t > limit_s) {
                r.timed_out = true;
                ::kill(-pid, SIGKILL);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(t < 1 ? 2 : 20));
        }
    } else {
        while (::wait4(pid, &st, 0, &ru) < 0 && errno == EINTR) {
        }
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.code = WIFEXITED(st) ? WEXITSTATUS(st) : WIFSIGNALED(st) ? 128 + WTERMSIG(st) : -1;
    r.maxrss_kib = ru.ru_maxrss;
    if (std::ifstream f(rss_file); f) {
        long kib = 0;
        if (f >> kib) r.maxrss_kib = kib;
    }
    fs::remove(rss_file, ec);
    r.err = read_file_bytes(err_file);
    if (!out_file.empty()) r.out = read_file_bytes(out_file);
    return r;
}

int run_rusage_wrapper(int argc, char** argv) {
    if (argc < 4) return 126;
    std::signal(SIGPIPE, SIG_DFL);  // the bench ignores SIGPIPE; the commands measured get the default
    const pid_t pid = ::fork();
    if (pid < 0) return 126;
    if (pid == 0) {
        ::execv(argv[3], argv + 3);
        ::_exit(127);
    }
    int st = 0;
    struct rusage ru {};
    while (::wait4(pid, &st, 0, &ru) < 0 && errno == EINTR) {
    }
    if (std::FILE* f = std::fopen(argv[2], "w")) {
        std::fprintf(f, "%ld\n", ru.ru_maxrss);
        std::fclose(f);
    }
    return WIFEXITED(st) ? WEXITSTATUS(st) : WIFSIGNALED(st) ? 128 + WTERMSIG(st) : 126;
}

}  // namespace meshless::bench
