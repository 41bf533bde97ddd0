#include "cli/args.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace meshless::cli {

double parse_double(const std::string& s, const std::string& what) {
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size())
        throw UsageError(what + ": expected a number, got '" + s + "'");
    return v;
}

double parse_finite(const std::string& s, const std::string& what) {
    const double v = parse_double(s, what);
    if (!std::isfinite(v)) throw UsageError(what + ": expected a finite number, got '" + s + "'");
    return v;
}

long long parse_int(const std::string& s, const std::string& what) {
    char* end = nullptr;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (s.empty() || end != s.c_str() + s.size())
        throw UsageError(what + ": expected an integer, got '" + s + "'");
    return v;
}

std::array<int, 2> parse_size(const std::string& s, const std::string& what, int lo, int hi) {
    const auto x = s.find('x');
    if (x == std::string::npos) throw UsageError(what + ": expected WxH, got '" + s + "'");
    const long long w = parse_int(s.substr(0, x), what), h = parse_int(s.substr(x + 1), what);
    if (w < lo || h < lo || w > hi || h > hi)
        throw UsageError(what + ": width and height must be " + std::to_string(lo) + ".." + std::to_string(hi));
    return {static_cast<int>(w), static_cast<int>(h)};
}

std::uint64_t parse_memory_size(const std::string& s) {
    auto bad = [&] {
        return UsageError("--memory: expected a size like 256M, 1G, 512K or a byte count, got '" + s + "'");
    };
    std::size_t i = 0;
    if (i == s.size() || !std::isdigit(static_cast<unsigned char>(s[i]))) throw bad();
    std::uint64_t v = 0;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) {
        const std::uint64_t d = static_cast<std::uint64_t>(s[i] - '0');
        if (v > (std::numeric_limits<std::uint64_t>::max() - d) / 10) throw bad();
        v = v * 10 + d;
        ++i;
    }
    std::string suffix;
    for (; i < s.size(); ++i) suffix += static_cast<char>(std::toupper(static_cast<unsigned char>(s[i])));
    int shift = 0;
    if (!suffix.empty()) {
        switch (suffix[0]) {
            case 'B': shift = suffix == "B" ? 0 : -1; break;
            case 'K': shift = 10; break;
            case 'M': shift = 20; break;
            case 'G': shift = 30; break;
            case 'T': shift = 40; break;
            default: shift = -1;
        }
        const std::string rest = suffix.substr(1);
        if (suffix[0] != 'B' && !(rest.empty() || rest == "B" || rest == "IB")) shift = -1;
    }
    if (shift < 0) throw bad();
    if (shift > 0 && v > (std::numeric_limits<std::uint64_t>::max() >> shift)) throw bad();
    v <<= shift;
    if (v == 0) throw UsageError("--memory: must be positive, got '" + s + "'");
    return v;
}

Args::Args(std::string command, std::string synopsis, std::string description)
    : command_(std::move(command)), synopsis_(std::move(synopsis)), description_(std::move(description)) {
    flag("help", "show this help and exit");
}

Args& Args::option(const std::string& name, const std::string& short_name, const std::string& metavar,
                   const std::string& help, const std::string& default_text) {
    specs_.push_back({name, short_name, metavar, help, default_text, true});
    return *this;
}

Args& Args::flag(const std::string& name, const std::string& help) {
    specs_.push_back({name, "", "", help, "", false});
    return *this;
}

Args& Args::repeatable() {
    if (specs_.empty() || !specs_.back().takes_value)
        throw std::logic_error("Args::repeatable() must follow an option() declaration");
    specs_.back().repeatable = true;
    return *this;
}

Args& Args::positionals(std::size_t min, std::size_t max) {
    min_positional_ = min;
    max_positional_ = max;
    return *this;
}

Args& Args::epilog(const std::string& text) {
    epilog_ += text;
    return *this;
}

const Args::Spec* Args::find(const std::string& token) const {
    for (const auto& s : specs_)
        if (token == "--" + s.name || (!s.short_name.empty() && token == "-" + s.short_name)) return &s;
    return nullptr;
}

bool Args::parse(int argc, char** argv, int first) {
    command_line_.clear();
    for (int i = 0; i < argc; ++i) command_line_ += (i ? " " : "") + std::string(argv[i]);
    bool only_positional = false;
    for (int i = first; i < argc; ++i) {
        std::string tok = argv[i];
        if (only_positional || tok == "-" || tok.size() < 2 || tok[0] != '-' ||
            (tok[0] == '-' && (std::isdigit(static_cast<unsigned char>(tok[1])) || tok[1] == '.'))) {
            positional_.push_back(tok);
            continue;
        }
        if (tok == "--") {
            only_positional = true;
            continue;
        }
        std::string value;
        bool inline_value = false;
        if (auto eq = tok.find('='); tok.rfind("--", 0) == 0 && eq != std::string::npos) {
            value = tok.substr(eq + 1);
            tok = tok.substr(0, eq);
            inline_value = true;
        }
        const Spec* s = find(tok);
        if (!s) throw UsageError("unknown option '" + tok + "' (see meshless " + command_ + " --help)");
        if (s->name == "help") {
            std::fputs(help_text().c_str(), stdout);
            return false;
        }
        if (s->takes_value) {
            if (!inline_value) {
                if (i + 1 >= argc) throw UsageError("option --" + s->name + " needs a value (" + s->metavar + ")");
                value = argv[++i];
            }
            if (!s->repeatable)
                for (const auto& [k, v] : values_)
                    if (k == s->name)
                        throw UsageError("option --" + s->name + " given twice ('" + v + "' and '" + value +
                                         "'); it takes one value (see meshless " + command_ + " --help)");
            values_.emplace_back(s->name, value);
        } else {
            if (inline_value) throw UsageError("option --" + s->name + " takes no value");
            values_.emplace_back(s->name, "1");
        }
    }
    if (positional_.size() > max_positional_)
        throw UsageError("unexpected argument '" + positional_[max_positional_] + "' (see meshless " + command_ + " --help)");
    (void)min_positional_;  // commands report their own missing arguments, with their names
    return true;
}

bool Args::has(const std::string& name) const {
    for (const auto& [k, v] : values_)
        if (k == name) return true;
    return false;
}

bool Args::declared(const std::string& name) const {
    for (const auto& s : specs_)
        if (s.name == name) return true;
    return false;
}

std::optional<std::string> Args::get(const std::string& name) const {
    std::optional<std::string> r;
    for (const auto& [k, v] : values_)
        if (k == name) r = v;  // at most one unless repeatable(): parse() refuses duplicates
    return r;
}

std::vector<std::string> Args::get_all(const std::string& name) const {
    std::vector<std::string> r;
    for (const auto& [k, v] : values_)
        if (k == name) r.push_back(v);
    return r;
}

std::string Args::get_or(const std::string& name, const std::string& def) const { return get(name).value_or(def); }

std::string Args::require(const std::string& name) const {
    auto v = get(name);
    if (!v) throw UsageError("missing required option --" + name + " (see meshless " + command_ + " --help)");
    return *v;
}

std::optional<double> Args::get_double(const std::string& name) const {
    auto v = get(name);
    if (!v) return std::nullopt;
    return parse_double(*v, "--" + name);
}

double Args::get_double_or(const std::string& name, double def) const { return get_double(name).value_or(def); }

long long Args::get_int_or(const std::string& name, long long def) const {
    auto v = get(name);
    return v ? parse_int(*v, "--" + name) : def;
}

std::optional<std::array<double, 3>> Args::get_triple(const std::string& name) const {
    auto v = get(name);
    if (!v) return std::nullopt;
    std::array<double, 3> r{};
    std::stringstream ss(*v);
    std::string part;
    int n = 0;
    while (std::getline(ss, part, ',')) {
        if (n >= 3) throw UsageError("--" + name + ": expected three comma-separated numbers, got '" + *v + "'");
        r[n++] = parse_double(part, "--" + name);
    }
    if (n != 3) throw UsageError("--" + name + ": expected three comma-separated numbers, got '" + *v + "'");
    return r;
}

std::string Args::help_text() const {
    std::string h = "usage: meshless " + command_ + " " + synopsis_ + "\n\n" + description_ + "\n\noptions:\n";
    for (const auto& s : specs_) {
        std::string left = "  ";
        if (!s.short_name.empty()) left += "-" + s.short_name + ", ";
        left += "--" + s.name;
        if (s.takes_value) left += " " + s.metavar;
        if (left.size() < 28) left += std::string(28 - left.size(), ' ');
        else left += "\n" + std::string(28, ' ');
        h += left + s.help;
        if (!s.default_text.empty()) h += " (default " + s.default_text + ")";
        h += "\n";
    }
    if (!epilog_.empty()) h += "\n" + epilog_;
    h += "\nexit codes: 0 success (also when a downstream pipe closes early), 1 usage error,\n"
         "            2 bad input data or I/O failure, 3 internal error.\n";
    return h;
}

}  // namespace meshless::cli
