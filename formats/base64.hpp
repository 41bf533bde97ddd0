// Base64 decoding (RFC 4648 alphabet) for VTK XML inline/appended binary data.
//
// Whitespace is skipped. Padding '=' may also occur inside the text: each 4-character group is
// decoded on its own, so separately padded encodings laid end to end (VTK writes the block
// header and the compressed blocks as two encodings) decode to their concatenation.
// Decoding stops at the first character that is neither base64 nor whitespace when
// `stop_at_other` is true; otherwise such a character is a FormatError naming `path`.
// Thread-safety: pure. Dissertation: input plumbing.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace meshless {

std::vector<std::byte> base64_decode(std::string_view text, const std::string& path, bool stop_at_other = false);
/// Encoder (for tests and writers).
std::string base64_encode(const void* data, std::size_t n);

}  // namespace meshless
