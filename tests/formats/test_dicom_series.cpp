// DICOM series through GDCM (formats/dicom_series.hpp): a CT-like series in shuffled file order
// equals its NRRD, backwards axes land in world order as the NRRD reader puts them, a compressed
// (RLE) series is refused, series are listed and chosen, and every defect is refused with its message.
// The series are written at test time with pydicom (tests/dicom_test_data.hpp).
#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "dicom_test_data.hpp"
#include "error_of.hpp"
#include "formats/dicom_series.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"

using namespace meshless;
using namespace meshless::test;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

bool same_samples(const Volume& a, const Volume& b) {
    return a.type == b.type && a.bytes.size() == b.bytes.size() && std::memcmp(a.bytes.data(), b.bytes.data(), a.bytes.size()) == 0;
}

void check_same_frame(const VolumeInfo& a, const VolumeInfo& b) {
    REQUIRE(a.frame);
    REQUIRE(b.frame);
    for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) CHECK(a.frame->axis[i][c] == Approx(b.frame->axis[i][c]).margin(1e-12));
}

}  // namespace

#if MESHLESS_DICOM

TEST_CASE("dicom: a CT series of 279 shuffled slices with per-slice rescale equals its NRRD", "[formats][dicom]") {
    if (!have_shared_data()) {
        WARN("shared data absent: skipping (the series is made from vtk_headsq/quarter)");
        return;
    }
    TempDir dir("dicom-ct");
    const auto ct = make_dicom_case("ct", dir);
    if (!ct) return;
    const Volume d = read_volume(ct->string());
    const Volume n = read_volume(ct->string() + ".nrrd");
    CHECK(d.grid.dims == std::array<std::int64_t, 3>{64, 60, 279});
    CHECK(d.grid == n.grid);
    CHECK(d.type == SampleType::f32);
    CHECK(same_samples(d, n));
    const VolumeInfo di = probe_volume(ct->string()), ni = probe_volume(ct->string() + ".nrrd");
    CHECK(di.format == "dicom");
    CHECK(di.data_files.size() == 279);
    CHECK(di.grid == ni.grid);
    CHECK(di.type == SampleType::f32);
    check_same_frame(di, ni);
    CHECK_THAT(di.series, Contains("CT head (quarter)") && Contains("279 slices"));
    CHECK_THAT(di.encoding, Contains("Rescale"));
    // one file of the series stands for its series
    const fs::path one = *fs::directory_iterator(*ct);
    CHECK(same_samples(read_volume(one.string()), n));
    CHECK(prove_volume(ct->string()).grid == n.grid);
}

TEST_CASE("dicom: backward column direction and normal are reversed to world order, as NRRD's", "[formats][dicom]") {
    TempDir dir("dicom-flip");
    const auto f = make_dicom_case("flipped", dir);
    if (!f) return;
    const Volume d = read_volume(f->string());
    const Volume n = read_volume(f->string() + ".nrrd");
    CHECK(d.type == SampleType::i16);
    CHECK(d.grid == n.grid);
    CHECK(d.grid.spacing == std::array<double, 3>{0.75, 0.5, 1.5});
    CHECK(same_samples(d, n));
    check_same_frame(probe_volume(f->string()), probe_volume(f->string() + ".nrrd"));
}

TEST_CASE("dicom: a compressed (RLE Lossless) series reads as the uncompressed one, a damaged stream fails in one line", "[formats][dicom]") {
    // GDCM's decoders assert on damaged streams (fuzz_dicom found RLECodec::Decode aborting): they
    // run in a child process (formats/isolated_call.hpp), so a damaged slice fails that file only
    TempDir dir("dicom-rle");
    const auto r = make_dicom_case("rle", dir);
    if (!r) return;
    const Volume plain = read_volume((*r / "plain").string());
    const Volume rle = read_volume((*r / "rle").string());
    CHECK(plain.grid.voxel_count() > 0);
    CHECK(rle.grid == plain.grid);
    CHECK(rle.type == plain.type);
    CHECK(std::equal(rle.bytes.data(), rle.bytes.data() + rle.bytes.size(), plain.bytes.data(), plain.bytes.data() + plain.bytes.size()));
    CHECK(probe_volume((*r / "rle").string()).encoding.find("1.2.840.10008.1.2.5") != std::string::npos);
    // the RLE header of one slice damaged: its segment count and offsets point past the data
    const fs::path slice = *r / "rle" / "slice0003.dcm";
    std::string bytes;
    {
        std::ifstream in(slice, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    const std::string original = bytes;
    // the first fragment (after the empty offset table item) starts with the 64-byte RLE header
    const std::string item("\xfe\xff\x00\xe0", 4);
    const std::size_t table = bytes.find(item);
    REQUIRE(table != std::string::npos);
    const std::size_t frag = bytes.find(item, table + 8);
    REQUIRE(frag != std::string::npos);
    const std::size_t header = frag + 8;
    REQUIRE(bytes.size() > header + 64);
    for (int k = 0; k < 16; ++k) bytes.replace(header + 4 * k, 4, k == 0 ? std::string("\x0f\0\0\0", 4) : std::string("\xf0\xff\xff\x0f", 4));
    {
        std::ofstream out(slice, std::ios::binary);
        out << bytes;
    }
    const std::string e = error_of([&] { read_volume((*r / "rle").string()); });
    INFO(e);
    CHECK(e.find(slice.string() + ": RLE pixel data at byte ") != std::string::npos);
    CHECK(e.find("15 segments, 2 expected") != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
    // two segments at one offset: GDCM decodes that without a word (a wrong slice); the check refuses it
    bytes = original;
    bytes.replace(header + 8, 4, bytes.substr(header + 4, 4));
    {
        std::ofstream out(slice, std::ios::binary);
        out << bytes;
    }
    const std::string same = error_of([&] { read_volume((*r / "rle").string()); });
    INFO(same);
    CHECK(same.find(slice.string() + ": RLE pixel data at byte ") != std::string::npos);
    CHECK(same.find("segment 2 at 64 (offsets must increase") != std::string::npos);
}

TEST_CASE("dicom: JPEG-LS, JPEG lossless and JPEG 2000 series (gdcmconv) read as the uncompressed one", "[formats][dicom]") {
    // the JPEG family is GDCM's to decode, each slice in a child process (formats/isolated_call.hpp)
    TempDir dir("dicom-jpeg");
    const auto r = make_dicom_case("rle", dir);
    if (!r) return;
    if (std::system("command -v gdcmconv >/dev/null 2>&1") != 0) {
        WARN("gdcmconv (libgdcm-tools) is not installed: skipping the JPEG-family series");
        return;
    }
    const Volume plain = read_volume((*r / "plain").string());
    for (const std::string codec : {"jpegls", "jpeg", "j2k"}) {
        INFO(codec);
        const fs::path out = dir / codec;
        fs::create_directories(out);
        for (const auto& e : fs::directory_iterator(*r / "plain")) {
            const std::string cmd = "gdcmconv --" + codec + " '" + e.path().string() + "' '" + (out / e.path().filename()).string() + "'";
            REQUIRE(std::system(cmd.c_str()) == 0);
        }
        const Volume v = read_volume(out.string());
        CHECK(v.grid == plain.grid);
        CHECK(v.type == plain.type);
        CHECK(std::equal(v.bytes.data(), v.bytes.data() + v.bytes.size(), plain.bytes.data(), plain.bytes.data() + plain.bytes.size()));
        CHECK(probe_volume(out.string()).encoding.find("1.2.840.10008.1.2.4.") != std::string::npos);
    }
}

TEST_CASE("dicom: a folder of two series is refused listing both, --series picks each", "[formats][dicom]") {
    TempDir dir("dicom-two");
    const auto t = make_dicom_case("two-series", dir);
    if (!t) return;
    const std::string p = t->string();
    const std::string e = error_of([&] { read_volume(p); });
    CHECK_THAT(e, Contains(p + ": holds 2 series") && Contains("1.2.826.0.1.3680043.8.498.100 'first', 6 slices, 32 x 30") &&
                      Contains("1.2.826.0.1.3680043.8.498.200 'second', 5 slices, 16 x 16"));
    CHECK(e.find('\n') == std::string::npos);
    RawOptions r;
    r.series = "1";
    CHECK(read_volume(p, r).grid.dims == std::array<std::int64_t, 3>{32, 30, 6});
    r.series = "1.2.826.0.1.3680043.8.498.200";
    CHECK(read_volume(p, r).grid.dims == std::array<std::int64_t, 3>{16, 16, 5});
    r.series = "2";
    CHECK_THAT(probe_volume(p, r).series, Contains("2 of 2") && Contains("also 1)"));
    r.series = "3";
    CHECK_THAT(error_of<InvalidArgument>([&] { probe_volume(p, r); }), Contains("--series 3") && Contains("no such series"));
}

TEST_CASE("dicom: defects are refused with one line naming the folder and the fault", "[formats][dicom]") {
    TempDir dir("dicom-bad");
    const std::pair<const char*, const char*> cases[] = {
        {"tilt", "gantry tilt: slice positions run 11.31 degrees off the orientation normal"},
        {"gap", "missing slice: the step from slice0003.dcm to slice0004.dcm is 3 mm, 2 times the usual 1.5 mm"},
        {"duplicate", "duplicated slice: slice0003.dcm and slice0007.dcm are both at 4.5 mm"},
        {"uneven", "uneven spacing: steps of 1.5, 1.8 mm along the normal"},
        {"mixed-sizes", "mixed sizes: "},
        {"mixed-orientation", "mixed orientations: "},
        {"no-pixels", "slice0002.dcm holds no image (no Pixel Data)"},
    };
    for (const auto& [name, message] : cases) {
        INFO(name);
        const auto p = make_dicom_case(name, dir);
        if (!p) return;
        const std::string e = error_of([&] { probe_volume(p->string()); });
        CHECK_THAT(e, Contains(p->string() + ": ") && Contains(message));
        CHECK(e.find('\n') == std::string::npos);
    }
}

TEST_CASE("dicom: a truncated slice file fails the read naming the file", "[formats][dicom]") {
    TempDir dir("dicom-trunc");
    const auto p = make_dicom_case("truncated", dir);
    if (!p) return;
    const std::string e = error_of([&] { read_volume(p->string()); });
    CHECK_THAT(e, Catch::Matchers::StartsWith(p->string() + "/slice0005.dcm: ") && Contains("truncated"));
    CHECK(e.find('\n') == std::string::npos);
    CHECK_THAT(error_of([&] { prove_volume(p->string()); }), Contains("slice0005.dcm"));
}

TEST_CASE("dicom: detection by the DICM magic, folders and DICOMDIR", "[formats][dicom]") {
    TempDir dir("dicom-detect");
    const auto p = make_dicom_case("gap", dir);
    if (!p) return;
    CHECK(looks_like_volume(p->string()));
    CHECK(looks_like_volume((*p / "slice0000.dcm").string()));
    CHECK(is_dicom_input(p->string()));
    CHECK_FALSE(looks_like_volume(dir.path.string()));  // only the generator's log and a subfolder
    const fs::path named = dir / "IM0001";  // no extension: the magic says DICOM
    fs::copy_file(*p / "slice0000.dcm", named);
    CHECK(is_dicom_input(named.string()));
}

TEST_CASE("dicom: a DICOMDIR stands for the DICOM files under its folder", "[formats][dicom]") {
    TempDir dir("dicom-dicomdir");
    const auto p = make_dicom_case("flipped", dir);
    if (!p) return;
    const fs::path root = dir / "media";
    fs::create_directories(root / "A" / "B");
    for (const auto& e : fs::directory_iterator(*p)) fs::copy_file(e.path(), root / "A" / "B" / e.path().filename());
    {
        std::FILE* out = std::fopen((root / "DICOMDIR").string().c_str(), "wb");  // its records are not read
        REQUIRE(out);
        std::fclose(out);
    }
    CHECK(looks_like_volume((root / "DICOMDIR").string()));
    const Volume a = read_volume((root / "DICOMDIR").string());
    const Volume b = read_volume(p->string());
    CHECK(a.grid == b.grid);
    CHECK(same_samples(a, b));
}

#else

TEST_CASE("dicom: a build without GDCM refuses a DICOM input in one line", "[formats][dicom]") {
    TempDir dir("dicom-none");
    const fs::path f = dir / "slice.dcm";
    {
        std::string bytes(128, '\0');
        bytes += "DICM";
        bytes += std::string(64, '\0');
        std::FILE* out = std::fopen(f.string().c_str(), "wb");
        REQUIRE(out);
        std::fwrite(bytes.data(), 1, bytes.size(), out);
        std::fclose(out);
    }
    CHECK(looks_like_volume(f.string()));
    CHECK_THAT(error_of([&] { read_volume(f.string()); }), Contains("this build has no DICOM reader"));
}

#endif

#if MESHLESS_DICOM
// Debian's GDCM asserts (aborts the process) on malformed elements: formats/dicom_structure.hpp walks
// every file first. A slice cut at any byte is read or refused with a FormatError naming it.
TEST_CASE("dicom: a slice cut at any byte is refused, never aborts inside GDCM", "[formats][dicom]") {
    TempDir dir("dicom-cut");
    const auto p = make_dicom_case("gap", dir);
    if (!p) return;
    std::string bytes;
    {
        std::FILE* in = std::fopen((*p / "slice0000.dcm").string().c_str(), "rb");
        REQUIRE(in);
        char buf[4096];
        for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, in)) > 0;) bytes.append(buf, n);
        std::fclose(in);
    }
    REQUIRE(bytes.size() > 1000);
    int refused = 0;
    for (std::size_t n = 100; n < bytes.size(); n += n < 900 ? 1 : 29) {
        const fs::path d = dir / ("cut" + std::to_string(n));
        fs::create_directories(d);
        const fs::path f = d / "s.dcm";
        std::FILE* out = std::fopen(f.string().c_str(), "wb");
        REQUIRE(out);
        std::fwrite(bytes.data(), 1, n, out);
        std::fclose(out);
        const std::string e = error_of([&] { read_volume(f.string()); });
        INFO(n << ": " << e);
        CHECK(e.rfind(f.string() + ": ", 0) == 0);
        refused += e != "(nothing thrown)";
        fs::remove_all(d);
    }
    CHECK(refused > 800);
}
#endif

#if MESHLESS_DICOM
// GDCM allocates a value of the length a delimiter claims (fuzz_dicom: 2 GiB from the sequence delimiter
// that ends encapsulated pixel data): a delimiter's length must be 0, checked before GDCM reads the file.
TEST_CASE("dicom: a delimiter with a length is refused before GDCM allocates it", "[formats][dicom]") {
    TempDir dir("dicom-delim");
    const auto r = make_dicom_case("rle", dir);
    if (!r) return;
    const fs::path slice = *r / "rle" / "slice0000.dcm";
    std::string bytes;
    {
        std::ifstream in(slice, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    // the encapsulated pixel data ends with the sequence delimiter (FFFE,E0DD) and its zero length
    REQUIRE(bytes.size() > 8);
    REQUIRE(bytes.compare(bytes.size() - 8, 8, std::string("\xfe\xff\xdd\xe0\0\0\0\0", 8)) == 0);
    bytes.replace(bytes.size() - 4, 4, std::string("\xff\xff\x7f\x7f", 4));
    const fs::path bad = dir / "bad";
    fs::create_directories(bad);
    {
        std::ofstream out(bad / "s.dcm", std::ios::binary);
        out << bytes;
    }
    const std::string e = error_of([&] { probe_volume((bad / "s.dcm").string()); });
    CHECK(e.rfind((bad / "s.dcm").string() + ": ", 0) == 0);
    CHECK(e.find("delimiter (FFFE,E0DD) with a length of 2139095039 (0 expected)") != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
}
#endif
