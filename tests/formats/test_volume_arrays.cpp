// The point array of a multi-array volume (RawOptions::array): VTK XML .vti, VTK legacy .vtk and
// vtk.js files holding several arrays, written here by hand. The default is what the readers always
// read (the active scalars where the file names them, else the first array); a named array reads
// that array's values; a missing name lists the arrays; the formats of one unnamed array refuse a name.
#include <catch2/catch.hpp>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "formats/format_test_util.hpp"
#include "formats/volume_reader.hpp"
#include "kernels/errors.hpp"
#include "test_paths.hpp"

using namespace meshless;
using namespace meshless::test;
namespace fs = std::filesystem;

namespace {

constexpr int kCount = 5 * 4 * 3;

// Array `a` of the test files: value a * 1000 + index (exact in float32 and in every type used).
double value(int a, int idx) { return a * 1000.0 + idx; }

std::string ascii_values(int a, int per_point = 1) {
    std::string s;
    for (int i = 0; i < kCount; ++i)
        for (int c = 0; c < per_point; ++c) s += std::to_string(static_cast<long long>(value(a, i))) + (i % 10 == 9 ? "\n" : " ");
    return s + "\n";
}

// The values read, as doubles.
std::vector<double> values(const Volume& v) {
    std::vector<double> out;
    const VolumeView view = v.view();
    for (std::int64_t i = 0; i < v.grid.voxel_count(); ++i) out.push_back(view.at(i));
    return out;
}
std::vector<double> expected(int a) {
    std::vector<double> out;
    for (int i = 0; i < kCount; ++i) out.push_back(value(a, i));
    return out;
}

RawOptions named(const std::string& name) {
    RawOptions r;
    r.array = name;
    return r;
}

std::string message_of(const std::string& path, const RawOptions& raw) {
    try {
        (void)read_volume(path, raw);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_CASE("vti: --array reads the named point array, the default is the active scalars, else the first", "[formats][arrays]") {
    TempDir dir("arrays-vti");
    // three point arrays, ascii: a (Float32), b (Int16), v (3 components), and the active-scalars variant
    const auto doc = [&](const std::string& scalars) {
        return "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
               "<ImageData WholeExtent=\"0 4 0 3 0 2\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n<Piece Extent=\"0 4 0 3 0 2\">\n"
               "<PointData" + scalars + ">\n"
               "<DataArray type=\"Float32\" Name=\"a\" format=\"ascii\">\n" + ascii_values(1) + "</DataArray>\n"
               "<DataArray type=\"Float64\" Name=\"v\" NumberOfComponents=\"3\" format=\"ascii\">\n" + ascii_values(9, 3) + "</DataArray>\n"
               "<DataArray type=\"Int16\" Name=\"b\" format=\"ascii\">\n" + ascii_values(2) + "</DataArray>\n"
               "</PointData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
    };
    const std::string first = (dir / "first.vti").string(), active = (dir / "active.vti").string();
    write_file(first, doc(""));
    write_file(active, doc(" Scalars=\"b\""));

    CHECK(values(read_volume(first)) == expected(1));   // no Scalars: the first array
    CHECK(values(read_volume(active)) == expected(2));  // Scalars="b": b, though it is the third
    CHECK(values(read_volume(active, named("a"))) == expected(1));
    CHECK(values(read_volume(first, named("b"))) == expected(2));
    CHECK(read_volume(first, named("b")).type == SampleType::i16);
    CHECK(values(map_volume(first, named("b"))) == expected(2));

    const VolumeInfo i = probe_volume(active);
    REQUIRE(i.arrays.size() == 3);
    CHECK(i.arrays[0].name == "a");
    CHECK(i.arrays[0].type == "float32");
    CHECK(i.arrays[1].name == "v");
    CHECK(i.arrays[1].type == "float64");
    CHECK(i.arrays[1].components == 3);
    CHECK(i.arrays[2].type == "int16");
    CHECK(i.default_array == 2);
    CHECK(i.read_array == 2);
    const VolumeInfo ia = prove_volume(active, named("a"));
    CHECK(ia.default_array == 2);
    CHECK(ia.read_array == 0);
    CHECK(ia.type == SampleType::f32);

    // a name the file lacks: one line naming the file and its arrays
    const std::string m = message_of(first, named("nope"));
    CHECK(m.rfind(first + ": no point array named 'nope'", 0) == 0);
    CHECK(m.find("'a' (float32), 'v' (float64, 3 components), 'b' (int16)") != std::string::npos);
    CHECK(m.find('\n') == std::string::npos);
    CHECK_THROWS_AS(probe_volume(first, named("nope")), FormatError);
    // a name the file has, of several components: refused as before
    CHECK_THROWS_WITH(read_volume(first, named("v")), Catch::Contains("3 components"));
    // names are escaped in the message
    CHECK(message_of(first, named("x\x1b[2Jy")).find("x\\x1b[2Jy") != std::string::npos);
}

TEST_CASE("vti: --array with appended raw data reads the array at its offset", "[formats][arrays]") {
    TempDir dir("arrays-vti-app");
    std::string payload;
    for (int a : {1, 2}) {
        std::vector<float> f(kCount);
        for (int i = 0; i < kCount; ++i) f[i] = static_cast<float>(value(a, i));
        const std::uint32_t n = kCount * 4;
        payload.append(reinterpret_cast<const char*>(&n), 4);
        payload.append(reinterpret_cast<const char*>(f.data()), n);
    }
    const std::string p = (dir / "app.vti").string();
    write_file(p, "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
                  "<ImageData WholeExtent=\"0 4 0 3 0 2\" Origin=\"0 0 0\" Spacing=\"1 1 1\">\n<Piece Extent=\"0 4 0 3 0 2\">\n"
                  "<PointData Scalars=\"one\">\n"
                  "<DataArray type=\"Float32\" Name=\"one\" format=\"appended\" offset=\"0\"/>\n"
                  "<DataArray type=\"Float32\" Name=\"two\" format=\"appended\" offset=\"" + std::to_string(4 + kCount * 4) + "\"/>\n"
                  "</PointData>\n</Piece>\n</ImageData>\n<AppendedData encoding=\"raw\">\n_" + payload + "\n</AppendedData>\n</VTKFile>\n");
    CHECK(values(read_volume(p)) == expected(1));
    CHECK(values(read_volume(p, named("two"))) == expected(2));
    CHECK(prove_volume(p, named("two")).read_array == 1);
}

TEST_CASE("vtk legacy: --array reads a later SCALARS or FIELD array, skipping the values before it", "[formats][arrays]") {
    TempDir dir("arrays-vtk");
    for (bool binary : {true, false}) {
        INFO((binary ? "BINARY" : "ASCII"));
        // a (float), v (VECTORS), b (short, with its LOOKUP_TABLE line), a lookup table section,
        // FIELD with c (3 components) and d (unsigned_char)
        const auto data = [&](StoredType t, int a, int per_point) {
            if (!binary) return ascii_values(a, per_point);
            std::vector<std::byte> out;
            for (int i = 0; i < kCount; ++i)
                for (int c = 0; c < per_point; ++c) {
                    const double x = value(a, i);
                    switch (t) {
                        case StoredType::f32: put_value(out, static_cast<float>(x), true); break;
                        case StoredType::i16: put_value(out, static_cast<std::int16_t>(x), true); break;
                        case StoredType::u8: put_value(out, static_cast<std::uint8_t>(x), true); break;
                        default: put_value(out, x, true); break;
                    }
                }
            return std::string(reinterpret_cast<const char*>(out.data()), out.size()) + "\n";
        };
        std::string table = binary ? std::string(2 * 4, '\x7f') + "\n" : "0 0 0 1\n1 1 1 1\n";
        const std::string text = std::string("# vtk DataFile Version 3.0\nseveral arrays\n") + (binary ? "BINARY" : "ASCII") +
                                 "\nDATASET STRUCTURED_POINTS\nDIMENSIONS 5 4 3\nSPACING 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 60\n"
                                 "SCALARS a float 1\nLOOKUP_TABLE default\n" + data(StoredType::f32, 1, 1) +
                                 "VECTORS v double\n" + data(StoredType::f64, 9, 3) +
                                 "SCALARS b short\nLOOKUP_TABLE mytable\n" + data(StoredType::i16, 2, 1) +
                                 "LOOKUP_TABLE mytable 2\n" + table +
                                 "FIELD FieldData 2\nc 3 60 float\n" + data(StoredType::f32, 7, 3) +
                                 "d 1 60 unsigned_char\n" + data(StoredType::u8, 0, 1) +
                                 "CELL_DATA 24\nSCALARS cells float\nLOOKUP_TABLE default\n";
        const std::string p = (dir / (binary ? "b.vtk" : "a.vtk")).string();
        write_file(p, text);
        CHECK(values(read_volume(p)) == expected(1));
        CHECK(values(read_volume(p, named("a"))) == expected(1));
        CHECK(values(read_volume(p, named("b"))) == expected(2));
        CHECK(read_volume(p, named("b")).type == SampleType::i16);
        CHECK(values(read_volume(p, named("d"))) == expected(0));
        CHECK_THROWS_WITH(read_volume(p, named("c")), Catch::Contains("3 components"));
        CHECK_THROWS_WITH(read_volume(p, named("v")), Catch::Contains("3 components"));
        // probe stops at the array read; prove (meshless info) lists them all, up to CELL_DATA
        CHECK(probe_volume(p).arrays.size() == 1);
        const VolumeInfo i = prove_volume(p, named("b"));
        REQUIRE(i.arrays.size() == 5);
        CHECK(i.arrays[0].name == "a");
        CHECK(i.arrays[1].name == "v");
        CHECK(i.arrays[1].components == 3);
        CHECK(i.arrays[2].name == "b");
        CHECK(i.arrays[2].type == "int16");
        CHECK(i.arrays[3].name == "c");
        CHECK(i.arrays[4].type == "uint8");
        CHECK(i.default_array == 0);
        CHECK(i.read_array == 2);
        const std::string m = message_of(p, named("cells"));
        CHECK(m.rfind(p + ": no point array named 'cells'", 0) == 0);
        CHECK(m.find("'a' (float32), 'v' (float64, 3 components), 'b' (int16), 'c' (float32, 3 components), 'd' (uint8)") !=
              std::string::npos);
    }
    // the first SCALARS of several components is refused by default, as always, and skipped for a name
    write_file((dir / "m.vtk").string(), "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 5 4 3\n"
                                         "POINT_DATA 60\nSCALARS rgb float 3\n" + ascii_values(5, 3) +
                                         "SCALARS one int\n" + ascii_values(1));
    CHECK_THROWS_WITH(read_volume((dir / "m.vtk").string()), Catch::Contains("unsupported SCALARS with 3 components"));
    CHECK(values(read_volume((dir / "m.vtk").string(), named("one"))) == expected(1));
    // a file that ends within the values of an array before the named one
    write_file((dir / "t.vtk").string(), "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 5 4 3\n"
                                         "POINT_DATA 60\nSCALARS one int\n1 2 3\n");
    CHECK_THROWS_WITH(read_volume((dir / "t.vtk").string(), named("two")), Catch::Contains("ends within the values of SCALARS 'one'"));
    // listing (meshless info) past the array read: its truncation is the payload's own error, as before
    CHECK_THROWS_AS(prove_volume((dir / "t.vtk").string()), FormatError);
    CHECK(message_of((dir / "t.vtk").string(), {}).find("ends within") == std::string::npos);
    // the same for a named array, the last, truncated: listing reports the payload's error as reading does
    const std::string t2 = (dir / "t2.vtk").string();
    write_file(t2, "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 5 4 3\n"
                   "POINT_DATA 60\nSCALARS one int\n" + ascii_values(1) + "SCALARS two int\n1 2 3\n");
    const std::string read_error = message_of(t2, named("two"));
    CHECK(!read_error.empty());
    CHECK(read_error.find("ends within") == std::string::npos);
    CHECK_THROWS_WITH(prove_volume(t2, named("two")), read_error);
}

TEST_CASE("vtk.js: --array reads the named array, the default is the setScalars one, else the first", "[formats][arrays]") {
    TempDir dir("arrays-vtkjs");
    fs::create_directories(dir / "v.vti" / "data");
    for (int a : {1, 2}) {
        std::vector<float> f(kCount);
        for (int i = 0; i < kCount; ++i) f[i] = static_cast<float>(value(a, i));
        write_file((dir / "v.vti" / "data" / ("id" + std::to_string(a))).string(),
                   std::string(reinterpret_cast<const char*>(f.data()), f.size() * 4));
    }
    const auto index = [&](bool registered) {
        const auto arr = [](int a, const char* reg) {
            return std::string("{\"data\": {\"numberOfComponents\": 1, \"name\": \"f") + std::to_string(a) +
                   "\", \"vtkClass\": \"vtkDataArray\", \"dataType\": \"Float32Array\", \"size\": 60, \"ref\": {" + reg +
                   "\"encode\": \"LittleEndian\", \"basepath\": \"data\", \"id\": \"id" + std::to_string(a) + "\"}}}";
        };
        return std::string("{\"vtkClass\": \"vtkImageData\", \"spacing\": [1, 1, 1], \"origin\": [0, 0, 0], \"extent\": [0, 4, 0, 3, 0, 2],"
                           " \"pointData\": {\"vtkClass\": \"vtkDataSetAttributes\", \"arrays\": [") +
               arr(1, registered ? "\"registration\": \"addArray\", " : "") + ", " +
               arr(2, registered ? "\"registration\": \"setScalars\", " : "") + "]}}";
    };
    write_file((dir / "v.vti" / "index.json").string(), index(true));
    const std::string p = (dir / "v.vti").string();
    CHECK(values(read_volume(p)) == expected(2));
    CHECK(values(read_volume(p, named("f1"))) == expected(1));
    const VolumeInfo i = prove_volume(p, named("f1"));
    REQUIRE(i.arrays.size() == 2);
    CHECK(i.arrays[0].type == "float32");
    CHECK(i.default_array == 1);
    CHECK(i.read_array == 0);
    CHECK_THROWS_WITH(read_volume(p, named("f3")), Catch::Contains("'f1' (float32), 'f2' (float32)"));
    write_file((dir / "v.vti" / "index.json").string(), index(false));
    CHECK(values(read_volume(p)) == expected(1));
    CHECK(values(read_volume(p, named("f2"))) == expected(2));
}

TEST_CASE("array choice: the formats of one unnamed array refuse a name (InvalidArgument)", "[formats][arrays]") {
    TempDir dir("arrays-single");
    const std::string raw = (dir / "v_5x4x3_uint8.raw").string();
    write_file(raw, std::string(kCount, '\1'));
    const std::string nrrd = (dir / "v.nrrd").string();
    write_file(nrrd, "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 5 4 3\nencoding: raw\n\n" + std::string(kCount, '\1'));
    for (const std::string& p : {raw, nrrd}) {
        INFO(p);
        CHECK_THROWS_AS(read_volume(p, named("a")), InvalidArgument);
        CHECK_THROWS_AS(map_volume(p, named("a")), InvalidArgument);
        CHECK_THROWS_AS(probe_volume(p, named("a")), InvalidArgument);
        CHECK_THROWS_WITH(prove_volume(p, named("a")), Catch::Contains("holds one unnamed array"));
        CHECK(probe_volume(p).arrays.empty());
    }
}
