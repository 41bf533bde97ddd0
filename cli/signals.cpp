#include "cli/signals.hpp"

#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "formats/ply.hpp"
#include "formats/temporary_files.hpp"

namespace meshless::cli {

namespace {

// Async-signal-safe: unlink(2) on the preallocated table, then _exit(2).
void on_fatal_signal(int sig) {
    remove_live_temporaries();
    ::_exit(128 + sig);
}

void report_stale(const char* path, long pid) {
    std::fprintf(stderr, "meshless: removed stale temporary file %s (process %ld no longer exists)\n",
                 ply_escape(path, 512).c_str(), pid);
}

}  // namespace

void install_signal_cleanup() {
    set_stale_temporary_reporter(&report_stale);
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGXFSZ}) {
        struct sigaction old {};
        if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;  // nohup, trap ""
        struct sigaction sa {};
        sa.sa_handler = &on_fatal_signal;
        sigfillset(&sa.sa_mask);  // no other of ours interrupts the clean-up
        sa.sa_flags = 0;
        ::sigaction(sig, &sa, nullptr);
    }
}

}  // namespace meshless::cli
