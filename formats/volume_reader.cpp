#include "formats/volume_reader.hpp"

#include <algorithm>
#include <cstring>
#include <new>
#include <filesystem>

#include "formats/binary_file.hpp"
#include "formats/dicom_series.hpp"
#include "formats/gzip.hpp"
#include "formats/length_unit.hpp"
#include "formats/metaimage.hpp"
#include "formats/nifti.hpp"
#include "formats/npy_header.hpp"
#include "formats/npy_volume.hpp"
#include "formats/nrrd.hpp"
#include "formats/payload.hpp"
#include "formats/raw_volume.hpp"
#include "formats/slc.hpp"
#include "formats/text_header.hpp"
#include "formats/voreen_dat.hpp"
#include "formats/vti.hpp"
#include "formats/vtk_legacy.hpp"
#include "formats/vtkjs_image.hpp"
#include "formats/hdf5_volume.hpp"
#include "formats/zarr.hpp"
#include "formats/reference_policy.hpp"
#include "kernels/checked_size.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace fs = std::filesystem;

namespace {

enum class Fmt { raw, npy, nrrd, metaimage, vtk_legacy, vti, vtkjs, slc, nifti, voreen_dat, dicom, zarr, hdf5, unknown };

bool ends_with(const std::string& s, const char* suf) {
    const std::size_t n = std::strlen(suf);
    return s.size() >= n && s.compare(s.size() - n, n, suf) == 0;
}

Fmt by_extension(const std::string& path) {
    const std::string l = to_lower(fs::path(path).filename().string());
    if (ends_with(l, ".nii.gz") || ends_with(l, ".nii") || ends_with(l, ".hdr") || ends_with(l, ".hdr.gz")) return Fmt::nifti;
    if (ends_with(l, ".nrrd") || ends_with(l, ".nhdr")) return Fmt::nrrd;
    if (ends_with(l, ".mhd") || ends_with(l, ".mha")) return Fmt::metaimage;
    if (ends_with(l, ".vtk")) return Fmt::vtk_legacy;
    if (ends_with(l, ".vti")) return Fmt::vti;
    if (ends_with(l, ".json")) return Fmt::vtkjs;
    if (ends_with(l, ".slc")) return Fmt::slc;
    if (ends_with(l, ".dat")) return Fmt::voreen_dat;
    if (ends_with(l, ".raw")) return Fmt::raw;
    if (ends_with(l, ".npy")) return Fmt::npy;
    return Fmt::unknown;
}

Fmt by_content(const std::string& path, const RawOptions& raw) {
    const std::string h = read_file_prefix(path, 4096);
    if (h.size() >= 132 && h.compare(128, 4, "DICM") == 0) return Fmt::dicom;
    if (h.rfind("NRRD", 0) == 0) return Fmt::nrrd;
    if (h.rfind("\x93NUMPY", 0) == 0) return Fmt::npy;
    if (to_lower(h.substr(0, 14)) == "# vtk datafile") return Fmt::vtk_legacy;
    if (h.rfind("<?xml", 0) == 0 || h.rfind("<VTKFile", 0) == 0) return Fmt::vti;
    if (h.rfind("11111", 0) == 0) return Fmt::slc;
    if (h.size() >= 348) {
        std::int32_t s;
        std::memcpy(&s, h.data(), 4);
        if (s == 348 || s == static_cast<std::int32_t>(__builtin_bswap32(348u))) return Fmt::nifti;
    }
    if (is_gzip_magic(h.data(), h.size())) return Fmt::nifti;  // the only gzipped single-file volume we know
    if (h.find("ElementDataFile") != std::string::npos) return Fmt::metaimage;
    if (h.find("ObjectFileName") != std::string::npos) return Fmt::voreen_dat;
    if (h.find("vtkImageData") != std::string::npos) return Fmt::vtkjs;
    if ((raw.dims && raw.type) || parse_raw_name(path)) return Fmt::raw;
    return Fmt::unknown;
}

// The input itself under a confined policy (a symbolic link out of the archive is refused before
// anything is read); a vtk-js directory's index.json too.
Fmt detect(const std::string& path, const RawOptions& raw) {
    check_reference(raw.references, path, path);
    std::error_code ec;
    if (fs::is_directory(path, ec)) {
        if (is_zarr_input(path)) return Fmt::zarr;
        check_reference(raw.references, path, (fs::path(path) / "index.json").string());
        if (fs::is_regular_file(fs::path(path) / "index.json", ec)) return Fmt::vtkjs;
        if (looks_like_dicom(path, std::size_t(-1))) return Fmt::dicom;
        throw IoError(path + ": is a directory, expected a volume file (or a vtk-js directory with index.json, a DICOM series, or a Zarr store)");
    }
    if (is_hdf5_input(path)) return Fmt::hdf5;  // FILE.h5 or FILE.h5:/DATASET
    if (!fs::exists(path, ec)) throw IoError(path + ": cannot open: No such file or directory");
    if (to_lower(fs::path(path).filename().string()) == "dicomdir") return Fmt::dicom;
    if (fs::path(path).filename() == ".zarray") return Fmt::zarr;
    const Fmt e = by_extension(path);
    if (e != Fmt::unknown) return e;
    const Fmt c = by_content(path, raw);
    if (c == Fmt::unknown)
        throw FormatError(path + ": unrecognized volume format (no known extension or magic; for raw data give dims and type)");
    return c;
}

const char* format_name(Fmt f) {
    switch (f) {
        case Fmt::raw: return "raw";
        case Fmt::npy: return "npy";
        case Fmt::nrrd: return "nrrd";
        case Fmt::metaimage: return "metaimage";
        case Fmt::vtk_legacy: return "vtk-legacy";
        case Fmt::vti: return "vti";
        case Fmt::vtkjs: return "vtkjs";
        case Fmt::slc: return "slc";
        case Fmt::nifti: return "nifti";
        case Fmt::voreen_dat: return "voreen-dat";
        case Fmt::dicom: return "dicom";
        case Fmt::zarr: return "zarr";
        case Fmt::hdf5: return "hdf5";
        case Fmt::unknown: break;
    }
    return "unknown";
}

// detect, then RawOptions::array refused for a format of one unnamed array (InvalidArgument).
Fmt detect_reading(const std::string& path, const RawOptions& raw) {
    const Fmt f = detect(path, raw);
    if (f != Fmt::vti && f != Fmt::vtk_legacy && f != Fmt::vtkjs && f != Fmt::hdf5) refuse_array_choice(raw.array, path, format_name(f));
    if (f != Fmt::zarr && raw.resolution_level != 0)
        throw InvalidArgument(path + ": a " + std::string(format_name(f)) +
                              " volume has one resolution: --resolution-level applies to OME-Zarr images (multiscales)");
    return f;
}

// A header's plan, its data files checked against the policy before any is opened.
PayloadPlan confined(PayloadPlan plan, const std::string& header, const ReferencePolicy& refs) {
    check_references(refs, header, plan.files);
    return plan;
}

}  // namespace

namespace {
// An allocation that fails while reading names the file (every error names the file).
template <class F>
Volume naming_out_of_memory(const std::string& path, F&& read) {
    try {
        return read();
    } catch (const std::bad_alloc&) {
        throw IoError(path + ": out of memory while reading the volume");
    }
}
Volume read_volume_unnamed(const std::string& path, const RawOptions& raw);
Volume map_volume_unnamed(const std::string& path, const RawOptions& raw);
}  // namespace

Volume read_volume(const std::string& path, const RawOptions& raw) {
    return naming_out_of_memory(path, [&] { return read_volume_unnamed(path, raw); });
}

Volume map_volume(const std::string& path, const RawOptions& raw) {
    return naming_out_of_memory(path, [&] { return map_volume_unnamed(path, raw); });
}

namespace {

Volume read_volume_unnamed(const std::string& path, const RawOptions& raw) {
    switch (detect_reading(path, raw)) {
        case Fmt::raw: return read_payload(confined(plan_raw(path, raw), path, raw.references));
        case Fmt::npy: return read_payload(plan_npy(path, raw));
        case Fmt::nrrd: return read_payload(confined(plan_nrrd(path), path, raw.references));
        case Fmt::metaimage: return read_payload(confined(plan_metaimage(path), path, raw.references));
        case Fmt::vtk_legacy: return read_vtk_legacy(path, raw.array);
        case Fmt::vti: return read_vti(path, raw.array);
        case Fmt::vtkjs: return read_vtkjs_image(path, raw.references, raw.array);
        case Fmt::slc: return read_slc(path);
        case Fmt::nifti: return read_nifti(path, raw.references);
        case Fmt::voreen_dat: return read_payload(confined(plan_voreen_dat(path), path, raw.references));
        case Fmt::dicom: return read_dicom_series(open_dicom_series(path, raw.series, raw.references));
        case Fmt::zarr: return read_zarr(path, raw);
        case Fmt::hdf5: return read_hdf5(path, raw);
        case Fmt::unknown: break;
    }
    throw FormatError(path + ": unrecognized volume format");
}

Volume map_volume_unnamed(const std::string& path, const RawOptions& raw) {
    switch (detect_reading(path, raw)) {
        case Fmt::raw: return read_payload(confined(plan_raw(path, raw), path, raw.references), true);
        case Fmt::npy: return read_payload(plan_npy(path, raw), true);
        case Fmt::nrrd: return read_payload(confined(plan_nrrd(path), path, raw.references), true);
        case Fmt::metaimage: return read_payload(confined(plan_metaimage(path), path, raw.references), true);
        case Fmt::voreen_dat: return read_payload(confined(plan_voreen_dat(path), path, raw.references), true);
        default: return read_volume_unnamed(path, raw);
    }
}

}  // namespace

namespace {
// The formats map_volume may map: their info says whether it does.
VolumeInfo mappable_info(const PayloadPlan& plan) {
    VolumeInfo i = info_from_plan(plan);
    i.maps = payload_maps(plan);
    return i;
}
}  // namespace

// A DICOM series as a VolumeInfo: its files, its transfer syntax, the series read and the others.
static VolumeInfo dicom_info(const DicomSeries& s) {
    VolumeInfo i;
    i.format = "dicom";
    i.grid = s.grid;
    i.type = s.type;
    i.frame = s.frame;
    i.length_unit = "mm";  // (PS3.3: Pixel Spacing, Image Position and Slice Thickness are in mm)
    i.value_unit = value_unit_text(s.value_unit);
    std::vector<std::string> syntaxes;
    for (const auto& h : s.slices) {
        i.data_files.push_back(h.file);
        if (std::find(syntaxes.begin(), syntaxes.end(), h.transfer_syntax) == syntaxes.end()) syntaxes.push_back(h.transfer_syntax);
    }
    i.encoding = "transfer syntax";
    for (std::size_t k = 0; k < syntaxes.size(); ++k) i.encoding += (k ? ", " : " ") + escape_field(syntaxes[k]);
    if (s.rescaled) i.encoding += "; Rescale Slope/Intercept applied per slice";
    for (std::size_t k = 0; k < s.series.size(); ++k)
        if (s.series[k].uid == s.uid) {
            i.series = std::to_string(k + 1) + " of " + std::to_string(s.series.size()) + ": " + describe_dicom_series(s.series[k]);
            for (std::size_t o = 0; o < s.series.size(); ++o)
                if (o != k) i.series += "; also " + std::to_string(o + 1) + ") " + describe_dicom_series(s.series[o]);
        }
    return i;
}

VolumeInfo probe_volume(const std::string& path, const RawOptions& raw) {
    switch (detect_reading(path, raw)) {
        case Fmt::raw: return mappable_info(confined(plan_raw(path, raw), path, raw.references));
        case Fmt::npy: return mappable_info(plan_npy(path, raw));
        case Fmt::nrrd: return mappable_info(confined(plan_nrrd(path), path, raw.references));
        case Fmt::metaimage: return mappable_info(confined(plan_metaimage(path), path, raw.references));
        case Fmt::voreen_dat: return mappable_info(confined(plan_voreen_dat(path), path, raw.references));
        case Fmt::vtk_legacy: return probe_vtk_legacy(path, raw.array);
        case Fmt::vti: return probe_vti(path, raw.array);
        case Fmt::vtkjs: return probe_vtkjs_image(path, raw.references, raw.array);
        case Fmt::slc: return probe_slc(path);
        case Fmt::nifti: return probe_nifti(path, raw.references);
        case Fmt::dicom: return dicom_info(open_dicom_series(path, raw.series, raw.references));
        case Fmt::zarr: return probe_zarr(path, raw);
        case Fmt::hdf5: return probe_hdf5(path, raw);
        case Fmt::unknown: break;
    }
    throw FormatError(path + ": unrecognized volume format");
}

VolumeInfo prove_volume(const std::string& path, const RawOptions& raw) {
    const Fmt f = detect_reading(path, raw);
    switch (f) {
        case Fmt::raw: prove_payload(confined(plan_raw(path, raw), path, raw.references)); break;
        case Fmt::npy: prove_payload(plan_npy(path, raw)); break;
        case Fmt::nrrd: prove_payload(confined(plan_nrrd(path), path, raw.references)); break;
        case Fmt::metaimage: prove_payload(confined(plan_metaimage(path), path, raw.references)); break;
        case Fmt::voreen_dat: prove_payload(confined(plan_voreen_dat(path), path, raw.references)); break;
        case Fmt::vtk_legacy: {  // every point array listed (the values of the others skipped)
            const PayloadPlan plan = plan_vtk_legacy(path, raw.array, /*list_all=*/true);
            prove_payload(plan);
            return info_from_plan(plan);
        }
        case Fmt::vtkjs: prove_payload(plan_vtkjs_image(path, raw.references, raw.array)); break;
        case Fmt::vti: prove_vti(path, raw.array); break;
        case Fmt::slc: prove_slc(path); break;
        case Fmt::nifti: prove_nifti(path, raw.references); break;
        case Fmt::zarr: return prove_zarr(path, raw);
        case Fmt::hdf5: return prove_hdf5(path, raw);
        case Fmt::dicom: {  // every slice decoded through one reused buffer
            const DicomSeries s = open_dicom_series(path, raw.series, raw.references);
            std::vector<std::byte> slice(static_cast<std::size_t>(s.grid.dims[0] * s.grid.dims[1]) * sample_size(s.type)), scratch;
            for (std::int64_t k = 0; k < s.grid.dims[2]; ++k) read_dicom_series_slice(s, k, slice.data(), scratch);
            return dicom_info(s);
        }
        case Fmt::unknown: throw FormatError(path + ": unrecognized volume format");
    }
    return probe_volume(path, raw);
}

std::uint64_t decoded_bytes(const VolumeInfo& vi, const std::string& path) {
    return checked_mul(static_cast<std::uint64_t>(vi.grid.voxel_count()), sample_size(vi.type),
                       path + ": decoded size (" + dims_string(vi.grid) + ")");
}

bool is_dicom_input(const std::string& path, const RawOptions& raw) {
    try {
        return detect(path, raw) == Fmt::dicom;
    } catch (const std::exception&) {
        return false;
    }
}

bool looks_like_volume(const std::string& path) {
    if (is_hdf5_input(path)) return true;
    std::error_code ec;
    if (fs::is_directory(path, ec))
        return fs::is_regular_file(fs::path(path) / "index.json", ec) || looks_like_zarr(path) || looks_like_dicom(path);
    if (fs::path(path).filename() == ".zarray") return true;
    const Fmt e = by_extension(path);
    if (e == Fmt::unknown) return looks_like_dicom(path);
    if (e == Fmt::npy) return npy_ndim(path) == 3;  // a 2-D .npy is a point set
    if (e == Fmt::vtkjs || e == Fmt::voreen_dat) {
        // .json only when it is a vtk-js image index; .dat only when it is a Voreen sidecar
        try {
            if (!fs::is_regular_file(path, ec)) return false;
            const std::string h = read_file_prefix(path, 1 << 16);
            return e == Fmt::vtkjs ? h.find("vtkImageData") != std::string::npos
                                   : h.find("ObjectFileName") != std::string::npos;
        } catch (const IoError&) {
            return false;
        }
    }
    return true;
}

}  // namespace meshless
