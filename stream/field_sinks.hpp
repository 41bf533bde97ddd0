// Sinks of the field-query graphs (stream/field_query_sources.hpp -> FieldEvaluateStage):
//   ProbeCsvSink    CSV "x,y,z,value,gx,gy,gz" (%.9g), one row per query, streamed through an
//                   AtomicFile (temporary name + rename on finish; "-" = stdout)
//   SliceImageSink  a width x height colour-mapped image, pixels in source order (row 0 = top)
//   NrrdVolumeSink  a float32 NRRD over the grid (formats/nrrd_writer.hpp's bytes), samples in source
//                   order, streamed through an AtomicFile: memory is one batch, not the volume
// All take batches of kind query in sequence order (FormatError otherwise, or when more values arrive
// than the raster holds). Not thread-safe (the runner calls them serially).
#pragma once
#include <memory>
#include <string>

#include "formats/atomic_file.hpp"
#include "kernels/colormap.hpp"
#include "kernels/splat_rasterizer.hpp"
#include "stream/stage.hpp"

namespace meshless {

class ProbeCsvSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::queries; }
    explicit ProbeCsvSink(const std::string& path);
    void consume(Batch&& b) override;
    void finish() override;

private:
    AtomicFile out_;
};

class SliceImageSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::queries; }
    SliceImageSink(int width, int height, Colormap cmap, double lo, double hi);
    void consume(Batch&& b) override;
    const Image& image() const { return img_; }
    Image& image() { return img_; }

private:
    Image img_;
    Colormap cmap_;
    double lo_, hi_;
    std::size_t next_ = 0;
};

class NrrdVolumeSink final : public Sink {
public:
    PayloadSet takes() const override { return Payload::queries; }
    NrrdVolumeSink(const GridSpec& g, const std::string& path, const std::string& comment);
    void consume(Batch&& b) override;
    /// Throws std::logic_error when fewer samples than the grid holds arrived (nothing is committed).
    void finish() override;

private:
    AtomicFile out_;
    std::size_t total_, next_ = 0;
    std::vector<float> buf_;
};

}  // namespace meshless
