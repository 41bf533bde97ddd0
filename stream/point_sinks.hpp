// Sinks that end a point pipeline: PlySink streams points into a binary PLY (formats/ply_points.hpp,
// temporary name + rename on finish), CollectSink keeps them in memory (for the splat renderer and
// for tests). Both require point batches (throw FormatError on samples). Not thread-safe.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "formats/ply_points.hpp"
#include "stream/stage.hpp"

namespace meshless {

class PlySink final : public Sink {
public:
    PlySink(const std::string& path, const std::vector<std::string>& comments);
    void consume(Batch&& b) override;
    void finish() override;
    std::uint64_t count() const { return count_; }

private:
    std::string path_;
    std::vector<std::string> comments_;
    std::unique_ptr<PlyPointWriter> w_;   // file output
    std::vector<PointRecord> held_;       // stdout output (count needed up front)
    std::uint64_t count_ = 0;
};

class CollectSink final : public Sink {
public:
    void consume(Batch&& b) override;
    std::vector<PointRecord> points;
};

}  // namespace meshless
