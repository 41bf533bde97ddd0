#include "cli/errors.hpp"

#include <algorithm>
#include <cstdio>
#include <new>

#include "kernels/errors.hpp"

namespace meshless::cli {

int exit_code(const std::exception& e) noexcept {
    if (dynamic_cast<const BrokenPipe*>(&e)) return kExitOk;
    if (dynamic_cast<const UsageError*>(&e) || dynamic_cast<const InvalidArgument*>(&e)) return kExitUsage;
    if (dynamic_cast<const FormatError*>(&e) || dynamic_cast<const IoError*>(&e) || dynamic_cast<const std::bad_alloc*>(&e))
        return kExitData;
    return kExitInternal;
}

std::string error_message(const std::exception& e) {
    if (dynamic_cast<const std::bad_alloc*>(&e)) return "out of memory";
    if (exit_code(e) == kExitInternal) return terminal_safe(std::string("internal error: ") + e.what());
    return terminal_safe(e.what());
}

}  // namespace meshless::cli
