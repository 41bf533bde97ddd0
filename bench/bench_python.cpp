// meshless-bench python: the Python module's numbers (python/README.md), measured by
// bench/python_module.py in the same run as their baselines (the CLI's outputs, sequential calls,
// SciPy's RBFInterpolator): equality with the CLI, peak RSS on an np.memmap volume, call overhead,
// two threads against two calls in sequence (the GIL released), Field against SciPy. The script
// prints TABLE / ROW / NOTE lines; this section turns them into the report's tables.
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_common.hpp"

namespace meshless::bench {

namespace {

std::vector<std::string> split_tabs(const std::string& line) {
    std::vector<std::string> parts;
    std::stringstream ss(line);
    std::string p;
    while (std::getline(ss, p, '\t')) parts.push_back(p);
    return parts;
}

}  // namespace

void run_python(const BenchOptions& o, Report& r) {
    r.section("Python module (meshless-bench python)");
    const std::string script = o.bench_dir + "/python_module.py";
    std::string cmd = "PYTHONPATH=" + shell_quote(std::string(MESHLESS_BENCH_PYTHON_DIR)) + "${PYTHONPATH:+:$PYTHONPATH} " +
                      shell_quote(o.python) + " " + shell_quote(script) + " --meshless " + shell_quote(o.meshless) + " --data " +
                      shell_quote(o.data_dir) + (o.quick ? " --quick" : "") +
                      (o.scratch_dir.empty() ? "" : " --scratch " + shell_quote(o.scratch_dir)) + " 2>&1";
    const auto [text, code] = capture(cmd);
    Table t;
    bool open = false;
    std::stringstream in(text);
    std::string line;
    std::vector<std::string> other;
    const auto flush = [&] {
        if (open) r.table(t);
        t = Table{};
        open = false;
    };
    while (std::getline(in, line)) {
        const auto parts = split_tabs(line);
        if (parts.size() >= 2 && parts[0] == "TABLE") {
            flush();
            r.note(parts[1]);
            t.header.assign(parts.begin() + 2, parts.end());
            open = true;
        } else if (!parts.empty() && parts[0] == "ROW" && open) {
            t.add(std::vector<std::string>(parts.begin() + 1, parts.end()));
        } else if (parts.size() >= 2 && parts[0] == "NOTE") {
            flush();
            r.note(parts[1]);
        } else if (!line.empty()) {
            other.push_back(line);
        }
    }
    flush();
    if (code != 0) {
        std::string tail;
        for (std::size_t i = other.size() > 5 ? other.size() - 5 : 0; i < other.size(); ++i) tail += other[i] + " / ";
        r.note(fmt("python_module.py failed (exit status %d; the module is built by -DMESHLESS_BUILD_PYTHON=ON with "
                   "pybind11-dev python3-dev python3-numpy): %s", code, tail.c_str()));
    }
}

}  // namespace meshless::bench
