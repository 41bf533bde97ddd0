#include "formats/reference_policy.hpp"

#include <filesystem>

#include "formats/text_header.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace fs = std::filesystem;

std::string resolved_path(const std::string& file) {
    std::error_code ec;
    fs::path a = fs::absolute(fs::path(file), ec);
    if (ec) a = fs::path(file);
    const fs::path c = fs::weakly_canonical(a, ec);
    return ec ? a.lexically_normal().string() : c.string();
}

bool resolves_inside(const std::string& file, const std::string& root) {
    const fs::path f(resolved_path(file)), r(resolved_path(root));
    auto fi = f.begin();
    for (auto ri = r.begin(); ri != r.end(); ++ri) {
        if (ri->empty()) continue;  // the empty last component of a root given with a trailing '/'
        if (fi == f.end() || *fi != *ri) return false;
        ++fi;
    }
    return true;
}

void check_reference(const ReferencePolicy& policy, const std::string& header, const std::string& file) {
    if (!policy.confined() || resolves_inside(file, policy.root)) return;
    const std::string where = escape_field(resolved_path(file), 256);
    const std::string root = escape_field(resolved_path(policy.root), 256);
    if (file == header)
        throw ReferenceRefused(escape_field(header, 256) + ": resolves to " + where + ", outside the archive folder " + root +
                               "; refused");
    throw ReferenceRefused(escape_field(header, 256) + ": names " + escape_field(file, 256) + " (resolved: " + where +
                           "), outside the archive folder " + root + "; refused");
}

void check_references(const ReferencePolicy& policy, const std::string& header, const std::vector<std::string>& files) {
    for (const auto& f : files) check_reference(policy, header, f);
}

}  // namespace meshless
