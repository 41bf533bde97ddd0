#include "kernels/checked_size.hpp"

namespace meshless {

void throw_size_error(std::string_view context, const std::string& what) {
    throw FormatError(std::string(context) + ": " + what);
}

}  // namespace meshless
