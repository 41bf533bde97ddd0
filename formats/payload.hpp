// Payload plans: where a volume's samples live (one file or a list of slab files, an offset, an
// encoding) and the reader that executes a plan with one large read per file.
//
// Units: bytes; `file_offset` is where the (possibly compressed) data starts in each file,
// `byte_skip` bytes are then discarded from the decoded stream (-1 for raw: the data is the last
// bytes of the file). Each of k files holds 1/k of the samples in order.
// Throws IoError (cannot open) and FormatError (size mismatch, truncation, bad ascii, corrupt
// compression), messages start with the file's path. Thread-safety: reentrant.
// Dissertation: none (input plumbing for chapter 3).
#pragma once
#include <string_view>
#include <utility>

#include "kernels/errors.hpp"
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "formats/anatomical_frame.hpp"
#include "formats/stored_type.hpp"
#include "formats/volume_reader.hpp"

namespace meshless {

enum class PayloadEncoding { raw, gzip, ascii };

struct PayloadPlan {
    std::string format;               ///< for VolumeInfo
    GridSpec grid;
    StoredType type = StoredType::u8;
    bool big_endian = false;
    PayloadEncoding encoding = PayloadEncoding::raw;
    std::vector<std::string> files;
    std::string header;               ///< the header naming `files` (its messages about them name it too)
    std::uint64_t file_offset = 0;    ///< where data starts in each file (before line skip)
    std::int64_t line_skip = 0;       ///< lines skipped after file_offset
    std::int64_t byte_skip = 0;       ///< bytes skipped after that; -1: data ends at end of file (raw only)
    bool exact_size = false;          ///< raw: each file must hold exactly offset+share bytes
    std::array<bool, 3> flip{false, false, false};  ///< axes whose file spacing was negative: samples reversed
                                                    ///< after reading (kernels/flip_axes.hpp; grid already positive)
    std::optional<AnatomicalFrame> frame;           ///< what the header says about the patient's axes (after flips)
    std::string length_unit;                        ///< the world coordinates' unit the header states (formats/length_unit.hpp), else ""
    std::string value_unit;                         ///< the values' unit the header states (value_unit_text), else ""
    std::vector<VolumeArray> arrays;                ///< multi-array formats: VolumeInfo::arrays
    std::size_t default_array = 0, read_array = 0;  ///< VolumeInfo::default_array, read_array
};

/// The index in `arrays` of the array called `name`, or `fallback` (the format's default) when
/// `name` is empty. FormatError "PATH: no point array named 'NAME'; its arrays: 'a' (float32),
/// 'b' (float64, 3 components)" (names escaped, formats/text_header.hpp escape_field) when none is.
std::size_t choose_volume_array(const std::vector<VolumeArray>& arrays, std::size_t fallback, const std::string& name,
                                const std::string& path);
/// For the readers of formats with one unnamed array: InvalidArgument "PATH: a FORMAT volume holds
/// one unnamed array: no array 'NAME' to choose" when `name` is not empty.
void refuse_array_choice(const std::string& name, const std::string& path, const std::string& format);

/// fn(), its IoError/FormatError about a data file prefixed with the detached header that names it
/// ("quarter.nhdr: data file ./quarter.1: ..."), unless the message already begins with the header.
template <class Fn>
decltype(auto) naming_header(const PayloadPlan& plan, Fn&& fn) {
    if (plan.header.empty()) return fn();
    return with_error_prefix(plan.header, plan.header + ": data file ", std::forward<Fn>(fn));
}

/// Executes the plan. map_raw: when the samples are one uncompressed file in host byte order and
/// a native type (uint8, int16, uint16, float32), the Volume maps the file instead of reading it
/// (formats/mapped_file.hpp: no copy; the file must not be truncated while the Volume lives).
Volume read_payload(const PayloadPlan& plan, bool map_raw = false);
VolumeInfo info_from_plan(const PayloadPlan& plan);
/// Proves a plan's sizes against its files before anything is allocated, and returns where each
/// file's data starts (after offset, line skip and byte skip): the grid is valid (validate_grid),
/// sizes are checked (kernels/checked_size.hpp), raw files hold exactly/at least their share,
/// gzip files hold enough compressed bytes for their share (deflate expands at most
/// kMaxDeflateRatio:1), ascii files enough bytes for their values. FormatError naming the file.
std::vector<std::uint64_t> check_payload_plan(const PayloadPlan& plan);
/// What `meshless info` runs: check_payload_plan, then proves the payload can be decoded without
/// keeping it: gzip streams are inflated through a 64 KiB buffer and must deliver byte skip +
/// their share (truncated or corrupt streams are refused), ascii values are parsed (their count
/// was bounded by the file above); raw payloads need no more than their sizes. Memory: O(1) for
/// raw and gzip, the text's size for ascii. FormatError/IoError naming the file, as read_payload.
void prove_payload(const PayloadPlan& plan);
/// True when read_payload(plan, map_raw = true) maps the file instead of decoding it into memory.
bool payload_maps(const PayloadPlan& plan);
const char* to_string(PayloadEncoding e);

/// Parses whitespace-separated numbers into `count` samples of type t in host order.
std::vector<std::byte> parse_ascii_samples(std::string_view text, StoredType t, std::size_t count,
                                           const std::string& path);

}  // namespace meshless
