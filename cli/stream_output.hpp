// The binary stream output of the stage commands (generate, project, extract and their multiblock
// and scattered forms): stdout when "-" (refused when stdout is a terminal), a FIFO or device
// written through, else a file written to a temporary name and renamed on commit()
// (formats/atomic_file.hpp). A file name with another format's extension (out.ply, out.csv,
// out.png, ...) is refused: the stream would not open in the programs that name promises
// (`meshless write -o out.ply` turns a point stream into PLY); point streams are conventionally
// named .mlp (as `batch` writes them).
// Throws UsageError (the name, a terminal) and what AtomicFile throws.
#pragma once
#include <cstdio>
#include <memory>
#include <string>

#include "formats/atomic_file.hpp"

namespace meshless::cli {

/// UsageError when `path` (a stream output of `what`, e.g. "a sample stream") has the extension of
/// a format the stream is not; "-", FIFOs and devices pass.
void check_stream_output_name(const std::string& path, const char* what);

struct BinaryStreamOutput {
    std::unique_ptr<AtomicFile> file;
    std::FILE* f = nullptr;
    std::string name;
    /// what: the stream's kind for the messages ("a sample stream", "a point stream", "a seed stream").
    BinaryStreamOutput(const std::string& path, const char* what);
    void commit() { file->commit(); }
};

}  // namespace meshless::cli
