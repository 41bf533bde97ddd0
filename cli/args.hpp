// The command line of the meshless subcommands: long options ("--iso 100.5" or "--iso=100.5"),
// short aliases ("-o"), boolean flags, repeatable options, positionals, and a generated --help
// text. Parsing and help formatting are CLI11's (libcli11-dev), kept behind this interface so that
// only args.cpp includes that header. An option's value is always the next argument, even when it
// starts with '-' ("--up -z", "--range -5,5"). Throws UsageError (exit code 1) with a one-line
// message of ours on unknown options, missing values, a single-valued option given twice, a flag
// given a value, too many positionals and malformed numbers. No globals; one Args per subcommand
// invocation.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/errors.hpp"

namespace meshless::cli {

class Args {
public:
    Args(std::string command, std::string synopsis, std::string description);
    ~Args();
    Args(const Args&) = delete;
    Args& operator=(const Args&) = delete;

    /// Declares an option taking a value. `short_name` may be empty. Default shown in --help only.
    Args& option(const std::string& name, const std::string& short_name, const std::string& metavar,
                 const std::string& help, const std::string& default_text = "");
    /// Marks the option declared last as repeatable (read with get_all). Any other option given
    /// twice is a UsageError at parse(): a duplicated single-valued option is never silently the last.
    Args& repeatable();
    /// Checks every value of the option declared last at parse() (after the unknown-option and
    /// duplicate checks, whether or not the command reads it later): `check` throws UsageError on
    /// a bad value, so a malformed value fails on every input, not only where it is used.
    Args& validate(std::function<void(const std::string&)> check);
    /// Gives the option or flag declared last an old name that still works, hidden from --help:
    /// parse() warns on stderr that `old_name` is now the new name, and the value counts as the
    /// new option's (both given: UsageError, as for an option given twice).
    Args& deprecated_alias(const std::string& old_name);
    /// Declares a boolean flag.
    Args& flag(const std::string& name, const std::string& help);
    /// Adds a paragraph (examples, exit codes) at the end of --help.
    Args& epilog(const std::string& text);
    /// Allowed number of positional arguments (default 0..1); parse() throws UsageError on more
    /// than `max`. Fewer than `min` is left to the command, which names what is missing.
    Args& positionals(std::size_t min, std::size_t max);
    /// The kind of input this variant of a command takes (e.g. "multiblock grids"), when the
    /// command's options depend on its input: parse()'s usage errors then point to the help of this
    /// variant ("meshless isosurface FILE --help") instead of the command's general one.
    Args& input_variant(const std::string& what);

    /// Parses argv[first..argc). Returns false when --help was requested (help text printed on
    /// stdout; --help wins over any other error on the line).
    bool parse(int argc, char** argv, int first);

    bool has(const std::string& name) const;
    /// True when option or flag `name` was declared (shared option sets that differ per command).
    bool declared(const std::string& name) const;
    std::optional<std::string> get(const std::string& name) const;
    std::vector<std::string> get_all(const std::string& name) const;
    std::string get_or(const std::string& name, const std::string& def) const;
    /// The default text declared with option `name` ("" when none or not declared).
    std::string default_of(const std::string& name) const;
    std::string require(const std::string& name) const;
    std::optional<double> get_double(const std::string& name) const;
    double get_double_or(const std::string& name, double def) const;
    long long get_int_or(const std::string& name, long long def) const;
    /// "a,b,c" -> 3 numbers; throws UsageError otherwise.
    std::optional<std::array<double, 3>> get_triple(const std::string& name) const;

    const std::vector<std::string>& positional() const { return positional_; }
    /// True when `token` ("--name" or "-x", no "=value") names a declared option that takes a
    /// value (so the next argument is its value, not a positional): lets a command look at its
    /// positionals before choosing which options to declare.
    bool takes_value(const std::string& token) const;
    std::string help_text() const;
    const std::string& command() const { return command_; }
    /// The command line as given (for provenance in stream metadata).
    const std::string& command_line() const { return command_line_; }

private:
    struct Impl;  // the CLI11 application (args.cpp)
    std::unique_ptr<Impl> impl_;
    std::string command_, command_line_;
    std::vector<std::string> positional_;
    std::size_t max_positional_ = 1;
    std::string variant_;
};

/// Parses a number with full-string validation; throws UsageError naming `what`.
double parse_double(const std::string& s, const std::string& what);
/// The same, refusing NaN and infinities.
double parse_finite(const std::string& s, const std::string& what);
/// A comma-separated list of 1..max finite numbers ("100.5" or "60.5,100.5"); throws UsageError
/// naming `what` for an empty item, a non-finite number or more than max of them.
std::vector<double> parse_finite_list(const std::string& s, const std::string& what, std::size_t max);
/// A validate() check: a finite number in (lo, hi], or [lo, hi] when `lo_inclusive`; UsageError
/// "OPTION: expected a number in (lo, hi], got 'V'" otherwise.
std::function<void(const std::string&)> in_range(const std::string& option, double lo, bool lo_inclusive, double hi);
long long parse_int(const std::string& s, const std::string& what);
/// "WxH" with both in [lo, hi]; throws UsageError naming `what`.
std::array<int, 2> parse_size(const std::string& s, const std::string& what, int lo, int hi);
/// --memory: "256M", "1G", "512k", "1048576" (binary units; K/M/G/T, optional B or iB, any case)
/// into bytes; UsageError for anything else, zero or overflow.
std::uint64_t parse_memory_size(const std::string& s);

}  // namespace meshless::cli
