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

// Temporaries seen by the handler (it runs once: it exits).
std::size_t& live_outputs() {
    static std::size_t n = 0;
    return n;
}

// Writes to stderr the output a temporary "<out>.tmp-<pid>[.spool]" stands for, quoted, control
// bytes as \xNN, once per output (a store and its spool name the same one). Async-signal-safe: a
// static buffer for the last name (the handler runs once: it exits), write(2).
void write_output_of(const char* tmp) {
    static char last[kMaxTemporaryPath];
    static std::size_t last_n = static_cast<std::size_t>(-1);
    std::size_t n = 0, cut = 0;
    for (; tmp[n] != '\0'; ++n)
        if (tmp[n] == '.' && tmp[n + 1] == 't' && tmp[n + 2] == 'm' && tmp[n + 3] == 'p' && tmp[n + 4] == '-') cut = n;
    if (cut == 0) cut = n;
    if (cut == last_n) {
        std::size_t i = 0;
        while (i < cut && last[i] == tmp[i]) ++i;
        if (i == cut) return;
    }
    for (std::size_t i = 0; i < cut && i < sizeof last; ++i) last[i] = tmp[i];
    last_n = cut < sizeof last ? cut : static_cast<std::size_t>(-1);
    char buf[512];
    std::size_t k = 0;
    const auto put = [&](char c) {
        if (k == sizeof buf) {
            (void)!::write(2, buf, k);
            k = 0;
        }
        buf[k++] = c;
    };
    static const char hex[] = "0123456789abcdef";
    put(' ');
    put('\'');
    for (std::size_t i = 0; i < cut; ++i) {
        const auto c = static_cast<unsigned char>(tmp[i]);
        if (c < 0x20 || c == 0x7f || c == '\'' || c == '\\') {
            put('\\');
            put('x');
            put(hex[c >> 4]);
            put(hex[c & 15]);
        } else {
            put(static_cast<char>(c));
        }
    }
    put('\'');
    (void)!::write(2, buf, k);
}

// SIGXFSZ (a write past `ulimit -f`): the process exits by itself, so no shell says why; a
// one-line message naming the abandoned outputs, the temporaries removed, exit 128 + SIGXFSZ.
// Async-signal-safe: write(2), unlink(2), _exit(2).
void count_temporary(const char*) { ++live_outputs(); }

void on_file_size_limit(int sig) {
    static const char head[] = "meshless: file size limit exceeded (SIGXFSZ, ulimit -f)";
    static const char named[] = " while writing";
    static const char tail[] = "; not written, temporaries removed\n";
    static const char bare[] = "; an output written without a temporary (standard output) is cut short\n";
    (void)!::write(2, head, sizeof head - 1);
    for_each_live_temporary(&count_temporary);
    if (live_outputs() > 0) {
        (void)!::write(2, named, sizeof named - 1);
        for_each_live_temporary(&write_output_of);
        (void)!::write(2, tail, sizeof tail - 1);
    } else {
        (void)!::write(2, bare, sizeof bare - 1);
    }
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
        sa.sa_handler = sig == SIGXFSZ ? &on_file_size_limit : &on_fatal_signal;
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
