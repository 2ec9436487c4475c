#include "estimation/internal/rough_optimum.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/format.h"

namespace axis {

double RoughTolerance(double s2, double resolution) {
  const double tol = 0.5 * kRoughChi2 * s2;
  return std::isfinite(tol) ? std::max(tol, resolution) : resolution;
}

void RoughRounds::Restarted(double decrease, double scale, double tolerance) {
  last_decrease_ = decrease;
  last_scale_ = scale;
  if (decrease < tolerance) {
    ++small_in_a_row_;
    small_decrease_ += decrease;
    if (small_in_a_row_ >= kRoughRounds) rough_ = true;
  } else if (!rough_) {
    small_in_a_row_ = 0;
    small_decrease_ = 0.0;
  }
}

std::string RoughCostNote(const RoughRounds& rounds, double s2) {
  if (!rounds.rough()) return "";
  std::ostringstream note;
  note << "the cost is rough below the standard-error scale: " << rounds.small_rounds()
       << " probe rounds in a row each lowered chi^2 by less than " << kRoughChi2
       << "·s^2 (in all " << FormatNumber(2.0 * rounds.small_decrease(), 3)
       << ", the last at " << FormatNumber(rounds.last_scale(), 2)
       << " standard deviations), so lower points count only past chi^2 "
       << FormatNumber(kRoughChi2 * s2, 3)
       << ": the estimate is within that of a local minimum; declare the sensors' sampling "
          "and bandwidth (e.g. the period-mean accelerometer), or trust intervals at the "
          "smooth scale or the bootstrap (uncertainty.bootstrap)";
  return note.str();
}

}  // namespace axis
