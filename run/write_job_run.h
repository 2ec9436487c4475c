// Writing a job run (run/job_run.h) into its output folder: the fit's
// files (report/report.h), report.html (report/html_report.h), the
// discovery and force-map files and the proposed experiment, all staged
// and moved into place when complete (io/output_staging.h).
#ifndef RUN_WRITE_JOB_RUN_H_
#define RUN_WRITE_JOB_RUN_H_

#include <string>
#include <utility>
#include <vector>

#include "run/job_run.h"

namespace axis {

// Writes the outputs of `run` into `dir` (created with its parents if
// missing): WriteFitOutputs' files and, if run.discovered, the
// diag_*.csv/.png of the declared model and model_discovered.yaml. They go
// to a staging folder moved into place when complete (MakeStagingDirectory,
// CommitStagingDirectory; interrupts held meanwhile). Returns the warnings
// (plots not drawn), naming the final paths. Throws std::runtime_error
// naming what cannot be written (nothing is left in `dir` then).
std::vector<std::string> WriteJobRun(const JobRun& run, const std::string& dir);

// As WriteJobRun for several runs written as one: run k into
// `<dir>/<subdirs[k]>`, and each (file name, contents) of `files` into
// `dir`, all in one staging folder moved into place when complete. Used for
// a job's benchmark criteria (run/benchmark.h). Throws std::invalid_argument
// if the sizes of `runs` and `subdirs` differ, std::runtime_error as
// WriteJobRun.
std::vector<std::string> WriteJobRuns(
    const std::vector<JobRun>& runs, const std::vector<std::string>& subdirs,
    const std::vector<std::pair<std::string, std::string>>& files, const std::string& dir);

}  // namespace axis

#endif  // RUN_WRITE_JOB_RUN_H_
