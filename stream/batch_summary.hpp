// The summary table of a batch run (stream/batch_job.hpp), one row per volume and a totals line,
// as `meshless batch` prints it on stdout.
//
//   volume  result      written  up to date   seconds
//   chest   done              3           0     12.34
//   knee    FAILED            0           0      0.01  knee.raw: truncated ...
//   2 volume(s): 1 done, 0 up to date, 1 failed; 3 output(s) written, 0 up to date; 12.40 s
// Names and messages pass through terminal_safe (formats/terminal_safe.hpp); ", N refused" joins the
// totals only when some volume was refused, ", N with empty point sets" only when some isovalue of
// some volume crossed no brick (its row then says "empty at K isovalue(s)"). Flushes `out`; write errors are not reported. Reentrant.
#pragma once
#include <cstdio>

#include "stream/batch_job.hpp"

namespace meshless {

void print_batch_summary(std::FILE* out, const BatchRun& run);
/// The line of a volume that failed or was refused (nothing for the others) to `out`, prefixed
/// `meshless batch: `; a full disk adds the line that says the run stops.
void print_batch_item_failure(std::FILE* out, const BatchItemResult& r);

}  // namespace meshless
