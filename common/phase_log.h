// Where a run's time and work go, phase by phase (issue 57): a phase is
// begun by name and ends where the next begins; each keeps its wall time
// and the simulations run in it, read from a counter the caller supplies
// (run/job_run.cc: sim/simulation_count.h). report.json "run_phases", the
// log's "run:" line and the HTML report's diagnostics show them.
#ifndef COMMON_PHASE_LOG_H_
#define COMMON_PHASE_LOG_H_

#include <chrono>
#include <functional>
#include <string>
#include <vector>

namespace axis {

// Simulations of one record each: in double and with derivatives (Jets).
struct WorkCount {
  long long simulations = 0;
  long long derivative_simulations = 0;
};

struct RunPhase {
  std::string name;
  double seconds = 0.0;              // wall time, s
  long long simulations = 0;         // in double
  long long derivative_simulations = 0;  // in ceres::Jet
};

class PhaseLog {
 public:
  // `counter` returns the process's counts so far (may be empty: zeros).
  explicit PhaseLog(std::function<WorkCount()> counter = {});

  // Ends the current phase (if any) and begins `name`. A phase of the same
  // name as the current one continues it. Never throws but std::bad_alloc.
  void Begin(const std::string& name);
  // Ends the current phase; the log stays readable. Never throws.
  void End();

  // The ended phases in order, phases of one name begun again kept apart.
  const std::vector<RunPhase>& phases() const { return phases_; }

 private:
  using Clock = std::chrono::steady_clock;
  WorkCount Count() const;

  std::function<WorkCount()> counter_;
  std::vector<RunPhase> phases_;
  std::string current_;
  Clock::time_point started_;
  WorkCount at_start_;
};

// "4.2 s (base fit 2.1 s: 120 simulations, 300 with derivatives; …)", the
// total and the phases as one line;
// phases under 0.05 s and without simulations are left out. Never throws
// but std::bad_alloc.
std::string FormatPhaseLog(const std::vector<RunPhase>& phases);

}  // namespace axis

#endif  // COMMON_PHASE_LOG_H_
