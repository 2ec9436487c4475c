// What the force-map step of the discovery loop found (discovery/force_map.h
// AddForceMap): the learned force on a grid with its band, the smoothing
// chosen, the forms tried, the effects the map replaced, and whether it was
// kept.
#ifndef DISCOVERY_FORCE_MAP_REPORT_H_
#define DISCOVERY_FORCE_MAP_REPORT_H_

#include <string>
#include <vector>

#include "discovery/channel_changes.h"
#include "sim/force_map.h"

namespace axis {

// The learned force on a grid of its variable, with its 95 % band.
struct ForceMapCurve {
  std::vector<double> z;            // variable (m or m/s)
  std::vector<double> force;        // f(z), N
  std::vector<double> low, high;    // f ∓ 1.96·sd (pointwise, Bayesian)
};

// One λ of the grid the penalty was chosen from (linearised at the first
// refit; the chosen one refitted).
struct SmoothingChoice {
  double lambda = 0.0;  // 1/N²
  double edf = 0.0;     // effective number of parameters of the whole fit
  double chi2 = 0.0;    // Σr² of the data (σ units) predicted at this λ
  double bic = 0.0;     // chi2 + edf·ln(m)
};

// One form's first refit (at the first λ), the forms competing by BIC.
struct ForceMapForm {
  std::string name;   // "force_map.x" etc.
  // Data Σr² + edf·ln(m); for a refit stopped under the level (`stopped`)
  // the lower bound of its Σr² + n·ln(m) where it stopped; +inf if the
  // refit failed.
  double bic = 0.0;
  double edf = 0.0;   // 0 for a stopped or failed refit
  // The refit's wall time (s), beside the other forms, and for a form that
  // ran to its end before the leading one any wait for its level.
  double seconds = 0.0;
  // Why the refit stopped early (StoppedText, discovery/internal/screen.h): a lower
  // bound of its BIC passed kStopFactor times the leading form's fit BIC
  // (2·cost + n·ln(m), its roughness penalty included); "" if it ran to
  // the end.
  std::string stopped;
};

// A library effect refitted away with the map in the model (the backward
// pass: an effect the loop added as a stand-in for what the map now
// carries).
struct ForceMapRemoval {
  std::string effect;
  double bic_with = 0.0, bic_without = 0.0;  // BIC (edf) with and without it
  bool removed = false;
};

// What the force-map step did (JobRun::force_map, estimation/fit.h).
struct ForceMapReport {
  bool tried = false;   // a map was refitted
  bool kept = false;    // ...and kept (its BIC below the library model's)
  std::string reason;   // why the step ran, or why it did not
  // The binned structure that triggered the step, one line each
  // ("e/a: x (chi2 p 1e-12)").
  std::vector<std::string> structure;
  std::vector<Score> scores;  // the score tests of the three forms
  std::vector<ForceMapForm> forms;  // the significant forms' refits
  std::vector<ForceMapRemoval> removals;
  std::string kind;           // "x", "x_friction" or "v" (ForceMapKind)
  ForceMap map;               // the refitted map's structure
  // The axis turns (AxisStructure::motion rotary): the variable in rad or
  // rad/s and the values in N·m, as the texts, the CSV and the plot say.
  bool rotary = false;
  std::vector<double> values, std_errors;  // N (N·m if rotary), per knot
  std::vector<SmoothingChoice> grid;
  double lambda = 0.0;  // the chosen λ, 1/N² (1/(N·m)² if rotary)
  double edf = 0.0;     // effective parameters at the refit
  double s2 = 0.0;      // data Σr²/(m − edf)
  // BIC of the library model (Σr² + n·ln(m)) and of the model with the map
  // (Σr² + edf·ln(m)), both from the residuals at the experiments' declared
  // initial states (StackedJacobian, estimation/stacked_jacobian.h).
  double bic_before = 0.0, bic_after = 0.0;
  std::vector<ChannelChange> channels;
  // The verdict with the map in the model (JudgeResiduals of its
  // diagnostics); the library's own stays DiscoveryReport::verdict.
  std::vector<ChannelDiagnostics> diagnostics;
  ResidualVerdict verdict;
  // Where the band excludes zero: "x in [0.021, 0.118] m" style runs.
  std::vector<std::string> significant;
  ForceMapCurve curve;
  double seconds = 0.0;  // wall time of the step
};

}  // namespace axis

#endif  // DISCOVERY_FORCE_MAP_REPORT_H_
