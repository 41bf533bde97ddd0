#include "formats/raw_volume.hpp"

#include <filesystem>
#include <regex>

#include "formats/binary_file.hpp"
#include "formats/text_header.hpp"
#include "formats/voreen_dat.hpp"
#include "formats/reference_policy.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace fs = std::filesystem;

std::optional<RawNameLayout> parse_raw_name(const std::string& path) {
    // (any bytes before the layout, line breaks included: ECMAScript's '.' matches neither \n nor \r)
    static const std::regex re(R"([\s\S]*_(\d+)x(\d+)x(\d+)_([A-Za-z0-9]+)\.[A-Za-z0-9]+)");
    const std::string name = fs::path(path).filename().string();
    std::smatch m;
    if (!std::regex_match(name, m, re)) return std::nullopt;
    const auto t = parse_stored_type(m[4].str());
    if (!t) return std::nullopt;
    RawNameLayout l{};
    for (int a = 0; a < 3; ++a) {
        try {
            l.dims[a] = std::stoll(m[a + 1].str());
        } catch (...) {
            return std::nullopt;
        }
        if (l.dims[a] < 1) return std::nullopt;
    }
    l.type = *t;
    return l;
}

namespace {
// A .dat in the directory describing this raw file: same stem first, then any .dat naming it. Under a
// confined policy a .dat resolving outside its root (a symbolic link) is refused, not read.
std::optional<std::string> find_sidecar(const std::string& path, const ReferencePolicy& refs) {
    const fs::path p(path);
    fs::path same = p;
    same.replace_extension(".dat");
    std::error_code ec;
    if (fs::is_regular_file(same, ec)) {
        check_reference(refs, path, same.string());
        return same.string();
    }
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const std::string fname = p.filename().string();
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        if (e.path().extension() != ".dat" || !e.is_regular_file(ec) || e.file_size(ec) > 4096) continue;
        if (refs.confined() && !resolves_inside(e.path().string(), refs.root)) continue;
        const std::string text = read_file_prefix(e.path().string(), 4096);
        for (const auto& line : split_lines(text)) {
            const auto c = line.find(':');
            if (c == std::string::npos) continue;
            if (to_lower(trim(line.substr(0, c))) == "objectfilename" &&
                fs::path(trim(line.substr(c + 1))).filename().string() == fname)
                return e.path().string();
        }
    }
    return std::nullopt;
}
}  // namespace

PayloadPlan plan_raw(const std::string& path, const RawOptions& opts) {
    regular_file_size(path);  // IoError for missing file or directory
    PayloadPlan plan;
    bool have_dims = false, have_type = false;
    if (const auto sidecar = find_sidecar(path, opts.references)) {
        plan = plan_voreen_dat(*sidecar);
        check_references(opts.references, *sidecar, plan.files);
        have_dims = have_type = true;
    } else if (const auto l = parse_raw_name(path)) {
        plan.grid.dims = l->dims;
        plan.type = l->type;
        have_dims = have_type = true;
    }
    plan.format = "raw";
    plan.files = {path};
    plan.exact_size = true;
    if (opts.dims) {
        for (int a = 0; a < 3; ++a)
            if ((*opts.dims)[a] < 1) throw InvalidArgument(path + ": raw dims must be >= 1");
        plan.grid.dims = *opts.dims;
        have_dims = true;
    }
    if (opts.type) {
        switch (*opts.type) {
            case SampleType::u8: plan.type = StoredType::u8; break;
            case SampleType::i16: plan.type = StoredType::i16; break;
            case SampleType::u16: plan.type = StoredType::u16; break;
            case SampleType::f32: plan.type = StoredType::f32; break;
        }
        have_type = true;
    }
    if (opts.big_endian) plan.big_endian = true;
    if (opts.spacing) {
        for (int a = 0; a < 3; ++a)
            if (!((*opts.spacing)[a] > 0)) throw InvalidArgument(path + ": raw spacing must be > 0");
        plan.grid.spacing = *opts.spacing;
    }
    if (!have_dims || !have_type)
        throw FormatError(path + ": raw volume without layout: name it name_XxYxZ_type.raw, add a .dat, or give "
                                 "dims and type");
    if (opts.spacing) validate_given_spacing(plan.grid, path);  // a spacing given, not read: the caller's fault
    return plan;
}

VolumeInfo probe_raw(const std::string& path, const RawOptions& opts) { return info_from_plan(plan_raw(path, opts)); }
Volume read_raw(const std::string& path, const RawOptions& opts) { return read_payload(plan_raw(path, opts)); }

}  // namespace meshless
