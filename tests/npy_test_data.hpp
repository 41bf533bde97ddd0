// .npy files written byte by byte in tests (the layout np.save writes, format version 1.0), so the
// NumPy readers' tests need no NumPy.
#pragma once
#include <string>

namespace meshless::test {

/// The magic, version 1.0, the header length and `dict` (a Python dict literal such as
/// "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 4, 5), }") padded with spaces and a
/// newline to a multiple of 64 bytes, as np.save aligns it; the array's bytes follow.
inline std::string npy_prefix(const std::string& dict) {
    std::string h = dict;
    while ((10 + h.size() + 1) % 64) h += ' ';
    h += '\n';
    std::string out("\x93NUMPY\x01\x00", 8);
    out += static_cast<char>(h.size() & 0xff);
    out += static_cast<char>(h.size() >> 8);
    return out + h;
}

}  // namespace meshless::test
