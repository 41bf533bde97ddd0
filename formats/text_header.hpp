// Small text helpers for key/value headers (NRRD "key: value", MetaImage "Key = Value", Voreen .dat).
//
// Thread-safety: pure functions. Numeric parsers throw FormatError("PATH: bad FIELD 'TEXT': ...")
// so messages name the file and the field. Dissertation: none (input plumbing).
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace meshless {

std::string trim(std::string_view s);
/// Bytes taken from a file, made safe to quote in a message: printable ASCII kept, everything else
/// (control bytes, ESC, DEL, non-ASCII, backslash) written as \xNN, cut to `max` bytes with "...".
std::string escape_field(std::string_view s, std::size_t max = 64);
/// `s` as one line of a header: a line feed (a file name's) becomes \x0a, every other byte stays as
/// it is, a carriage return included (the PLY and metadata readers keep one inside a line, so a
/// parsed header formats back to the same text; fuzz_ply checks it) (stream metadata, PLY comments).
std::string line_breaks_escaped(std::string_view s);
std::string to_lower(std::string_view s);
/// A number for a message: the shortest text that reads back as v ("0.1", "1e-09", "1e+300",
/// "nan", "-inf"), never a 300-digit expansion or a 0.000000 that hides a small value.
std::string number_text(double v);
/// Splits on runs of whitespace.
std::vector<std::string> split_ws(std::string_view s);
/// Splits text into lines (handles \n and \r\n); keeps empty lines.
std::vector<std::string> split_lines(std::string_view s);

/// Parses a whole token as a number; throws FormatError naming path and field on failure.
double parse_double(const std::string& tok, const std::string& path, const char* field);
std::int64_t parse_int(const std::string& tok, const std::string& path, const char* field);
/// Exactly n numbers from whitespace/comma separated text.
std::vector<double> parse_doubles(std::string_view text, std::size_t n, const std::string& path, const char* field);
std::vector<std::int64_t> parse_ints(std::string_view text, std::size_t n, const std::string& path, const char* field);

/// Parses "true"/"false"/"1"/"0"/"yes"/"no" (case-insensitive).
bool parse_bool(const std::string& tok, const std::string& path, const char* field);

/// Expands a printf-like file pattern with exactly one integer conversion (%d, %i, %u, with
/// optional 0 flag and width, %% for a literal %), e.g. "quarter.%d" or "slice%03d.raw".
/// Anything else is rejected with FormatError (no general printf on header text).
std::string format_file_pattern(const std::string& fmt, std::int64_t i, const std::string& path);

/// The indices min, min+step, ... up to max of a "PATTERN min max step" file list (NRRD's data
/// file, MetaImage's ElementDataFile), in checked arithmetic; FormatError "PATH: bad FIELD range"
/// for a zero step, a step pointing away from max, or more than 2^20 files.
std::vector<std::int64_t> file_range_indices(std::int64_t min, std::int64_t max, std::int64_t step,
                                             const std::string& path, const char* field);

/// Directory part of a path ("" -> ".").
std::string parent_dir(const std::string& path);
/// Joins a file name found in a header to the header's directory unless it is absolute.
std::string resolve_relative(const std::string& header_path, const std::string& name);

}  // namespace meshless
