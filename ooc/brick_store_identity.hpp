// The identity of a brick store file as a sample store records it (ooc/sample_store_format.hpp):
// its size and the CRCs stored in its header and footer. The footer's index CRC covers every
// brick's CRC, so any change of the .mlb's content or layout changes the identity.
// Reads 256 + 32 bytes; IoError when the file cannot be opened/read, FormatError (naming it) when
// it is not a brick store. Thread-safe.
#pragma once
#include <string>

#include "ooc/sample_store_format.hpp"

namespace meshless {

BrickStoreIdentity brick_store_identity(const std::string& mlb_path);

}  // namespace meshless
