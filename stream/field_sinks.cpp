#include "stream/field_sinks.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "formats/nrrd_writer.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

void require_values(const Batch& b, const char* who) {
    if (b.query.value.size() != b.query.at.size())
        throw FormatError(std::string(who) + ": expected evaluated field queries");
}

void require_room(std::size_t at, std::size_t n, std::size_t total, const char* who) {
    if (n > total - std::min(at, total)) throw FormatError(std::string(who) + ": more values than the raster holds");
}

void append9(std::string& s, double v) {
    char b[32];
    const int n = std::snprintf(b, sizeof b, "%.9g", v);
    s.append(b, static_cast<std::size_t>(n));
}

}  // namespace

ProbeCsvSink::ProbeCsvSink(const std::string& path) : out_(path) { out_.write(std::string("x,y,z,value,gx,gy,gz\n")); }

void ProbeCsvSink::consume(Batch&& b) {
    require_values(b, "probe writer");
    const FieldQueries& q = b.query;
    if (q.grad.size() != q.at.size()) throw FormatError("probe writer: expected gradients");
    std::string s;
    for (std::size_t i = 0; i < q.at.size(); ++i) {
        const double v[7] = {q.at[i].x, q.at[i].y, q.at[i].z, q.value[i], q.grad[i].x, q.grad[i].y, q.grad[i].z};
        for (int k = 0; k < 7; ++k) {
            append9(s, v[k]);
            s.push_back(k == 6 ? '\n' : ',');
        }
    }
    out_.write(s);
}

void ProbeCsvSink::finish() { out_.commit(); }

SliceImageSink::SliceImageSink(int width, int height, Colormap cmap, double lo, double hi)
    : cmap_(cmap), lo_(lo), hi_(hi) {
    img_.width = width;
    img_.height = height;
    img_.rgb.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
}

void SliceImageSink::consume(Batch&& b) {
    require_values(b, "slice image");
    const auto& val = b.query.value;
    require_room(next_, val.size(), img_.rgb.size() / 3, "slice image");
    for (std::size_t i = 0; i < val.size(); ++i) {
        const auto c = map_color(cmap_, val[i], lo_, hi_);
        std::copy(c.begin(), c.end(), img_.rgb.begin() + static_cast<std::ptrdiff_t>(3 * (next_ + i)));
    }
    next_ += val.size();
}

NrrdVolumeSink::NrrdVolumeSink(const GridSpec& g, const std::string& path, const std::string& comment)
    : out_(path), total_(static_cast<std::size_t>(g.voxel_count())) {
    out_.write(nrrd_header(g, SampleType::f32, comment));
}

void NrrdVolumeSink::consume(Batch&& b) {
    require_values(b, "resample writer");
    const auto& val = b.query.value;
    require_room(next_, val.size(), total_, "resample writer");
    buf_.resize(val.size());
    for (std::size_t i = 0; i < val.size(); ++i) buf_[i] = static_cast<float>(val[i]);
    out_.write(buf_.data(), buf_.size() * sizeof(float));
    next_ += val.size();
}

void NrrdVolumeSink::finish() {
    if (next_ != total_)
        throw std::logic_error("resample writer: " + std::to_string(next_) + " of " + std::to_string(total_) + " samples arrived");
    out_.commit();
}

}  // namespace meshless
