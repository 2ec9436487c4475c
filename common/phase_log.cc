#include "common/phase_log.h"

#include <sstream>
#include <utility>

#include "common/format.h"

namespace axis {

PhaseLog::PhaseLog(std::function<WorkCount()> counter) : counter_(std::move(counter)) {}

WorkCount PhaseLog::Count() const { return counter_ ? counter_() : WorkCount{}; }

void PhaseLog::Begin(const std::string& name) {
  if (!current_.empty() && name == current_) return;
  End();
  current_ = name;
  started_ = Clock::now();
  at_start_ = Count();
}

void PhaseLog::End() {
  if (current_.empty()) return;
  const WorkCount now = Count();
  RunPhase p;
  p.name = current_;
  p.seconds = std::chrono::duration<double>(Clock::now() - started_).count();
  p.simulations = now.simulations - at_start_.simulations;
  p.derivative_simulations = now.derivative_simulations - at_start_.derivative_simulations;
  phases_.push_back(std::move(p));
  current_.clear();
}

std::string FormatPhaseLog(const std::vector<RunPhase>& phases) {
  std::ostringstream out;
  double total = 0.0;
  for (const RunPhase& p : phases) total += p.seconds;
  out << FormatNumber(total, 3) << " s";
  const char* sep = " (";
  bool any = false;
  for (const RunPhase& p : phases) {
    if (p.seconds < 0.05 && p.simulations == 0 && p.derivative_simulations == 0) continue;
    out << sep << p.name << " " << FormatNumber(p.seconds, 3) << " s: " << p.simulations
        << " simulations, " << p.derivative_simulations << " with derivatives";
    sep = "; ";
    any = true;
  }
  if (any) out << ")";
  return out.str();
}

}  // namespace axis
