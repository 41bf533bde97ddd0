#include "formats/output_folder.hpp"

#include <filesystem>

#include "kernels/errors.hpp"

namespace meshless {

void make_output_folder(const std::string& dir) {
    std::error_code made, ec;
    std::filesystem::create_directories(dir, made);
    if (std::filesystem::is_directory(dir, ec)) return;
    throw IoError(dir + ": cannot create output folder: " +
                  (std::filesystem::exists(dir, ec) ? std::string("a file of that name exists")
                                                    : made ? made.message() : std::string("unknown reason")));
}

}  // namespace meshless
