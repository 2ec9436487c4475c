// Progress of a long run (issue 14): which stage it is in (start k of n,
// horizon, optimum check, intervals, discovery step, candidate refit i of
// k), the elapsed time and, where there is a basis, an estimate of the
// remaining time of the current phase.
//
// A ProgressStream is the std::ostream a run prints to. On a terminal it
// keeps one status line at the bottom, redrawn in place with a carriage
// return; every other text written to the stream first erases that line,
// so tables and messages scroll above it as usual. Anywhere else (a pipe,
// a file, a test's string stream) each status becomes a plain line
// "progress: <elapsed> elapsed; <status>[; <phase> ~<time> left]" and the
// other text passes through unchanged, so that logs keep every line they
// had before.
//
// The fitter finds the stream by dynamic_cast of the std::ostream* it is
// given (FitParameters, Discover, ResidualBootstrap); with any other stream
// they print what they printed before (one line per solver iteration).
#ifndef COMMON_PROGRESS_H_
#define COMMON_PROGRESS_H_

#include <chrono>
#include <memory>
#include <ostream>
#include <streambuf>
#include <string>

namespace axis {

// The width of the terminal on file descriptor `fd`, or 0 if `fd` is not a
// terminal (isatty). A terminal whose width cannot be read counts as 80
// columns.
int TerminalColumns(int fd);

// "12 s", "4 min 05 s", "1 h 02 min": a duration in seconds for the
// progress line (negative or non-finite values print as "0 s").
std::string FormatDuration(double seconds);

class ProgressStream : public std::ostream {
 public:
  // Text goes to `out`. `columns` > 0: `out` is a terminal that wide (one
  // updating status line, cut to columns − 1 characters so that it never
  // wraps); 0: plain lines. The clock of the elapsed time starts here.
  ProgressStream(std::ostream& out, int columns);
  // Erases the status line (terminal) and flushes.
  ~ProgressStream() override;
  ProgressStream(const ProgressStream&) = delete;
  ProgressStream& operator=(const ProgressStream&) = delete;

  bool terminal() const;

  // Starts a phase named `name` (e.g. "starts", "profile intervals"): its
  // own clock and no basis for a remaining time until Status reports a
  // fraction above 0.
  void BeginPhase(const std::string& name);

  // The current stage, e.g. "start 1 of 4, horizon 0.200 s (stage 3 of 5)".
  // `done` in [0, 1] is the part of the current phase finished (NaN:
  // unknown); with done > 0 and at least 1 s spent in the phase the line
  // adds "<phase> ~<time> left": the phase's time so far scaled by
  // (1 − done)/done, an extrapolation, hence the "~". On a terminal it
  // counts down until the next status and disappears once overdue.
  // Clears the detail. Terminal: redraws the status line; plain: prints
  // one line.
  void Status(const std::string& what, double done);

  // A detail of the current stage that changes often (the solver's
  // iteration and cost): shown after the status on a terminal (redrawn at
  // most every 0.2 s), ignored in plain mode, where the solver's own
  // iteration lines are printed instead.
  void Detail(const std::string& detail);

  // Seconds since construction.
  double Elapsed() const;

 private:
  class Buffer;
  void Redraw(bool force);
  std::string Line() const;
  double InPhase() const;  // s since BeginPhase

  std::unique_ptr<Buffer> buffer_;
  int columns_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point phase_start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::string phase_;
  std::string status_;
  std::string detail_;
  double phase_total_ = 0.0;  // s, the phase's extrapolated length (0: no basis)
};

// The ProgressStream behind `out`, or nullptr if `out` is null or another
// kind of stream.
ProgressStream* AsProgressStream(std::ostream* out);

}  // namespace axis

#endif  // COMMON_PROGRESS_H_
