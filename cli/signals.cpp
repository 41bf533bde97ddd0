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

// SIGBUS: an input read in place (formats/mapped_file.hpp, map_volume) shrank while it was read.
// Async-signal-safe: write(2), unlink(2), _exit(2); a data error (exit 2), as a short read is.
void on_bus_error(int) {
    static const char msg[] = "meshless: an input file shrank or became unreadable while it was read (SIGBUS); nothing was written\n";
    (void)!::write(2, msg, sizeof msg - 1);
    remove_live_temporaries();
    ::_exit(2);
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
    struct sigaction bus {};
    bus.sa_handler = &on_bus_error;
    sigfillset(&bus.sa_mask);
    ::sigaction(SIGBUS, &bus, nullptr);
}

}  // namespace meshless::cli
