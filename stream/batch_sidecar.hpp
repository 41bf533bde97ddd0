// Up-to-date bookkeeping of the batch job (stream/batch_job.hpp, `meshless batch`), input
// fingerprints and output sidecars.
//
// Fingerprint: the files an input volume is made of (the path itself when a file, plus the payload
// files its header names, see probe_volume), each with its size and modification time (ns), and
// one CRC-32 (zlib polynomial) over all their bytes in that order, computed streaming (1 MiB reads,
// constant memory).
// Sidecar: "OUT.meta" beside each output OUT, text "key=value" lines (sorted keys, '#' comments),
// written through AtomicFile after the output itself is in place, so an output with a matching
// sidecar is complete. Keys: kind, input, input_files, input_file.N ("size mtime_ns path"),
// input_size, input_crc32, param.*, meshless (tool and format versions), output, output_size.
// An output is up to date when its sidecar's identity (kind, input size and CRC, param.*, meshless)
// equals the expected one and the output file has the recorded size; the input path and the
// stat list are not part of the identity (a moved or touched archive with the same bytes stays up
// to date), but a stat list equal to the current one lets the caller skip re-hashing the input.
// Throws IoError naming the file (unreadable input, unwritable sidecar). Not thread-safe.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace meshless {

/// The tool's version recorded in sidecars: CMake's project VERSION, as `meshless --version` says.
const char* meshless_version();

struct FileStat {
    std::string path;
    std::uint64_t size = 0;
    std::int64_t mtime_ns = 0;
    bool operator==(const FileStat&) const = default;
};

/// stat() of each file; a directory counts as size 0 with its mtime. IoError when one is missing.
std::vector<FileStat> stat_files(const std::vector<std::string>& paths);
/// CRC-32 over the bytes of all files in order (directories contribute nothing).
std::uint32_t crc32_files(const std::vector<FileStat>& files);

using Sidecar = std::map<std::string, std::string>;

/// The path of OUT's sidecar: OUT + ".meta".
std::string sidecar_path(const std::string& output);
/// Parsed sidecar, or nullopt when it is missing or unreadable (= not up to date).
std::optional<Sidecar> read_sidecar(const std::string& path);
/// Writes atomically (temporary + rename).
void write_sidecar(const std::string& path, const Sidecar& s);

/// The sidecar keys describing an input: input, input_files, input_file.N, input_size, input_crc32.
void put_input(Sidecar& s, const std::string& input, const std::vector<FileStat>& files, std::uint32_t crc);
/// The stat list recorded by put_input (empty when absent or malformed).
std::vector<FileStat> recorded_files(const Sidecar& s);
/// input_crc32 as recorded, if parseable.
std::optional<std::uint32_t> recorded_crc(const Sidecar& s);
/// True when the identity keys of `stored` equal those of `expected` (see above).
bool same_identity(const Sidecar& stored, const Sidecar& expected);

}  // namespace meshless
