// Bytes from files and users shown on a terminal: what the tool prints (error messages, `info`
// reports, names quoted from headers) never carries a control sequence to the user's terminal.
// Pure string work; throws nothing but std::bad_alloc.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>

namespace meshless {

/// `s` made safe for a terminal and one line: control bytes (ESC, CR, LF, ...), DEL and UTF-8 C1
/// controls become \xNN; cut to `max` bytes with "...".
std::string terminal_safe(std::string_view s, std::size_t max = 4096);

}  // namespace meshless
