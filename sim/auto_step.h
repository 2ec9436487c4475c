// The integration step chosen from the model and the records when a job
// gives none (`simulation.step` absent; issue 57): a fixed 10 µs step is
// right for the paper's full current loop and a hundred times too fine for
// a rigid axis whose fastest time constant is a second.
//
// The rule: the record's output period T_o itself where it is at most
// kAutoStepFraction of the RK4 stability limit of the linearised model
// (sim/preflight.h), else the largest round step (1, 2, 2.5 or 5 times a
// power of ten) under that bound that divides T_o, and in closed loop also
// the control period T_s (T_o/n where no round step divides T_o). The
// limit is taken at the start values and with each listed parameter at
// each end of its range, the smallest of them, so that the step stays
// stable while the fit moves a free parameter inside its bounds.
#ifndef SIM_AUTO_STEP_H_
#define SIM_AUTO_STEP_H_

#include <string>
#include <utility>
#include <vector>

#include "sim/axis_params.h"

namespace axis {

// The fraction of the RK4 stability limit an automatic step may reach: the
// ratio at which the paper integrated its own model, its 10 µs step on the
// X axis whose full current loop limits RK4 to 19.5 µs (MODEL.md §2 and §5,
// sim/preflight.h), 0.512, rounded up to 0.52 so that the paper's model gets
// the paper's step; carried to every model. On the fastest mode that is
// |hλ| ≤ 1.45, where RK4's amplification 0.27 stands for e^{hλ} = 0.23: a
// mode that has decayed to a quarter within the step; the slower modes,
// which make the records, are integrated far more finely.
constexpr double kAutoStepFraction = 0.52;

// A parameter range the step must stay stable over (a free parameter's
// name as FindParam knows it, and its bounds).
struct ParameterRange {
  std::string name;
  double lower = 0.0;
  double upper = 0.0;
};

// The step limit of the rule above, s (> 0; +∞ where no eigenvalue limits
// the step). Throws std::invalid_argument where the model's linearisation
// is not finite at the start values (a NaN limit).
double AutoStepLimit(const AxisStructure& structure, const AxisParams<double>& params,
                     const std::vector<ParameterRange>& ranges);

// The step for a record of output period `output_period` (s, > 0) under
// `limit` (AutoStepLimit), by the rule above; `control_period` > 0 in
// closed loop (T_s a whole number of steps, within 10⁻⁶ of a step), else 0.
// Throws std::invalid_argument if no step T_o/n, n up to 10⁴, qualifies (a
// control period incommensurate with the output period).
double AutoStep(double limit, double output_period, double control_period);

// One line for the logs and report.json: "step chosen from the model (…)".
std::string AutoStepNote(double limit);

}  // namespace axis

#endif  // SIM_AUTO_STEP_H_
