// How many simulations this process has run (sim/simulate.h Simulate), for
// the time and work a run reports per phase (issue 57: run/run_phases.h).
// One count is one record simulated once: `values` in double (a cost, a
// check, a trace), `derivatives` in ceres::Jet (a Jacobian's share: a fit's
// Jacobian evaluation simulates every fitted record once). Counted with
// relaxed atomics: exact totals, no ordering with other work.
#ifndef SIM_SIMULATION_COUNT_H_
#define SIM_SIMULATION_COUNT_H_

namespace axis {

struct SimulationCount {
  long long values = 0;       // simulations in double
  long long derivatives = 0;  // simulations in ceres::Jet (with sensitivities)
};

// The counts since the process started. Never throws.
SimulationCount SimulationsSoFar();

namespace internal {
// Called by SimulatePlant (and so Simulate) once per run. Never throws.
void CountSimulation(bool with_derivatives);
}  // namespace internal

}  // namespace axis

#endif  // SIM_SIMULATION_COUNT_H_
