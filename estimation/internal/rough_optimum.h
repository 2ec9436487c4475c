// A cost rough below the standard-error scale (issue 42): the optimum
// check's probe rounds that each find a point lower by a little, the solver
// restarting there again and again (14–48 rounds on records sampled at the
// instant across backlash contacts, MODEL.md §6). RoughRounds counts them;
// past kRoughRounds in a row the fit (estimation/internal/fitter.cc CheckOptimum)
// judges lower points by RoughTolerance instead of the solver's resolution,
// which bounds the rounds, and RoughCostNote says so.
#ifndef ESTIMATION_INTERNAL_ROUGH_OPTIMUM_H_
#define ESTIMATION_INTERNAL_ROUGH_OPTIMUM_H_

#include <string>

namespace axis {

// A restart that lowers χ² (= 2·cost) by less than this many units of s²
// moved the estimate within its one-standard-error contour (χ² rises by 1
// at one standard error of a quadratic cost, by s² with residual variance
// s²): a gain that changes no interval.
constexpr double kRoughChi2 = 1.0;
// Rounds in a row with such a gain that make the cost rough.
constexpr int kRoughRounds = 2;

// ½·kRoughChi2·s2 in cost units (½χ²), at least `resolution`
// (CostResolution, estimation/optimum_check.h); `resolution` for NaN s2.
// Never throws.
double RoughTolerance(double s2, double resolution);

// The probe rounds of one fit, in order.
class RoughRounds {
 public:
  // A round that restarted the solver and lowered the cost by `decrease`
  // (cost units) with the lowest probe at `scale` standard deviations,
  // judged against `tolerance` (RoughTolerance). A round with a larger gain
  // resets the count.
  void Restarted(double decrease, double scale, double tolerance);
  bool rough() const { return rough_; }
  int small_rounds() const { return small_in_a_row_; }
  double last_decrease() const { return last_decrease_; }  // cost units
  double last_scale() const { return last_scale_; }        // standard deviations
  double small_decrease() const { return small_decrease_; }  // sum, cost units

 private:
  bool rough_ = false;
  int small_in_a_row_ = 0;
  double last_decrease_ = 0.0;
  double last_scale_ = 0.0;
  double small_decrease_ = 0.0;
};

// The one line of FitResult::optimum_check on a rough cost: the rounds, the
// gain they found in χ² units of s² (`s2`), the tolerance it now verifies
// to, and what to do. "" unless rounds.rough(). Never throws.
std::string RoughCostNote(const RoughRounds& rounds, double s2);

}  // namespace axis

#endif  // ESTIMATION_INTERNAL_ROUGH_OPTIMUM_H_
