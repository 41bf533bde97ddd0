#include "stream/batch_sidecar.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include "formats/atomic_file.hpp"
#include "formats/crc32.hpp"
#include "kernels/errors.hpp"

namespace meshless {

const char* meshless_version() { return MESHLESS_VERSION; }  // stream/CMakeLists.txt defines it for this file

std::vector<FileStat> stat_files(const std::vector<std::string>& paths) {
    std::vector<FileStat> out;
    for (const auto& p : paths) {
        struct ::stat st {};
        if (::stat(p.c_str(), &st) != 0) throw IoError(p + ": cannot read (" + std::strerror(errno) + ")");
        FileStat f;
        f.path = p;
        f.size = S_ISDIR(st.st_mode) ? 0 : static_cast<std::uint64_t>(st.st_size);
        f.mtime_ns = static_cast<std::int64_t>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
        out.push_back(std::move(f));
    }
    return out;
}

std::uint32_t crc32_files(const std::vector<FileStat>& files) {
    std::uint32_t crc = 0;
    std::vector<unsigned char> buf(1 << 20);
    for (const auto& f : files) {
        struct ::stat st {};
        if (::stat(f.path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) continue;  // a directory; a FIFO would block
        std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(std::fopen(f.path.c_str(), "rb"), &std::fclose);
        if (!in) throw IoError(f.path + ": cannot open (" + std::strerror(errno) + ")");
        std::size_t n;
        while ((n = std::fread(buf.data(), 1, buf.size(), in.get())) > 0) crc = crc32_ieee(crc, buf.data(), n);
        if (std::ferror(in.get())) throw IoError(f.path + ": read failed (" + std::strerror(errno) + ")");
    }
    return crc;
}

std::string sidecar_path(const std::string& output) { return output + ".meta"; }

std::optional<Sidecar> read_sidecar(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return std::nullopt;  // none, or not one we wrote
    std::ifstream in(path);
    if (!in) return std::nullopt;
    Sidecar s;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        const auto eq = line.find('=');
        if (eq == std::string::npos) return std::nullopt;  // damaged: treat as missing
        s[line.substr(0, eq)] = line.substr(eq + 1);
    }
    if (in.bad()) return std::nullopt;
    return s;
}

void write_sidecar(const std::string& path, const Sidecar& s) {
    std::string text = "# meshless batch: the output beside this file is complete and was made from this input\n";
    for (const auto& [k, v] : s) text += k + "=" + v + "\n";
    AtomicFile f(path, Durability::fsync);
    f.write(text);
    f.commit();
}

void put_input(Sidecar& s, const std::string& input, const std::vector<FileStat>& files, std::uint32_t crc) {
    std::uint64_t total = 0;
    s["input"] = input;
    s["input_files"] = std::to_string(files.size());
    for (std::size_t i = 0; i < files.size(); ++i) {
        s["input_file." + std::to_string(i)] =
            std::to_string(files[i].size) + " " + std::to_string(files[i].mtime_ns) + " " + files[i].path;
        total += files[i].size;
    }
    s["input_size"] = std::to_string(total);
    char buf[16];
    std::snprintf(buf, sizeof buf, "%08x", crc);
    s["input_crc32"] = buf;
}

std::vector<FileStat> recorded_files(const Sidecar& s) {
    std::vector<FileStat> out;
    const auto n = s.find("input_files");
    if (n == s.end()) return {};
    const long count = std::strtol(n->second.c_str(), nullptr, 10);
    for (long i = 0; i < count; ++i) {
        const auto e = s.find("input_file." + std::to_string(i));
        if (e == s.end()) return {};
        FileStat f;
        unsigned long long size = 0;
        long long mtime = 0;
        int used = 0;
        if (std::sscanf(e->second.c_str(), "%llu %lld %n", &size, &mtime, &used) != 2 || used <= 0) return {};
        f.size = size;
        f.mtime_ns = mtime;
        f.path = e->second.substr(static_cast<std::size_t>(used));
        out.push_back(std::move(f));
    }
    return out;
}

std::optional<std::uint32_t> recorded_crc(const Sidecar& s) {
    const auto c = s.find("input_crc32");
    if (c == s.end() || c->second.size() != 8) return std::nullopt;
    char* end = nullptr;
    const unsigned long v = std::strtoul(c->second.c_str(), &end, 16);
    if (*end != '\0') return std::nullopt;
    return static_cast<std::uint32_t>(v);
}

namespace {
bool is_identity_key(const std::string& k) {
    return k == "kind" || k == "input_size" || k == "input_crc32" || k == "meshless" || k.rfind("param.", 0) == 0;
}
Sidecar identity(const Sidecar& s) {
    Sidecar id;
    for (const auto& [k, v] : s)
        if (is_identity_key(k)) id[k] = v;
    return id;
}
}  // namespace

bool same_identity(const Sidecar& stored, const Sidecar& expected) { return identity(stored) == identity(expected); }

}  // namespace meshless
