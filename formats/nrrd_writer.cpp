#include "formats/nrrd_writer.hpp"

#include <cstdio>

#include "formats/atomic_file.hpp"

namespace meshless {

namespace {
const char* nrrd_type(SampleType t) {
    switch (t) {
        case SampleType::u8: return "uint8";
        case SampleType::i16: return "int16";
        case SampleType::u16: return "uint16";
        case SampleType::f32: break;
    }
    return "float";
}
}  // namespace

std::string nrrd_header(const GridSpec& g, SampleType type, const std::string& comment) {
    char buf[1024];
    std::string h = "NRRD0004\n";
    if (!comment.empty()) h += "# " + comment + "\n";
    h += std::string("type: ") + nrrd_type(type) + "\ndimension: 3\nspace dimension: 3\n";
    std::snprintf(buf, sizeof buf, "sizes: %lld %lld %lld\n", static_cast<long long>(g.dims[0]),
                  static_cast<long long>(g.dims[1]), static_cast<long long>(g.dims[2]));
    h += buf;
    std::snprintf(buf, sizeof buf, "space directions: (%.17g,0,0) (0,%.17g,0) (0,0,%.17g)\n", g.spacing[0], g.spacing[1],
                  g.spacing[2]);
    h += buf;
    std::snprintf(buf, sizeof buf, "space origin: (%.17g,%.17g,%.17g)\n", g.origin[0], g.origin[1], g.origin[2]);
    h += buf;
    h += "endian: little\nencoding: raw\n\n";
    return h;
}

void write_nrrd(const Volume& v, const std::string& path, const std::string& comment) {
    AtomicFile f(path);
    f.write(nrrd_header(v.grid, v.type, comment));
    f.write(v.bytes.data(), v.bytes.size());
    f.commit();
}

}  // namespace meshless
