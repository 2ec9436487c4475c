// SIGINT and SIGTERM for the command-line tools (issue 17): an interrupted
// run exits at once with 130 (SIGINT) or 143 (SIGTERM), 128 + the signal
// number as shells report it, and one line on stderr saying what was not
// written; outputs are committed inside a DeferInterrupts scope, so that an
// interrupt never leaves a partial file or output folder behind.
#ifndef IO_INTERRUPT_H_
#define IO_INTERRUPT_H_

#include <string>

namespace axis {

// Installs the handlers for SIGINT and SIGTERM (sigaction). `program` names
// the tool in the message, e.g. "fit-params: interrupted by SIGINT: nothing
// written to out/paper". Call once, before any other thread starts. Throws
// std::runtime_error if sigaction fails.
void InstallInterruptHandlers(const std::string& program);

// The output an interrupt now leaves unwritten (a file or folder path); the
// message says "nothing written to <path>". Before the first call it says
// "nothing written". Not async-signal-safe: call from the main thread while
// no DeferInterrupts scope is active.
void SetInterruptTarget(const std::string& path);

// While alive, an interrupt is held instead of acted on; the destructor acts
// on a held one: "…: interrupted by SIGINT after <path> was written" if
// Committed() was called, else the usual message, then exits 128 + signal.
// Scopes do not nest. Never throws.
class DeferInterrupts {
 public:
  DeferInterrupts();
  ~DeferInterrupts();
  DeferInterrupts(const DeferInterrupts&) = delete;
  DeferInterrupts& operator=(const DeferInterrupts&) = delete;

  // The outputs are complete at their final paths.
  void Committed();
};

}  // namespace axis

#endif  // IO_INTERRUPT_H_
