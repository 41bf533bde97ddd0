// The binary stream output of the stage commands (generate, project, extract and their multiblock
// and scattered forms; formats/point_stream.hpp): stdout when "-" (refused when stdout is a
// terminal), a FIFO or device written through, else a file written to a temporary name and renamed
// on commit() (formats/atomic_file.hpp). A file name with another format's extension is refused
// (formats/output_names.hpp check_stream_output_name).
// Throws InvalidArgument (the name, a terminal) and what AtomicFile throws.
#pragma once
#include <cstdio>
#include <memory>
#include <string>

#include "formats/atomic_file.hpp"
#include "formats/output_names.hpp"

namespace meshless {

struct BinaryStreamOutput {
    std::unique_ptr<AtomicFile> file;
    std::FILE* f = nullptr;
    std::string name;
    /// what: the stream's kind for the messages ("a sample stream", "a point stream", "a seed stream").
    BinaryStreamOutput(const std::string& path, const char* what) : name(path) {
        check_stream_output_name(path, what);
        refuse_binary_to_terminal(path, "a binary stream");
        file = std::make_unique<AtomicFile>(path);
        f = file->handle();
    }
    void commit() { file->commit(); }
};

}  // namespace meshless
