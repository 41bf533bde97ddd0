// cli/args.hpp on CLI11 (Debian libcli11-dev, header-only): CLI11 matches the options, collects
// their values, enforces single-valued options (MultiOptionPolicy::Throw) and formats --help; this
// file maps its outcomes onto one-line UsageErrors that name the option.
#include "cli/args.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
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

std::vector<double> parse_finite_list(const std::string& s, const std::string& what, std::size_t max) {
    std::vector<double> values;
    for (std::size_t at = 0;;) {
        const std::size_t comma = s.find(',', at);
        const std::string item = s.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
        if (item.empty()) throw UsageError(what + ": expected numbers separated by commas, got '" + s + "'");
        if (values.size() == max)
            throw UsageError(what + ": at most " + std::to_string(max) + " values, got more in '" + s + "'");
        values.push_back(parse_finite(item, what));
        if (comma == std::string::npos) return values;
        at = comma + 1;
    }
}

std::function<void(const std::string&)> in_range(const std::string& option, double lo, bool lo_inclusive, double hi) {
    return [=](const std::string& s) {
        const double v = parse_finite(s, option);
        if (lo_inclusive ? v >= lo && v <= hi : v > lo && v <= hi) return;
        char range[96];
        std::snprintf(range, sizeof range, "%s%g, %g]", lo_inclusive ? "[" : "(", lo, hi);
        throw UsageError(option + ": expected a number in " + range + ", got '" + s + "'");
    };
}

long long parse_int(const std::string& s, const std::string& what) {
    char* end = nullptr;
    errno = 0;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (s.empty() || end != s.c_str() + s.size())
        throw UsageError(what + ": expected an integer, got '" + s + "'");
    if (errno == ERANGE)  // strtoll clamps to LLONG_MIN/MAX: never a silent substitute
        throw UsageError(what + ": " + s + " is out of range (an integer of at most 18 digits)");
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

namespace {

constexpr const char* kExitCodes =
    "exit codes: 0 success (also when a downstream pipe closes early), 1 usage error,\n"
    "            2 bad input data or I/O failure, 3 internal error.";

/// Positional arguments CLI11 may collect: more than any command allows (each checks its own
/// maximum with a message of ours), below CLI11's "unlimited" marker.
constexpr int kPositionalCapacity = 1 << 28;

/// Width of --help: option descriptions are wrapped to it (the usage text, the description and
/// the epilog keep their own line breaks).
constexpr std::size_t kHelpWidth = 100, kHelpColumn = 28;

/// The words of `text` (its line breaks and indentation are spaces) wrapped into lines of at most
/// `width` characters (longer words stay whole).
std::string wrap(const std::string& text, std::size_t width) {
    std::string out;
    std::size_t line = 0;  // length of the line being filled
    for (std::size_t i = 0; i < text.size();) {
        if (text[i] == ' ' || text[i] == '\n') {
            ++i;
            continue;
        }
        const std::size_t end = std::min(text.find_first_of(" \n", i), text.size());
        const std::size_t n = end - i;
        if (line > 0 && line + 1 + n > width) {
            out += '\n';
            line = 0;
        } else if (line > 0) {
            out += ' ';
            ++line;
        }
        out.append(text, i, n);
        line += n;
        i = end;
    }
    return out;
}

/// CLI11's option layout (name column, metavar, description) in the order of a Unix usage text:
/// the usage line, the description, the options with their defaults, the epilog.
class HelpFormatter final : public CLI::Formatter {
public:
    explicit HelpFormatter(std::string synopsis) : synopsis_(std::move(synopsis)) { column_width(kHelpColumn); }

    std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override {
        return make_usage(app, std::move(name)) + make_description(app) + make_groups(app, mode) + "\n" +
               make_footer(app);
    }
    std::string make_usage(const CLI::App*, std::string name) const override {
        return "usage: " + name + (synopsis_.empty() ? "" : " " + synopsis_) + "\n\n";
    }
    std::string make_option_name(const CLI::Option* opt, bool positional) const override {
        std::string names = CLI::Formatter::make_option_name(opt, positional);  // "-o,--output"
        for (std::size_t p = 0; (p = names.find(',', p)) != std::string::npos; p += 2) names.insert(p + 1, " ");
        return names;
    }
    std::string make_option_opts(const CLI::Option* opt) const override {
        return opt->get_items_expected_max() > 0 ? " " + opt->get_type_name() : std::string();
    }
    std::string make_option_desc(const CLI::Option* opt) const override {
        const std::string& def = opt->get_default_str();
        return wrap(opt->get_description() + (def.empty() ? std::string() : " (default " + def + ")"),
                    kHelpWidth - kHelpColumn);
    }

private:
    std::string synopsis_;
};

bool is_flag(const CLI::Option* o) { return o->get_items_expected_max() == 0; }

/// "--name" of an option (its first long name; every option here has one).
std::string long_name(const CLI::Option* o) { return "--" + o->get_lnames().front(); }

}  // namespace

struct Args::Impl {
    CLI::App app;
    CLI::Option* positional = nullptr;
    CLI::Option* last = nullptr;  // the option or flag declared last (repeatable())
    std::vector<std::pair<const CLI::Option*, std::function<void(const std::string&)>>> checks;  // validate()
    std::vector<std::pair<CLI::Option*, CLI::Option*>> aliases;  // deprecated_alias(): (old, new)
    std::string epilog;

    Impl(const std::string& command, std::string synopsis, std::string description)
        : app(std::move(description), "meshless " + command) {
        app.formatter(std::make_shared<HelpFormatter>(std::move(synopsis)));
        // the positionals first: their group "" (hidden from --help) then precedes "options"
        positional = app.add_option("ARGS", CLI::callback_t{}, "", false);
        positional->expected(kPositionalCapacity)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)->group("");
        app.option_defaults()->group("options");
        app.set_help_flag("-h,--help", "show this help and exit");
        app.allow_extras(true);  // unknown options are reported by parse(), in our words
        app.footer(kExitCodes);
    }

    /// The option named by `token` ("--name" or "-x"), or nullptr.
    const CLI::Option* find(const std::string& token) const {
        const bool long_form = token.size() > 2 && token.compare(0, 2, "--") == 0;
        const bool short_form = token.size() == 2 && token[0] == '-' && token[1] != '-';
        if (!long_form && !short_form) return nullptr;
        const CLI::Option* o = app.get_option_no_throw(token);
        return o && !o->get_positional() ? o : nullptr;
    }

    /// Our one-line message for a CLI11 parse error (an argument mismatch: a single-valued option
    /// given twice, or an option at the end of the line without its value).
    UsageError usage_error(const CLI::ParseError& e, int argc, char** argv, int first, const std::string& command) const {
        const std::string see = " (see meshless " + command + " --help)";
        for (const CLI::Option* o : app.get_options()) {
            if (o->get_positional() || is_flag(o) || o->get_multi_option_policy() != CLI::MultiOptionPolicy::Throw)
                continue;
            if (const auto& r = o->results(); r.size() > 1)
                return UsageError("option " + long_name(o) + " given twice ('" + r[0] + "' and '" + r[1] +
                                  "'); it takes one value" + see);
        }
        if (argc > first) {
            // an option's value is always the next argument, so only the last one can lack it
            std::string tok = argv[argc - 1];
            if (tok.size() > 2 && tok.back() == '=') tok.pop_back();
            if (const CLI::Option* o = find(tok); o && !is_flag(o))
                return UsageError("option " + long_name(o) + " needs a value (" + o->get_type_name() + ")");
        }
        return UsageError(e.what() + see);
    }
};

Args::Args(std::string command, std::string synopsis, std::string description)
    : impl_(std::make_unique<Impl>(command, std::move(synopsis), std::move(description))), command_(std::move(command)) {}

Args::~Args() = default;

Args& Args::option(const std::string& name, const std::string& short_name, const std::string& metavar,
                   const std::string& help, const std::string& default_text) {
    const std::string names = (short_name.empty() ? "" : "-" + short_name + ",") + "--" + name;
    CLI::Option* o = impl_->app.add_option(names, CLI::callback_t{}, help, false);
    o->type_name(metavar)->default_str(default_text)->multi_option_policy(CLI::MultiOptionPolicy::Throw);
    impl_->last = o;
    return *this;
}

Args& Args::flag(const std::string& name, const std::string& help) {
    impl_->last = impl_->app.add_flag("--" + name, help);
    return *this;
}

Args& Args::deprecated_alias(const std::string& old_name) {
    CLI::Option* target = impl_->last;
    if (!target) throw std::logic_error("Args::deprecated_alias() must follow an option() or flag() declaration");
    const std::string no_help;
    CLI::Option* old = is_flag(target) ? impl_->app.add_flag("--" + old_name, no_help)
                                       : impl_->app.add_option("--" + old_name, CLI::callback_t{}, "", false);
    if (!is_flag(target)) old->type_name(target->get_type_name())->multi_option_policy(CLI::MultiOptionPolicy::Throw);
    old->group("");  // hidden from --help
    impl_->aliases.emplace_back(old, target);
    impl_->last = target;
    return *this;
}

Args& Args::repeatable() {
    if (!impl_->last || is_flag(impl_->last))
        throw std::logic_error("Args::repeatable() must follow an option() declaration");
    impl_->last->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
    return *this;
}

Args& Args::validate(std::function<void(const std::string&)> check) {
    if (!impl_->last || is_flag(impl_->last))
        throw std::logic_error("Args::validate() must follow an option() declaration");
    impl_->checks.emplace_back(impl_->last, std::move(check));
    return *this;
}

Args& Args::positionals(std::size_t /*min: the commands name what is missing*/, std::size_t max) {
    max_positional_ = max;
    return *this;
}

Args& Args::epilog(const std::string& text) {
    impl_->epilog += text;
    impl_->app.footer(impl_->epilog + "\n" + kExitCodes);
    return *this;
}

bool Args::takes_value(const std::string& token) const {
    const CLI::Option* o = impl_->find(token);
    return o && !is_flag(o);
}

bool Args::parse(int argc, char** argv, int first) {
    command_line_.clear();
    for (int i = 0; i < argc; ++i) command_line_ += (i ? " " : "") + std::string(argv[i]);
    CLI::App& app = impl_->app;
    std::vector<std::string> args(argv + std::min(first, argc), argv + argc);
    std::reverse(args.begin(), args.end());  // CLI11 takes them last first
    try {
        app.parse(std::move(args));
    } catch (const CLI::ParseError& e) {  // CallForHelp included
        if (app.get_help_ptr()->count() > 0) {
            std::fputs(help_text().c_str(), stdout);
            return false;
        }
        throw impl_->usage_error(e, argc, argv, first, command_);
    }
    std::string see = " (see meshless " + command_ + " --help)";
    if (!variant_.empty()) {
        const auto& given = impl_->positional->results();
        see = " (the options for " + variant_ + ": meshless " + command_ + " " + (given.empty() ? std::string("FILE") : "'" + given.front() + "'") +
              " --help)";
    }
    for (std::string tok : app.remaining()) {
        if (tok == "--") continue;  // CLI11 keeps the end-of-options mark among the extras
        if (tok.compare(0, 2, "--") == 0) tok = tok.substr(0, tok.find('='));
        throw UsageError("unknown option '" + tok + "'" + see);
    }
    for (const CLI::Option* o : app.get_options())
        if (!o->get_positional() && is_flag(o))
            for (const auto& r : o->results())
                if (r != "true") throw UsageError("option " + long_name(o) + " takes no value");
    // a value may start with '-' (--iso -5), but one that is this command's option name means the
    // value was left out ("--iso -o out.ply")
    for (const CLI::Option* o : app.get_options())
        if (!o->get_positional() && !is_flag(o))
            for (const auto& r : o->results())
                if (impl_->find(r.substr(0, r.find('='))))
                    throw UsageError("option " + long_name(o) + " needs a value; '" + r + "' is an option" + see);
    for (auto& [old, target] : impl_->aliases) {
        if (old->count() == 0) continue;
        if (target->count() > 0)
            throw UsageError("option " + long_name(target) + " given twice (also as its old name " + long_name(old) + ")" + see);
        std::fprintf(stderr, "meshless %s: warning: %s is now %s (the old name still works, for now)\n", command_.c_str(),
                     long_name(old).c_str(), long_name(target).c_str());
        target->add_result(old->results());
        old->clear();
    }
    positional_ = impl_->positional->results();
    if (positional_.size() > max_positional_)
        throw UsageError("unexpected argument '" + positional_[max_positional_] + "'" + see);
    for (const auto& [o, check] : impl_->checks)
        for (const auto& r : o->results()) check(r);
    return true;
}

Args& Args::input_variant(const std::string& what) {
    variant_ = what;
    return *this;
}

bool Args::has(const std::string& name) const {
    const CLI::Option* o = impl_->find("--" + name);
    return o && o->count() > 0;
}

bool Args::declared(const std::string& name) const { return impl_->find("--" + name) != nullptr; }

std::optional<std::string> Args::get(const std::string& name) const {
    const CLI::Option* o = impl_->find("--" + name);
    if (!o || is_flag(o) || o->results().empty()) return std::nullopt;
    return o->results().back();  // the only one unless repeatable(): parse() refuses duplicates
}

std::vector<std::string> Args::get_all(const std::string& name) const {
    const CLI::Option* o = impl_->find("--" + name);
    if (!o || is_flag(o)) return {};
    return o->results();
}

std::string Args::get_or(const std::string& name, const std::string& def) const { return get(name).value_or(def); }

std::string Args::default_of(const std::string& name) const {
    const CLI::Option* o = impl_->find("--" + name);
    return o ? o->get_default_str() : std::string();
}

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

std::string Args::help_text() const { return impl_->app.help(); }

}  // namespace meshless::cli
