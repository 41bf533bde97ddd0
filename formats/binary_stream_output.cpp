#include "formats/binary_stream_output.hpp"

#include "formats/output_names.hpp"

namespace meshless {

BinaryStreamOutput::BinaryStreamOutput(const std::string& path, const char* what) : name(path) {
    check_stream_output_name(path, what);
    refuse_binary_to_terminal(path, "a binary stream");
    file = std::make_unique<AtomicFile>(path);
    f = file->handle();
}

}  // namespace meshless
