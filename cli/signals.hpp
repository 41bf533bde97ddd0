// What the meshless executable does on SIGINT, SIGTERM, SIGHUP and SIGXFSZ: remove the temporary
// files this process is writing (formats/temporary_files.hpp, registered by AtomicFile and the
// brick converter's spool) and exit with status 128 + signal, as a shell reports a killed command;
// on SIGXFSZ first a one-line message naming the outputs abandoned (the shell, seeing an exit
// rather than a kill, would say nothing).
// A signal that is ignored when meshless starts (nohup, `trap "" XFSZ`) stays ignored: with
// SIGXFSZ ignored, a write over `ulimit -f` fails with EFBIG and the command reports it as an
// error (batch goes on with the next volume), still removing its temporaries.
// SIGBUS (an input read in place through a mapping shrank under it, formats/mapped_file.hpp): a one-line
// message on stderr, the temporaries removed, exit status 2 (a data error).
// Also installs the reporter that says on stderr which stale temporaries of dead processes were
// removed before an output is written. Call once, from main's thread, before anything is written.
#pragma once

namespace meshless::cli {

void install_signal_cleanup();

}  // namespace meshless::cli
