// Output folders that hold one run's complete outputs: checked before the
// work, written into a staging folder and moved into place when complete
// (interrupts held meanwhile, io/interrupt.h).
#ifndef IO_OUTPUT_STAGING_H_
#define IO_OUTPUT_STAGING_H_

#include <functional>
#include <string>
#include <vector>

namespace axis {

// A run's outputs are written into a staging folder and moved into place
// only when all of them are complete, so that a failure or an interrupt
// (io/interrupt.h) leaves no partial output folder.
//
// Checks, before any work, that the outputs can go to `dir`: `dir`, if it
// exists, and the nearest existing folder above it (where the staging
// folder is made, or `dir` created) are directories this process may write
// into; with `staged` false (outputs written into `dir` directly, as
// fit-campaign's) the folder above is not checked when `dir` exists. Throws
// std::invalid_argument "<dir>: expected an output directory …, got …"
// naming the file in the way or the folder that cannot be written.
void CheckOutputDirectory(const std::string& dir, bool staged = true);

// Creates and returns an empty sibling of `dir`, "<dir>.partial.<pid>"
// (creating the parents of `dir` if missing; removing a stale staging folder
// of the same name). Throws std::runtime_error naming the folder.
std::string MakeStagingDirectory(const std::string& dir);

// Whether `name` may name outputs (an experiment's fit_<name>.csv, a
// benchmark criterion's folder): non-empty, of letters, digits, '_', '-',
// '.'. Never throws.
bool IsOutputName(const std::string& name);

// Removes the staging folders "<dir>.partial.<pid>" beside `dir` whose
// process <pid> no longer exists (a run killed with SIGKILL, which no
// handler can catch, while writing its outputs), and returns their paths,
// sorted. A folder whose process still runs (another run writing the same
// output), or that cannot be removed, is left. Never throws (except
// std::bad_alloc).
std::vector<std::string> RemoveStaleStagingDirectories(const std::string& dir);

// Moves the outputs of `staging` to `dir`: a single rename if `dir` does not
// exist, else file by file (each rename atomic; a subfolder that exists in
// both is merged the same way), then removes `staging`. Each folder it
// fills gets a list of the outputs it moved there (kOutputList, one name a
// line); an earlier run's outputs that this run does not write (a
// validation experiment dropped from the job, say) are removed before the
// move, so the folder holds one run's outputs. Files that no run listed
// (the user's own) stay, also inside a listed folder, which is then kept. Throws std::runtime_error naming the file
// that cannot be moved or removed.
void CommitStagingDirectory(const std::string& staging, const std::string& dir);

// The name of the list of its outputs that CommitStagingDirectory keeps in
// each output folder.
inline constexpr const char* kOutputList = ".outputs";

// Calls `write(staging, &warnings)` on a staging folder of `dir`
// (MakeStagingDirectory), after removing the stale staging folders of
// earlier runs (RemoveStaleStagingDirectories; each removal is a warning),
// and moves its contents into place when it returns
// (CommitStagingDirectory); an interrupt meanwhile is held
// (io/interrupt.h DeferInterrupts). On an exception the staging folder is
// removed and the exception passed on. Returns the warnings with the
// staging folder's path replaced by `dir`. Throws std::runtime_error as
// MakeStagingDirectory and CommitStagingDirectory.
std::vector<std::string> WriteStaged(
    const std::string& dir,
    const std::function<void(const std::string&, std::vector<std::string>*)>& write);

}  // namespace axis

#endif  // IO_OUTPUT_STAGING_H_
