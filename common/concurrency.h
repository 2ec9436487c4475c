// Running independent pieces of work on a few threads: the fits of
// FitConcurrently (estimation/fit.h), the records of a stacked Jacobian
// (estimation/stacked_jacobian.h), the sampling-convention check's refits
// (estimation/sampling_check.h), the experiment design's inputs
// (design/experiment_design.h), the seeds of a campaign (run/campaign.h)
// and the gnuplot runs of a report (report/report.h, report/html_report.h).
#ifndef COMMON_CONCURRENCY_H_
#define COMMON_CONCURRENCY_H_

#include <cstddef>
#include <functional>

namespace axis {

// Calls body(k) for every k in [0, n), on up to `threads` threads (the
// calling thread is one of them, and no more threads than n), each taking
// the next k when it has finished one, so that a long item does not hold up
// the others. Returns when every call has returned. If calls threw, rethrows
// the exception of the lowest such k after every thread has finished (the
// other items still run). threads < 1 counts as 1; if the system refuses
// a thread, the ones it gave do the work. `body` must be safe to call from
// several threads at once for different k.
void ForEachConcurrently(size_t n, int threads, const std::function<void(size_t)>& body);

// The threads for work that waits on child processes (gnuplot): the
// machine's hardware threads (std::thread::hardware_concurrency), at least 1.
int ProcessThreads();

}  // namespace axis

#endif  // COMMON_CONCURRENCY_H_
