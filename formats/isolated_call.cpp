#include "formats/isolated_call.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>

#include "kernels/errors.hpp"

namespace meshless {

namespace {

constexpr std::size_t kMessageBytes = 1024;

/// The anonymous shared mapping, unmapped on every path out.
struct SharedMapping {
    void* p = MAP_FAILED;
    std::size_t n = 0;
    ~SharedMapping() {
        if (p != MAP_FAILED) ::munmap(p, n);
    }
};

struct Pipe {
    int fd[2] = {-1, -1};
    void close_end(int i) {
        if (fd[i] >= 0) ::close(fd[i]);
        fd[i] = -1;
    }
    ~Pipe() {
        close_end(0);
        close_end(1);
    }
};

[[noreturn]] void run_child(const std::function<void(std::byte*)>& work, std::byte* buffer, char* message, pid_t parent) {
    // the parent's handlers remove its temporaries and _exit, a sanitizer's report a fault and exit 1:
    // the child takes the defaults, so that a fault ends it by its signal
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGXFSZ, SIGBUS, SIGPIPE, SIGSEGV, SIGFPE, SIGILL, SIGABRT}) ::signal(sig, SIG_DFL);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(4);  // the parent died before the line above: nobody waits for this
    int rc = 0;
    try {
        work(buffer);
    } catch (const std::exception& e) {
        std::snprintf(message, kMessageBytes, "%s", e.what());
        rc = 2;
    } catch (...) {
        rc = 3;
    }
    ::_exit(rc);  // no atexit handlers, no stdio flush: the parent's buffers are the parent's
}

}  // namespace

IsolatedResult run_isolated(std::size_t bytes, std::byte* out, const std::function<void(std::byte*)>& work, int timeout_seconds) {
    SharedMapping m;
    m.n = bytes + kMessageBytes;
    m.p = ::mmap(nullptr, m.n, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (m.p == MAP_FAILED) throw IoError(std::string("cannot map memory for an isolated decoder: ") + std::strerror(errno));
    auto* buffer = static_cast<std::byte*>(m.p);
    char* message = reinterpret_cast<char*>(buffer + bytes);
    message[0] = '\0';
    Pipe alive;  // the child holds the write end: its exit (or death) closes it
    if (::pipe2(alive.fd, O_CLOEXEC) != 0) throw IoError(std::string("cannot make a pipe for an isolated decoder: ") + std::strerror(errno));
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) throw IoError(std::string("cannot start an isolated decoder process: ") + std::strerror(errno));
    if (pid == 0) {
        alive.close_end(0);
        run_child(work, buffer, message, parent);
    }
    alive.close_end(1);
    IsolatedResult r;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_seconds);
    for (;;) {  // until the pipe closes (the child ended) or the deadline
        int wait_ms = -1;
        if (timeout_seconds > 0) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
            if (left <= 0) {
                ::kill(pid, SIGKILL);
                r.outcome = IsolatedResult::Outcome::timed_out;
                break;
            }
            wait_ms = static_cast<int>(std::min<long long>(left, 1 << 30));
        }
        pollfd p{alive.fd[0], POLLIN, 0};
        const int n = ::poll(&p, 1, wait_ms);
        if (n < 0 && errno == EINTR) continue;
        if (n != 0) break;  // closed (POLLHUP), or a poll error: waitpid says what became of the child
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0)
        if (errno != EINTR) throw IoError(std::string("cannot wait for an isolated decoder: ") + std::strerror(errno));
    if (r.outcome == IsolatedResult::Outcome::timed_out) return r;
    if (WIFSIGNALED(status)) {
        r.outcome = IsolatedResult::Outcome::crashed;
        r.signal = WTERMSIG(status);
    } else if (WEXITSTATUS(status) != 0) {
        r.outcome = IsolatedResult::Outcome::error;
        message[kMessageBytes - 1] = '\0';
        r.message = message;
        if (r.message.empty()) r.message = "the decoder failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")";
    } else {
        std::memcpy(out, buffer, bytes);
    }
    return r;
}

}  // namespace meshless
