// Reading a point store (.mlc, formats/point_store_format.hpp): open validates header, index and
// footer (not the bricks); read_brick reads one brick's frame, checks its CRC and size and decodes
// its points. The file is checked for a rewrite while it is read: every read_brick compares the
// file's size and modification time with those seen at open, so a store rewritten in place gives
// a FormatError naming the file and the brick, never points from two versions (a store replaced by
// a rename is not affected: the open descriptor keeps reading the old file).
// point_set_from_point_store reads every brick into a PointSet (one block named after the file,
// points in Morton order; dropped counts from the header). Units: as the converted input's.
// Errors: FormatError (one line starting with the path; brick damage names the brick), IoError when
// the file cannot be opened or read. Thread-safety: a PointStore is immutable after open();
// read_brick may be called concurrently (positional reads).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "formats/point_store_format.hpp"
#include "kernels/point_set.hpp"

namespace meshless {

class PointStore {
public:
    static std::unique_ptr<PointStore> open(const std::string& path);
    ~PointStore();
    PointStore(const PointStore&) = delete;
    PointStore& operator=(const PointStore&) = delete;
    const std::string& path() const { return path_; }
    const PointStoreLayout& layout() const { return layout_; }
    const PointStoreInfo& info() const { return layout_.info; }
    const std::vector<PointBrickEntry>& bricks() const { return layout_.bricks; }
    /// Brick i's points as count x 4 doubles (x, y, z, value) into out (resized).
    void read_brick(std::size_t i, std::vector<double>& out) const;

private:
    PointStore() = default;
    void check_unchanged(std::size_t brick) const;
    std::string path_;
    int fd_ = -1;
    PointStoreLayout layout_;
    long long size_ = 0, mtime_ns_ = 0;
};

/// True when the file starts with the point store magic (false for a missing, short or special file).
bool is_point_store(const std::string& path);

/// Every point of a store, brick by brick (see above); notes (when given) get what `meshless info`
/// prints about the store (bricks, levels, source).
PointSet point_set_from_point_store(const std::string& path, std::vector<std::string>* notes = nullptr);

}  // namespace meshless
