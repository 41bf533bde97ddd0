#include "stream/batch_archive.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>

#include "formats/binary_file.hpp"
#include "formats/file_names.hpp"
#include "formats/reference_policy.hpp"
#include "formats/text_header.hpp"
#include "kernels/errors.hpp"

namespace meshless {

namespace fs = std::filesystem;

namespace {

std::string canonical_or_self(const fs::path& p) {
    std::error_code ec;
    const fs::path c = fs::weakly_canonical(p, ec);
    return ec ? p.lexically_normal().string() : c.string();
}

std::string format_triple(const std::array<double, 3>& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g", v[0], v[1], v[2]);
    return buf;
}

/// Canonical text of raw options (the sidecars compare it), "" when nothing was given.
std::string raw_text(const RawOptions& r) {
    std::string t;
    if (r.dims) t += " dims=" + std::to_string((*r.dims)[0]) + "," + std::to_string((*r.dims)[1]) + "," + std::to_string((*r.dims)[2]);
    if (r.type) t += std::string(" type=") + to_string(*r.type);
    if (r.big_endian) t += " endian=big";
    if (r.spacing) t += " spacing=" + format_triple(*r.spacing);
    if (!r.array.empty()) t += " array=" + escape_field(r.array, 256);
    return t.empty() ? t : t.substr(1);
}

/// Whitespace-separated tokens; "double quoted" tokens may hold spaces. Throws InvalidArgument on an
/// unterminated quote.
std::vector<std::string> tokenize(const std::string& line) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i >= line.size()) break;
        std::string tok;
        if (line[i] == '"') {
            const auto end = line.find('"', i + 1);
            if (end == std::string::npos) throw InvalidArgument("unterminated quote");
            tok = line.substr(i + 1, end - i - 1);
            i = end + 1;
        } else {
            while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) tok += line[i++];
        }
        out.push_back(std::move(tok));
    }
    return out;
}

void walk(const fs::path& root, const fs::path& dir, bool recursive, const std::string& out_canon,
          std::vector<BatchItem>& items) {
    std::error_code ec;
    std::vector<fs::path> entries;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) entries.push_back(it->path());
    if (ec) throw IoError(dir.string() + ": cannot list directory (" + ec.message() + ")");
    std::sort(entries.begin(), entries.end());

    // payload files named by a header in this folder are part of that volume, not volumes of their own
    std::set<std::string> payloads;
    for (const auto& e : entries) {
        if (lower_extension(e.string()) == ".raw" || e.filename().string().front() == '.' || !looks_like_volume(e.string())) continue;
        if (payloads.count(canonical_or_self(e))) continue;  // one slice of a DICOM series already probed: the series is listed
        try {
            RawOptions confined;
            confined.references.root = root.string();  // a header naming files outside the archive lists none
            const VolumeInfo info = probe_volume(e.string(), confined);
            for (const auto& f : info.data_files)
                if (canonical_or_self(f) != canonical_or_self(e)) payloads.insert(canonical_or_self(f));
        } catch (const std::exception&) {
            // a bad header fails later, as an item of the run
        }
    }
    for (const auto& e : entries) {
        const std::string fname = e.filename().string();
        if (fname.empty() || fname.front() == '.') continue;
        if (payloads.count(canonical_or_self(e))) continue;
        if (looks_like_volume(e.string())) {
            BatchItem it;
            it.path = e.string();
            it.raw.references.root = root.string();
            const fs::path rel = e.lexically_relative(root);
            it.name = (rel.parent_path() / volume_stem(rel.string())).lexically_normal().string();
            items.push_back(std::move(it));
        } else if (recursive && fs::is_directory(e, ec) && canonical_or_self(e) != out_canon) {
            walk(root, e, recursive, out_canon, items);
        }
    }
}

}  // namespace

std::string volume_stem(const std::string& path) {
    fs::path p = fs::path(path).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();
    std::string name = p.filename().string();
    if (to_lower(name) == "index.json" && p.has_parent_path()) return p.parent_path().filename().string();
    for (const char* two : {".nii.gz", ".vtk.gz"}) {
        const std::size_t n = std::strlen(two);
        if (name.size() > n && ends_with_ci(name, two)) return name.substr(0, name.size() - n);
    }
    const auto dot = name.rfind('.');
    return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

std::vector<BatchItem> list_archive_dir(const std::string& dir, bool recursive, const std::string& out_dir) {
    std::vector<BatchItem> items;
    walk(fs::path(dir), fs::path(dir), recursive, canonical_or_self(out_dir), items);
    std::stable_sort(items.begin(), items.end(), [](const BatchItem& a, const BatchItem& b) { return a.name < b.name; });
    return items;
}

std::vector<BatchItem> read_manifest(const std::string& manifest, const RawOptionsParser& parse_raw) {
    require_regular_file(manifest);
    std::ifstream in(manifest);
    if (!in) throw IoError(manifest + ": cannot open manifest (" + std::strerror(errno) + ")");
    const fs::path base = fs::path(manifest).parent_path();
    std::vector<BatchItem> items;
    std::string line;
    for (int lineno = 1; std::getline(in, line); ++lineno) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        if (line.find('\0') != std::string::npos)
            throw IoError(manifest + ": line " + std::to_string(lineno) + " holds binary data: not a manifest (one path per line)");
        BatchItem it;
        std::vector<std::string> tok;
        try {
            tok = tokenize(line);
        } catch (const InvalidArgument& e) {
            it.name = "line " + std::to_string(lineno);
            it.error = manifest + ":" + std::to_string(lineno) + ": " + e.what();
            items.push_back(std::move(it));
            continue;
        }
        if (tok.empty()) continue;
        const fs::path p = fs::path(tok[0]).is_absolute() ? fs::path(tok[0]) : base / tok[0];
        it.path = p.lexically_normal().string();
        it.name = volume_stem(tok[0]);
        // the archive folder: the manifest's, or the volume's own for one listed outside it
        const std::string manifest_dir = base.empty() ? std::string(".") : base.string();
        it.raw.references.root = resolves_inside(it.path, manifest_dir) ? manifest_dir : parent_dir(it.path);
        if (tok.size() > 1) {
            try {
                if (!parse_raw) throw InvalidArgument("options after the path are not read here");
                const ReferencePolicy refs = it.raw.references;
                it.raw = parse_raw(std::vector<std::string>(tok.begin() + 1, tok.end()));
                it.raw.references = refs;
                it.raw_text = raw_text(it.raw);
            } catch (const InvalidArgument& e) {
                it.error = manifest + ":" + std::to_string(lineno) + ": " + e.what();
            }
        }
        items.push_back(std::move(it));
    }
    if (in.bad()) throw IoError(manifest + ": read failed");
    return items;
}

}  // namespace meshless
