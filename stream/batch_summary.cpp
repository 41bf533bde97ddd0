#include "stream/batch_summary.hpp"

#include <algorithm>

#include "formats/terminal_safe.hpp"

namespace meshless {

namespace {

const char* status_text(BatchStatus s) {
    switch (s) {
        case BatchStatus::done: return "done";
        case BatchStatus::up_to_date: return "up to date";
        case BatchStatus::failed: return "FAILED";
        case BatchStatus::refused: return "REFUSED";
    }
    return "?";
}

}  // namespace

void print_batch_summary(std::FILE* out, const BatchRun& run) {
    std::size_t w = 6;
    for (const auto& r : run.items) w = std::max(w, terminal_safe(r.name).size());
    std::fprintf(out, "%-*s  %-10s  %7s  %10s  %8s\n", static_cast<int>(w), "volume", "result", "written", "up to date", "seconds");
    int done = 0, current = 0, failed = 0, refused = 0, written = 0, outputs_current = 0, empty = 0;
    for (const auto& r : run.items) {
        std::string note = terminal_safe(r.message);
        if (r.empty > 0)
            note += (note.empty() ? "" : "; ") + std::string("empty at ") + std::to_string(r.empty) + " isovalue(s)";
        std::fprintf(out, "%-*s  %-10s  %7d  %10d  %8.2f%s%s\n", static_cast<int>(w), terminal_safe(r.name).c_str(), status_text(r.status),
                     r.written, r.current, r.seconds, note.empty() ? "" : "  ", note.c_str());
        empty += r.empty > 0;
        done += r.status == BatchStatus::done;
        current += r.status == BatchStatus::up_to_date;
        failed += r.status == BatchStatus::failed;
        refused += r.status == BatchStatus::refused;
        written += r.written;
        outputs_current += r.current;
    }
    const std::string refused_text = (refused ? ", " + std::to_string(refused) + " refused" : "") +
                                     (empty ? ", " + std::to_string(empty) + " with empty point sets" : "");
    std::fprintf(out, "%zu volume(s): %d done, %d up to date, %d failed%s; %d output(s) written, %d up to date; %.2f s\n",
                 run.items.size(), done, current, failed, refused_text.c_str(), written, outputs_current, run.seconds);
    if (run.shards > 1)
        std::fprintf(out, "shard %u/%u: %zu of the archive's %zu volume(s)\n", run.shard + 1, run.shards, run.items.size(),
                     run.archive_count);
    std::fflush(out);
}

void print_batch_item_failure(std::FILE* out, const BatchItemResult& r) {
    if (r.status != BatchStatus::failed && r.status != BatchStatus::refused) return;
    std::fprintf(out, "meshless batch: %s: %s\n", terminal_safe(r.name).c_str(), terminal_safe(r.message).c_str());
    if (!r.stops_run.empty())
        std::fprintf(out,
                     "meshless batch: %s; stopping. Finished outputs are kept, temporaries removed; free some space "
                     "and run the same command again to finish the rest\n",
                     terminal_safe(r.stops_run).c_str());
}

}  // namespace meshless
