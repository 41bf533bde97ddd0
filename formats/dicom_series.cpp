// DICOM series assembly (formats/dicom_series.hpp): gather, group, choose, sort along the normal,
// check the grid, then read slice by slice through formats/dicom_slice.hpp (GDCM).
#include "formats/dicom_series.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "kernels/significant_text.hpp"
#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"
#include "kernels/flip_axes.hpp"
#include "kernels/vec3.hpp"

namespace meshless {

namespace fs = std::filesystem;

namespace {

bool is_dicomdir_name(const fs::path& p) { return to_lower(p.filename().string()) == "dicomdir"; }

std::string name_of(const std::string& file) { return fs::path(file).filename().string(); }

// The candidate files of an input, sorted by path (the order only breaks ties in messages).
std::vector<std::string> gather(const std::string& path, const ReferencePolicy& refs, std::string& only_series_of) {
    std::error_code ec;
    std::vector<std::string> files;
    auto consider = [&](const fs::path& p) {
        if (p.filename().string().front() == '.' || is_dicomdir_name(p)) return;
        check_reference(refs, path, p.string());
        if (fs::is_regular_file(p, ec) && has_dicom_magic(p.string())) files.push_back(p.string());
    };
    if (fs::is_directory(path, ec)) {
        for (fs::directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) consider(it->path());
        if (ec) throw IoError(path + ": cannot list the folder: " + ec.message());
    } else if (is_dicomdir_name(path)) {
        const fs::path root = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
        for (fs::recursive_directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec))
            if (it->is_regular_file(ec)) consider(it->path());
        if (ec) throw IoError(path + ": cannot list the DICOMDIR's folder: " + ec.message());
    } else {
        if (!has_dicom_magic(path)) throw FormatError(path + ": not a DICOM file (no 'DICM' after the 128-byte preamble)");
        only_series_of = path;
        const fs::path root = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
        for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) consider(it->path());
        if (ec) throw IoError(path + ": cannot list its folder: " + ec.message());
    }
    std::sort(files.begin(), files.end());
    if (files.empty()) throw FormatError(path + ": no DICOM files (none with 'DICM' after a 128-byte preamble)");
    return files;
}

Vec3 v3(const double* a) { return Vec3{a[0], a[1], a[2]}; }

// A distance for a message: 6 significant digits (a step of 1.7999999999999998 says 1.8).
std::string num6(double v) { return significant_text(v, 6); }
std::string mm(double v) { return num6(v) + " mm"; }

// The rules a series must keep to be one regular grid; `s.slices` sorted along the normal on return.
void check_and_sort(DicomSeries& s, const std::string& path) {
    auto& sl = s.slices;
    const DicomSliceHeader& first = sl.front();
    const std::string in = path + ": ";
    for (const auto& h : sl) {
        if (!h.has_pixel_data) throw FormatError(in + name_of(h.file) + " holds no image (no Pixel Data)");
        if (h.samples_per_pixel != 1 || h.stored_bytes() == 0 || h.frames != 1 || h.rows < 1 || h.columns < 1)
            throw FormatError(in + name_of(h.file) + ": unsupported pixel data (" + std::to_string(h.columns) + " x " +
                              std::to_string(h.rows) + ", " + std::to_string(h.samples_per_pixel) + " sample(s) per pixel, " +
                              std::to_string(h.bits_allocated) + " bits allocated, " + std::to_string(h.frames) +
                              " frame(s); one 8- or 16-bit sample per pixel, one frame, is read)");
        if (!h.photometric.empty() && h.photometric != "MONOCHROME1" && h.photometric != "MONOCHROME2")
            throw FormatError(in + name_of(h.file) + ": unsupported pixel data (Photometric Interpretation '" +
                              escape_field(h.photometric) + "'; MONOCHROME1 and MONOCHROME2 are read)");
        if (h.rows != first.rows || h.columns != first.columns)
            throw FormatError(in + "mixed sizes: " + name_of(first.file) + " is " + std::to_string(first.columns) + " x " +
                              std::to_string(first.rows) + ", " + name_of(h.file) + " is " + std::to_string(h.columns) + " x " +
                              std::to_string(h.rows));
        if (h.bits_allocated != first.bits_allocated || h.pixel_representation != first.pixel_representation)
            throw FormatError(in + "mixed pixel formats: " + name_of(first.file) + " and " + name_of(h.file) +
                              " differ in Bits Allocated or Pixel Representation");
        if (h.pixel_spacing.has_value() != first.pixel_spacing.has_value() ||
            (h.pixel_spacing && (std::abs((*h.pixel_spacing)[0] - (*first.pixel_spacing)[0]) > 1e-4 * std::abs((*first.pixel_spacing)[0]) ||
                                 std::abs((*h.pixel_spacing)[1] - (*first.pixel_spacing)[1]) > 1e-4 * std::abs((*first.pixel_spacing)[1]))))
            throw FormatError(in + "mixed pixel spacings: " + name_of(first.file) + " and " + name_of(h.file));
        if (h.orientation.has_value() != first.orientation.has_value())
            throw FormatError(in + "mixed orientations: " + name_of(first.file) + " and " + name_of(h.file) +
                              " (one has no Image Orientation (Patient))");
        if (h.orientation)
            for (int i = 0; i < 6; ++i)
                if (std::abs((*h.orientation)[i] - (*first.orientation)[i]) > 1e-4)
                    throw FormatError(in + "mixed orientations: " + name_of(first.file) + " and " + name_of(h.file) +
                                      " differ in Image Orientation (Patient)");
        // the float32 range: |slope| x 65535 + |intercept|
        if (!(std::abs(h.slope) * 65536.0 + std::abs(h.intercept) < 3.0e38))
            throw FormatError(in + name_of(h.file) + ": Rescale Slope " + number_text(h.slope) + " and Intercept " +
                              number_text(h.intercept) + " put samples beyond the float32 range");
    }
    const std::size_t n = sl.size();
    Vec3 row{1, 0, 0}, col{0, 1, 0};
    if (first.orientation) {
        row = v3(first.orientation->data());
        col = v3(first.orientation->data() + 3);
        if (std::abs(norm(row) - 1) > 1e-2 || std::abs(norm(col) - 1) > 1e-2 || std::abs(dot(row, col)) > 1e-2)
            throw FormatError(in + name_of(first.file) + ": bad Image Orientation (Patient): the row and column directions are not orthogonal unit vectors");
        row = normalized(row);
        col = normalized(col);
    } else if (n > 1) {
        throw FormatError(in + name_of(first.file) + ": no Image Orientation (Patient) (0020,0037): the slices cannot be ordered");
    }
    const Vec3 nrm = normalized(cross(row, col));
    for (const auto& h : sl)
        if (!h.position && n > 1)
            throw FormatError(in + name_of(h.file) + ": no Image Position (Patient) (0020,0032): the slices cannot be ordered");
    auto along = [&](const DicomSliceHeader& h) { return h.position ? dot(v3(h.position->data()), nrm) : 0.0; };
    std::stable_sort(sl.begin(), sl.end(), [&](const DicomSliceHeader& a, const DicomSliceHeader& b) { return along(a) < along(b); });
    std::vector<double> d(n);
    for (std::size_t k = 0; k < n; ++k) d[k] = along(sl[k]);
    double step = 1.0;
    if (n > 1) {
        std::vector<double> steps(n - 1);
        for (std::size_t k = 0; k + 1 < n; ++k) steps[k] = d[k + 1] - d[k];
        std::vector<double> sorted = steps;
        std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
        const double m = sorted[sorted.size() / 2];  // the usual step
        for (std::size_t k = 0; k + 1 < n; ++k)
            if (!(steps[k] > 1e-2 * m) || !(steps[k] > 1e-6))
                throw FormatError(in + "duplicated slice: " + name_of(sl[k].file) + " and " + name_of(sl[k + 1].file) +
                                  " are both at " + mm(d[k]) + " along the normal");
        // gantry tilt: the positions must run along the normal
        const Vec3 p0 = v3(sl.front().position->data());
        for (std::size_t k = 1; k < n; ++k) {
            const Vec3 dp = v3(sl[k].position->data()) - p0;
            const double a = dot(dp, nrm);
            const double off = norm(dp - nrm * a);
            if (off > 1e-3 * std::abs(a) + 1e-4)
                throw FormatError(in + "gantry tilt: slice positions run " + num6(std::round(std::atan2(off, a) * 180.0 / M_PI * 100) / 100) +
                                  " degrees off the orientation normal (" + name_of(sl[k].file) +
                                  "; a tilted series is not a regular grid)");
        }
        for (std::size_t k = 0; k + 1 < n; ++k) {
            const double r = steps[k] / m;
            if (std::abs(r - 1) <= 1e-2) continue;
            const double whole = std::round(r);
            if (whole >= 2 && std::abs(r - whole) <= 1e-2 * whole)
                throw FormatError(in + "missing slice" + (whole > 2 ? "s" : "") + ": the step from " + name_of(sl[k].file) + " to " +
                                  name_of(sl[k + 1].file) + " is " + mm(steps[k]) + ", " + number_text(whole) + " times the usual " + mm(m));
            std::vector<double> distinct;
            for (double x : steps)
                if (std::none_of(distinct.begin(), distinct.end(), [&](double y) { return std::abs(x - y) <= 1e-2 * m; })) distinct.push_back(x);
            std::string list;
            for (std::size_t i = 0; i < distinct.size() && i < 6; ++i) list += (i ? ", " : "") + num6(distinct[i]);
            if (distinct.size() > 6) list += ", ...";
            throw FormatError(in + "uneven spacing: steps of " + list + " mm along the normal (from " + name_of(sl[k].file) + " to " +
                              name_of(sl[k + 1].file) + ": " + mm(steps[k]) + ", the usual " + mm(m) + ")");
        }
        step = (d[n - 1] - d[0]) / static_cast<double>(n - 1);
    }
    // the grid
    GridSpec& g = s.grid;
    g.dims = {first.columns, first.rows, static_cast<std::int64_t>(n)};
    const double sx = first.pixel_spacing ? (*first.pixel_spacing)[1] : 1.0;
    const double sy = first.pixel_spacing ? (*first.pixel_spacing)[0] : 1.0;
    if (!(sx > 0) || !(sy > 0))
        throw FormatError(in + name_of(first.file) + ": bad Pixel Spacing (0028,0030) " + number_text(sy) + "\\" + number_text(sx) + " (must be > 0)");
    const Vec3 p0 = first.position ? v3(sl.front().position->data()) : Vec3{};
    g.origin = {p0.x, p0.y, p0.z};
    const auto signs = axis_aligned_signs({row * sx, col * sy, nrm * step});
    if (signs) {
        const double len[3] = {sx, sy, step};
        for (int a = 0; a < 3; ++a) honour_signed_spacing(g, s.flip, a, (*signs)[static_cast<std::size_t>(a)] * len[a]);
    } else {
        g.spacing = {sx, sy, step};
    }
    validate_grid(g, path);
    if (first.orientation) {
        AnatomicalFrame f;
        f.axis = {row, col, nrm};
        f.source = "Image Orientation (Patient)";
        s.frame = f;
        flip_frame(s.frame, s.flip);
    }
    // the samples
    s.rescaled = std::any_of(sl.begin(), sl.end(), [](const DicomSliceHeader& h) { return h.slope != 1.0 || h.intercept != 0.0; });
    if (s.rescaled) s.type = SampleType::f32;
    else if (first.bits_allocated == 8) s.type = first.pixel_representation == 1 ? SampleType::i16 : SampleType::u8;
    else s.type = first.pixel_representation == 1 ? SampleType::i16 : SampleType::u16;
    // the files prove the pixels their headers claim before anything is allocated from them
    const std::uint64_t slice_bytes = checked_mul(checked_mul(static_cast<std::uint64_t>(first.rows), static_cast<std::uint64_t>(first.columns),
                                                              in + "Rows x Columns"),
                                                  static_cast<std::uint64_t>(first.stored_bytes()), in + "slice bytes");
    checked_mul(checked_mul(slice_bytes, n, in + "slices"), sample_size(s.type), in + "volume bytes");
    for (const auto& h : sl) {
        const std::uint64_t holds = h.pixel_data_length.value_or(h.file_size);
        if (!h.compressed && holds < slice_bytes)
            throw FormatError(in + name_of(h.file) + ": truncated: Rows x Columns (" + std::to_string(h.columns) + " x " +
                              std::to_string(h.rows) + ") takes " + std::to_string(slice_bytes) + " bytes of pixel data, the file has " +
                              std::to_string(holds));
        if (h.compressed && slice_bytes / kDicomMaxCompression > h.file_size)
            throw FormatError(in + name_of(h.file) + ": compressed pixel data of " + std::to_string(h.file_size) +
                              " bytes cannot hold Rows x Columns (" + std::to_string(h.columns) + " x " + std::to_string(h.rows) +
                              ", more than " + std::to_string(kDicomMaxCompression) + ":1)");
    }
}

}  // namespace

std::string describe_dicom_series(const DicomSeriesSummary& s) {
    return (s.uid.empty() ? std::string("(no Series Instance UID)") : escape_field(s.uid)) + " '" + escape_field(s.description) +
           "', " + std::to_string(s.slices) + " slice" + (s.slices == 1 ? "" : "s") + ", " + std::to_string(s.columns) + " x " +
           std::to_string(s.rows);
}

bool looks_like_dicom(const std::string& path, std::size_t scan) {
    std::error_code ec;
    try {
        if (fs::is_directory(path, ec)) {
            std::size_t seen = 0;
            for (fs::directory_iterator it(path, ec), end; !ec && it != end && seen < scan; it.increment(ec), ++seen)
                if (is_dicomdir_name(it->path()) || (it->is_regular_file(ec) && has_dicom_magic(it->path().string()))) return true;
            return false;
        }
        return fs::is_regular_file(path, ec) && (is_dicomdir_name(path) || has_dicom_magic(path));
    } catch (const std::exception&) {
        return false;
    }
}

namespace {

// The image series of an input: headers grouped by Series Instance UID (in UID order), those
// without any Pixel Data left out.
struct Collected {
    std::map<std::string, std::vector<DicomSliceHeader>> groups;
    std::vector<const std::vector<DicomSliceHeader>*> images;
    std::vector<DicomSeriesSummary> series;
};

void collect(const std::string& path, const ReferencePolicy& refs, Collected& c) {
    if (!dicom_reader_available()) read_dicom_slice_header(path);  // throws: this build has no DICOM reader
    std::string only_series_of;
    const std::vector<std::string> files = gather(path, refs, only_series_of);
    std::string only_uid;
    for (const auto& f : files) {
        DicomSliceHeader h = read_dicom_slice_header(f);
        if (f == only_series_of) only_uid = h.series_uid;
        c.groups[h.series_uid].push_back(std::move(h));
    }
    if (!only_series_of.empty())
        for (auto it = c.groups.begin(); it != c.groups.end();) it = it->first == only_uid ? std::next(it) : c.groups.erase(it);
    std::size_t without_pixels = 0;
    for (const auto& [uid, g] : c.groups) {
        if (std::none_of(g.begin(), g.end(), [](const DicomSliceHeader& h) { return h.has_pixel_data; })) {
            without_pixels += g.size();
            continue;
        }
        c.images.push_back(&g);
        c.series.push_back(DicomSeriesSummary{uid, g.front().series_description, static_cast<std::int64_t>(g.size()),
                                              g.front().columns, g.front().rows});
    }
    if (c.images.empty())
        throw FormatError(path + ": no image series (" + std::to_string(without_pixels) + " DICOM file(s), none with Pixel Data)");
}

}  // namespace

std::vector<DicomSeriesSummary> list_dicom_series(const std::string& path, const ReferencePolicy& refs) {
    Collected c;
    collect(path, refs, c);
    return c.series;
}

DicomSeries open_dicom_series(const std::string& path, const std::string& choice, const ReferencePolicy& refs) {
    Collected c;
    collect(path, refs, c);
    DicomSeries s;
    s.input = path;
    s.series = c.series;
    const auto& images = c.images;
    std::size_t pick = 0;
    auto listing = [&] {
        std::string l;
        for (std::size_t i = 0; i < s.series.size(); ++i)
            l += (i ? "; " : "") + std::to_string(i + 1) + ") " + describe_dicom_series(s.series[i]);
        return l;
    };
    if (!choice.empty()) {
        const bool number = std::all_of(choice.begin(), choice.end(), [](char ch) { return ch >= '0' && ch <= '9'; }) && choice.size() < 9;
        std::size_t i = 0;
        for (; i < s.series.size(); ++i)
            if (s.series[i].uid == choice || (number && std::stoul(choice) == i + 1)) break;
        if (i == s.series.size())
            throw InvalidArgument("--series " + escape_field(choice) + ": " + path + " holds no such series (" + listing() + ")");
        pick = i;
    } else if (s.series.size() > 1) {
        throw FormatError(path + ": holds " + std::to_string(s.series.size()) + " series, choose one with --series UID or --series N: " + listing());
    }
    s.slices = *images[pick];
    s.uid = s.series[pick].uid;
    s.description = s.series[pick].description;
    if (!s.slices.empty())
    {  // (Rescale Type US: "unspecified", no unit)
        const std::string& type = s.slices.front().rescale_type;
        s.value_unit = !type.empty() && type != "US" ? type : s.slices.front().modality == "CT" ? "HU" : "";
    }
    check_and_sort(s, path);
    return s;
}

void read_dicom_series_slice(const DicomSeries& s, std::int64_t k, std::byte* out, std::vector<std::byte>& scratch) {
    const std::int64_t nz = s.grid.dims[2];
    if (k < 0 || k >= nz) throw InvalidArgument(s.input + ": slice " + std::to_string(k) + " outside 0.." + std::to_string(nz - 1));
    const DicomSliceHeader& h = s.slices[static_cast<std::size_t>(s.flip[2] ? nz - 1 - k : k)];
    const std::int64_t nx = s.grid.dims[0], ny = s.grid.dims[1];
    const std::size_t sb = static_cast<std::size_t>(h.stored_bytes());
    scratch.resize(static_cast<std::size_t>(nx * ny) * sb);
    with_error_prefix(s.input, s.input + ": ", [&] { decode_dicom_slice(h, scratch.data()); });
    const bool is_signed = h.pixel_representation == 1;
    auto stored = [&](std::int64_t i) -> double {
        if (sb == 1) {
            const auto b = static_cast<std::uint8_t>(scratch[static_cast<std::size_t>(i)]);
            return is_signed ? static_cast<double>(static_cast<std::int8_t>(b)) : static_cast<double>(b);
        }
        std::uint16_t v;
        std::memcpy(&v, scratch.data() + 2 * i, 2);
        return is_signed ? static_cast<double>(static_cast<std::int16_t>(v)) : static_cast<double>(v);
    };
    const std::size_t os = sample_size(s.type);
    for (std::int64_t j = 0; j < ny; ++j) {
        const std::int64_t sj = s.flip[1] ? ny - 1 - j : j;
        for (std::int64_t i = 0; i < nx; ++i) {
            const std::int64_t si = s.flip[0] ? nx - 1 - i : i;
            const double v = stored(si + nx * sj);
            std::byte* dst = out + static_cast<std::size_t>(i + nx * j) * os;
            switch (s.type) {
                case SampleType::f32: {
                    const float f = static_cast<float>(h.slope * v + h.intercept);
                    std::memcpy(dst, &f, 4);
                    break;
                }
                case SampleType::u8: {
                    const auto b = static_cast<std::uint8_t>(v);
                    std::memcpy(dst, &b, 1);
                    break;
                }
                case SampleType::i16: {
                    const auto b = static_cast<std::int16_t>(v);
                    std::memcpy(dst, &b, 2);
                    break;
                }
                case SampleType::u16: {
                    const auto b = static_cast<std::uint16_t>(v);
                    std::memcpy(dst, &b, 2);
                    break;
                }
            }
        }
    }
}

Volume read_dicom_series(const DicomSeries& s) {
    Volume v(s.grid, s.type);
    const std::size_t slice = static_cast<std::size_t>(s.grid.dims[0] * s.grid.dims[1]) * sample_size(s.type);
    std::vector<std::byte> scratch;
    std::byte* base = v.bytes.data();
    for (std::int64_t k = 0; k < s.grid.dims[2]; ++k) read_dicom_series_slice(s, k, base + static_cast<std::size_t>(k) * slice, scratch);
    return v;
}

}  // namespace meshless
