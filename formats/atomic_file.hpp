// Output files that are never left half-written.
//
// Durability (the constructor's choice):
//  - Durability::replace (the default, for outputs that a command can make again: points, meshes,
//    images, streams): the temporary is renamed into place without waiting for the disk, as
//    sed -i, sort -o and VTK's writers do. A failed or killed process never leaves a file that
//    looks complete. An existing target is swapped with the temporary (renameat2 RENAME_EXCHANGE,
//    atomic: readers see the old or the new file) and the old file then unlinked, because a rename
//    over it makes ext4 (auto_da_alloc) write the new file out inside the rename; this side-steps
//    that safety net on purpose, so after an operating-system crash the previous output may be gone
//    and the new one missing, empty or short (run the command again).
//    Measured on `isosurface -o out.ply` with a 54 MB output: fsync was 20-35 % of the wall time,
//    the rename over the old file 30-80 ms.
//  - Durability::fsync (stores and fits, costly to rebuild: .mlb, .mls, .mlf, .mlh; batch sidecars): commit()
//    flushes and fsyncs before the rename, so after a crash the file is either the old one or the
//    complete new one. To keep that wait short, write-back is started every few MiB as the file is
//    written (sync_file_range, asynchronous), overlapping the disk with the computation; commit()
//    then waits only for the tail.
//
// AtomicFile writes to "<path>.tmp-<pid>" in the same directory and puts it in place of <path> on
// commit() (the swap above, else a rename); if the object is destroyed without commit() (an exception, an early return) the
// temporary is removed. A process killed by a signal leaves only the temporary, never a file that
// looks complete, and the CLI's handlers for SIGINT, SIGTERM, SIGHUP and SIGXFSZ remove even that
// (the temporary is registered in formats/temporary_files.hpp). Before creating its temporary,
// AtomicFile removes the stale temporaries of <path> left by processes that no longer exist
// (remove_stale_temporaries). The path "-" means standard output, and an existing path that is not a regular
// file (a device such as /dev/null, a FIFO) is written directly, never replaced; a symbolic link
// is followed (the temporary goes beside its target, which is replaced).
// Throws IoError naming the path when the file cannot be created, written or renamed, or when the
// path is a directory. Not thread-safe; one writer per object.
#pragma once
#include <cstddef>
#include <cstdio>
#include <memory>
#include <cstdint>
#include <optional>
#include <string>

#include "formats/temporary_files.hpp"

namespace meshless {

/// Waits until the regular file at `path` (already complete and in place) is on disk: fsync of its
/// data, then of its directory entry. For outputs written with Durability::replace whose completion
/// is recorded elsewhere (the batch command's sidecars). Throws IoError naming the path.
void sync_to_disk(const std::string& path);

/// True for outputs that cannot seek: "-" and existing non-regular files (devices, FIFOs).
bool is_streaming_output(const std::string& path);

/// Bytes free for an unprivileged writer on the file system that an output file at `path` would be
/// written to (its folder's); nullopt for streaming outputs and when the folder cannot be asked.
std::optional<std::uint64_t> free_space_for_output(const std::string& path);

enum class Durability { replace, fsync };

class AtomicFile {
public:
    explicit AtomicFile(std::string path, Durability durability = Durability::replace);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// Appends bytes; throws IoError (or BrokenPipe when stdout's reader has gone).
    void write(const void* data, std::size_t n);
    void write(const std::string& s) { write(s.data(), s.size()); }
    /// Hands the buffered bytes to the file (or stdout, device, FIFO) now, so that a full disk or
    /// a closed pipe shows before commit(); throws as write().
    void flush();
    /// Overwrites bytes at an absolute offset already written (not for stdout).
    void pwrite(std::size_t offset, const void* data, std::size_t n);
    /// Flushes, closes and renames into place. After commit() no more writes.
    void commit();
    std::FILE* handle() { return file_; }
    const std::string& path() const { return path_; }
    bool is_stdout() const { return path_ == "-"; }
    /// True when the output cannot seek (stdout, a device or FIFO): see is_streaming_output.
    bool is_streaming() const { return is_stdout() || direct_; }

    /// The stdio buffer of the files AtomicFile opens (not stdout's).
    static constexpr std::size_t kBufferBytes = std::size_t{1} << 20;

private:
    bool replace_by_exchange();
    void buffer_file();
    std::string path_, target_, tmp_;
    std::FILE* file_ = nullptr;
    /// The stdio buffer of a regular file or FIFO (kBufferBytes; stdio's own is st_blksize, 4 KiB:
    /// one write(2) per 4 KiB of a large output); freed after the file is closed.
    std::unique_ptr<char[]> buffer_;
    TemporaryRegistration registration_;  ///< tmp_, for the signal handlers
    bool committed_ = false;
    bool direct_ = false;  ///< writing straight into a non-regular file
    Durability durability_ = Durability::replace;
    std::size_t written_ = 0, synced_ = 0;  ///< bytes appended; bytes whose write-back was started
};

}  // namespace meshless
