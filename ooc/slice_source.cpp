#include "ooc/slice_source.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <vector>

#include "formats/binary_file.hpp"
#include "formats/dicom_series.hpp"
#include "ooc/brick_slice_source.hpp"
#include "formats/gzip.hpp"
#include "formats/metaimage.hpp"
#include "formats/npy_volume.hpp"
#include "formats/nrrd.hpp"
#include "formats/payload.hpp"
#include "formats/raw_volume.hpp"
#include "formats/stored_type.hpp"
#include "formats/voreen_dat.hpp"
#include "formats/hdf5_volume.hpp"
#include "formats/zarr.hpp"
#include "formats/reference_policy.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace {

void check_range(const SliceSource& s, std::int64_t k, std::int64_t count) {
    if (k < 0 || count < 0 || k + count > s.grid().dims[2])
        throw InvalidArgument(s.name() + ": slices [" + std::to_string(k) + "," + std::to_string(k + count) +
                              ") outside the volume's " + std::to_string(s.grid().dims[2]) + " slices");
}

/// A volume already in memory (formats that are read whole).
class MemorySliceSource final : public SliceSource {
public:
    MemorySliceSource(Volume v, std::string name) : v_(std::move(v)), name_(std::move(name)) {}
    const GridSpec& grid() const override { return v_.grid; }
    SampleType type() const override { return v_.type; }
    std::string name() const override { return name_; }
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        check_range(*this, k, count);
        const std::size_t slice = static_cast<std::size_t>(v_.grid.dims[0] * v_.grid.dims[1]) * sample_size(v_.type);
        std::memcpy(out, v_.bytes.data() + static_cast<std::size_t>(k) * slice, static_cast<std::size_t>(count) * slice);
    }

private:
    Volume v_;
    std::string name_;
};

/// A DICOM series, one file decoded per slice (memory: one slice and its decoded file).
class DicomSliceSource final : public SliceSource {
public:
    DicomSliceSource(DicomSeries s, std::string name) : s_(std::move(s)), name_(std::move(name)) {}
    const GridSpec& grid() const override { return s_.grid; }
    SampleType type() const override { return s_.type; }
    std::string name() const override { return name_; }
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        check_range(*this, k, count);
        const std::size_t slice = static_cast<std::size_t>(s_.grid.dims[0] * s_.grid.dims[1]) * sample_size(s_.type);
        for (std::int64_t i = 0; i < count; ++i) read_dicom_series_slice(s_, k + i, out + static_cast<std::size_t>(i) * slice, scratch_);
    }

private:
    DicomSeries s_;
    std::string name_;
    std::vector<std::byte> scratch_;
};

/// Executes a payload plan (raw or gzip, no line skip) slab by slab: random access for raw files,
/// sequential decompression for gzip (restarting the current file when asked to go back).
class PlanSliceSource final : public SliceSource {
public:
    PlanSliceSource(PayloadPlan plan, std::string name) : plan_(std::move(plan)), name_(std::move(name)) {
        // grid, sizes and files proven before any slab is allocated (formats/payload.hpp)
        starts_ = check_payload_plan(plan_);
        type_ = volume_type_for(plan_.type);
        share_ = static_cast<std::uint64_t>(plan_.grid.voxel_count()) * stored_size(plan_.type) / plan_.files.size();
    }
    const GridSpec& grid() const override { return plan_.grid; }
    SampleType type() const override { return type_; }
    std::string name() const override { return name_; }

    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        check_range(*this, k, count);
        if (count == 0) return;
        const std::uint64_t slice_stored = static_cast<std::uint64_t>(plan_.grid.dims[0] * plan_.grid.dims[1]) * stored_size(plan_.type);
        const std::uint64_t begin = static_cast<std::uint64_t>(k) * slice_stored;
        const std::uint64_t bytes = static_cast<std::uint64_t>(count) * slice_stored;
        const bool native = plan_.type == StoredType::u8 || plan_.type == StoredType::u16 || plan_.type == StoredType::i16 ||
                            plan_.type == StoredType::f32;
        const bool direct = native && plan_.big_endian != host_is_little_endian();
        if (direct) {
            fetch(begin, bytes, out);
            return;
        }
        std::vector<std::byte> buf(static_cast<std::size_t>(bytes));
        fetch(begin, bytes, buf.data());
        GridSpec g = plan_.grid;
        g.dims[2] = count;
        const Volume v = make_volume(std::move(buf), plan_.type, plan_.big_endian, g, plan_.files.front());
        std::memcpy(out, v.bytes.data(), v.bytes.size());
    }

private:
    // Bytes [begin, begin+n) of the concatenated (decoded) payload; errors name the header too.
    void fetch(std::uint64_t begin, std::uint64_t n, std::byte* dst) {
        naming_header(plan_, [&] { fetch_files(begin, n, dst); });
    }
    void fetch_files(std::uint64_t begin, std::uint64_t n, std::byte* dst) {
        while (n > 0) {
            const std::size_t f = static_cast<std::size_t>(begin / share_);
            const std::uint64_t in_file = begin % share_;
            const std::uint64_t take = std::min(n, share_ - in_file);
            const std::string& file = plan_.files[f];
            if (plan_.encoding == PayloadEncoding::raw) {
                if (!raw_ || raw_file_ != f) {  // one file open at a time (a stack may hold thousands)
                    raw_.reset();
                    raw_ = std::make_unique<FileRangeReader>(file);
                    raw_file_ = f;
                }
                raw_->read_into(starts_[f] + in_file, take, dst);
            } else {
                if (!inflate_ || inflate_file_ != f || inflate_->position() > in_file + skip_) {
                    inflate_ = std::make_unique<InflateReader>(file, starts_[f]);
                    inflate_file_ = f;
                    skip_ = static_cast<std::uint64_t>(std::max<std::int64_t>(0, plan_.byte_skip));
                    inflate_->skip(skip_);
                }
                const std::uint64_t pos = inflate_->position() - skip_;
                if (pos < in_file) inflate_->skip(in_file - pos);
                inflate_->read_exact(dst, static_cast<std::size_t>(take), "payload");
                // the file's share is complete: its stream must end here (the gzip tail rule, as read_payload)
                if (in_file + take == share_) inflate_->expect_end(skip_ + share_);
            }
            dst += take;
            begin += take;
            n -= take;
        }
    }

    PayloadPlan plan_;
    std::string name_;
    SampleType type_ = SampleType::u8;
    std::uint64_t share_ = 0;
    std::vector<std::uint64_t> starts_;
    std::unique_ptr<FileRangeReader> raw_;  // the raw payload file read last, kept open
    std::size_t raw_file_ = 0;
    std::unique_ptr<InflateReader> inflate_;
    std::size_t inflate_file_ = 0;
    std::uint64_t skip_ = 0;
};

/// A Zarr store, one z-row of chunks decoded at a time (memory: the row, one chunk and its file).
class ZarrSliceSource final : public SliceSource {
public:
    ZarrSliceSource(ZarrArray a, std::string name) : rows_(std::move(a)), name_(std::move(name)) {}
    const GridSpec& grid() const override { return rows_.array().grid; }
    SampleType type() const override { return rows_.type(); }
    std::string name() const override { return name_; }
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        check_range(*this, k, count);
        const GridSpec& g = grid();
        const std::int64_t cz = rows_.array().chunk[2];
        const std::size_t slice = static_cast<std::size_t>(g.dims[0] * g.dims[1]) * sample_size(type());
        for (std::int64_t s = k; s < k + count;) {
            const std::int64_t r = s / cz, z0 = r * cz, z1 = std::min(g.dims[2], z0 + cz);
            const std::int64_t take = std::min(k + count, z1) - s;
            std::byte* dst = out + static_cast<std::size_t>(s - k) * slice;
            if (s == z0 && take == z1 - z0) {  // the whole row asked for: decoded in place
                rows_.read_row(r, dst);
            } else {
                if (row_ != r) {
                    buffer_.resize(static_cast<std::size_t>(z1 - z0) * slice);
                    rows_.read_row(r, buffer_.data());
                    row_ = r;
                }
                std::memcpy(dst, buffer_.data() + static_cast<std::size_t>(s - z0) * slice, static_cast<std::size_t>(take) * slice);
            }
            s += take;
        }
    }

private:
    ZarrChunkRows rows_;
    std::string name_;
    std::vector<std::byte> buffer_;  // the row read last
    std::int64_t row_ = -1;
};

// An HDF5 dataset one z-row of chunks at a time (formats/hdf5_volume.hpp).
class Hdf5SliceSource final : public SliceSource {
public:
    explicit Hdf5SliceSource(Hdf5Slices s) : slices_(std::move(s)) {}
    const GridSpec& grid() const override { return slices_.grid(); }
    SampleType type() const override { return slices_.type(); }
    std::string name() const override { return slices_.name(); }
    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        check_range(*this, k, count);
        slices_.read_slices(k, count, out);
    }

private:
    Hdf5Slices slices_;
};

std::optional<PayloadPlan> streamable_plan(const std::string& path, const RawOptions& raw) {
    const VolumeInfo vi = probe_volume(path, raw);
    PayloadPlan plan;
    if (vi.format == "raw") plan = plan_raw(path, raw);
    else if (vi.format == "npy") plan = plan_npy(path, raw);
    else if (vi.format == "nrrd") plan = plan_nrrd(path);
    else if (vi.format == "metaimage") plan = plan_metaimage(path);
    else if (vi.format == "voreen-dat") plan = plan_voreen_dat(path);
    else return std::nullopt;
    check_references(raw.references, path, plan.files);  // probe_volume checked them too; the plan is read again
    if (plan.files.empty() || plan.line_skip != 0) return std::nullopt;
    if (plan.flip[0] || plan.flip[1] || plan.flip[2]) return std::nullopt;  // read whole, then reversed
    if (plan.encoding != PayloadEncoding::raw && plan.encoding != PayloadEncoding::gzip) return std::nullopt;
    if (plan.encoding == PayloadEncoding::gzip && plan.byte_skip < 0) return std::nullopt;  // read_payload reports it
    return plan;
}

// ---------------------------------------------------------------------------------------------
// Upsampling.

struct Taps {
    std::int64_t idx[4];
    double w[4];
    int n = 0;
};

// Interpolation taps of fine sample I on an axis of n coarse samples (factor f).
std::vector<Taps> axis_taps(std::int64_t n, int f, Upsampling mode) {
    const std::int64_t fine = n == 1 ? 1 : (n - 1) * f + 1;
    std::vector<Taps> taps(static_cast<std::size_t>(fine));
    for (std::int64_t I = 0; I < fine; ++I) {
        Taps& t = taps[static_cast<std::size_t>(I)];
        const std::int64_t i0 = I / f;
        const double u = static_cast<double>(I % f) / f;
        auto add = [&](std::int64_t i, double w) {
            if (w == 0) return;
            i = std::clamp<std::int64_t>(i, 0, n - 1);
            for (int q = 0; q < t.n; ++q)
                if (t.idx[q] == i) {
                    t.w[q] += w;
                    return;
                }
            t.idx[t.n] = i;
            t.w[t.n++] = w;
        };
        if (u == 0) {
            add(i0, 1.0);
        } else if (mode == Upsampling::trilinear) {
            add(i0, 1 - u);
            add(i0 + 1, u);
        } else {  // Catmull-Rom
            const double u2 = u * u, u3 = u2 * u;
            add(i0 - 1, 0.5 * (-u3 + 2 * u2 - u));
            add(i0, 0.5 * (3 * u3 - 5 * u2 + 2));
            add(i0 + 1, 0.5 * (-3 * u3 + 4 * u2 + u));
            add(i0 + 2, 0.5 * (u3 - u2));
        }
    }
    return taps;
}

template <class T>
T to_sample(double v) {
    if constexpr (std::is_floating_point_v<T>) {
        return static_cast<T>(v);
    } else {
        const double r = std::floor(v + 0.5);
        return static_cast<T>(std::clamp(r, static_cast<double>(std::numeric_limits<T>::lowest()),
                                         static_cast<double>(std::numeric_limits<T>::max())));
    }
}

class UpsamplingSliceSource final : public SliceSource {
public:
    UpsamplingSliceSource(const Volume& v, int f, Upsampling mode, std::string name) : v_(v), name_(std::move(name)) {
        if (f < 1 || f > 64) throw InvalidArgument(name_ + ": upsampling factor must be 1..64, got " + std::to_string(f));
        for (int a = 0; a < 3; ++a) {
            taps_[a] = axis_taps(v.grid.dims[a], f, mode);
            grid_.dims[a] = static_cast<std::int64_t>(taps_[a].size());
            grid_.origin[a] = v.grid.origin[a];
            grid_.spacing[a] = v.grid.spacing[a] / f;
        }
        if (grid_.dims[0] >= (std::int64_t{1} << 31) || grid_.dims[1] >= (std::int64_t{1} << 31))
            throw InvalidArgument(name_ + ": upsampled slice too large");
    }
    const GridSpec& grid() const override { return grid_; }
    SampleType type() const override { return v_.type; }
    std::string name() const override { return name_; }

    void read_slices(std::int64_t k, std::int64_t count, std::byte* out) override {
        check_range(*this, k, count);
        const std::size_t slice_bytes = static_cast<std::size_t>(grid_.dims[0] * grid_.dims[1]) * sample_size(v_.type);
        for (std::int64_t q = 0; q < count; ++q)
            visit_samples(v_.view(), [&](const auto* src) {
                using T = std::remove_const_t<std::remove_pointer_t<decltype(src)>>;
                slice(src, k + q, reinterpret_cast<T*>(out + static_cast<std::size_t>(q) * slice_bytes));
            });
    }

private:
    template <class T>
    void slice(const T* src, std::int64_t K, T* dst) {
        const std::int64_t nx = v_.grid.dims[0], ny = v_.grid.dims[1];
        const std::int64_t NX = grid_.dims[0], NY = grid_.dims[1];
        zbuf_.assign(static_cast<std::size_t>(nx * ny), 0.0);
        const Taps& tz = taps_[2][static_cast<std::size_t>(K)];
        for (int q = 0; q < tz.n; ++q) {
            const T* s = src + tz.idx[q] * nx * ny;
            const double w = tz.w[q];
            for (std::int64_t i = 0; i < nx * ny; ++i) zbuf_[static_cast<std::size_t>(i)] += w * static_cast<double>(s[i]);
        }
        ybuf_.assign(static_cast<std::size_t>(nx * NY), 0.0);
        for (std::int64_t J = 0; J < NY; ++J) {
            const Taps& ty = taps_[1][static_cast<std::size_t>(J)];
            double* row = ybuf_.data() + J * nx;
            for (int q = 0; q < ty.n; ++q) {
                const double* s = zbuf_.data() + ty.idx[q] * nx;
                const double w = ty.w[q];
                for (std::int64_t i = 0; i < nx; ++i) row[i] += w * s[i];
            }
        }
        const auto& tx = taps_[0];
        for (std::int64_t J = 0; J < NY; ++J) {
            const double* row = ybuf_.data() + J * nx;
            T* o = dst + J * NX;
            for (std::int64_t I = 0; I < NX; ++I) {
                const Taps& t = tx[static_cast<std::size_t>(I)];
                double v = 0;
                for (int q = 0; q < t.n; ++q) v += t.w[q] * row[t.idx[q]];
                o[I] = to_sample<T>(v);
            }
        }
    }

    const Volume& v_;
    std::string name_;
    GridSpec grid_;
    std::vector<Taps> taps_[3];
    std::vector<double> zbuf_, ybuf_;
};

}  // namespace

std::unique_ptr<SliceSource> open_slice_source(const std::string& path, const RawOptions& raw) {
    if (is_brick_store(path)) {
        refuse_array_choice(raw.array, path, "brick store (.mlb)");
        return open_brick_store_slices(path);
    }
    if (is_dicom_input(path, raw)) {
        refuse_array_choice(raw.array, path, "dicom");
        return std::make_unique<DicomSliceSource>(open_dicom_series(path, raw.series, raw.references), path);
    }
    if (is_zarr_input(path)) {
        check_reference(raw.references, path, path);
        refuse_array_choice(raw.array, path, "zarr");
        return std::make_unique<ZarrSliceSource>(open_zarr(path, raw), path);
    }
    if (is_hdf5_input(path)) {
        check_reference(raw.references, path, path);
        return std::make_unique<Hdf5SliceSource>(Hdf5Slices(path, raw));
    }
    if (auto plan = streamable_plan(path, raw)) return std::make_unique<PlanSliceSource>(std::move(*plan), path);
    return std::make_unique<MemorySliceSource>(read_volume(path, raw), path);
}

std::unique_ptr<SliceSource> make_volume_source(Volume v, std::string name) {
    return std::make_unique<MemorySliceSource>(std::move(v), std::move(name));
}

std::unique_ptr<SliceSource> make_upsampling_source(const Volume& v, int factor, Upsampling mode, std::string name) {
    return std::make_unique<UpsamplingSliceSource>(v, factor, mode, std::move(name));
}

}  // namespace meshless
