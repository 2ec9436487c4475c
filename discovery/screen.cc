#include "discovery/screen.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "estimation/fit.h"
#include "estimation/fit_control.h"
#include "estimation/fit_result.h"
#include "job/fit_job.h"

namespace axis {

std::vector<ScreenedFit> ScreenFits(std::vector<FitJob> jobs, int threads) {
  for (FitJob& j : jobs) {
    if (!(j.solver.first_horizon > 0.0)) {
      throw std::invalid_argument(
          "ScreenFits: expected jobs with solver.first_horizon > 0 (a horizon continuation), "
          "got " + std::to_string(j.solver.first_horizon) + " s");
    }
  }
  std::vector<FitControl> controls(jobs.size());
  for (size_t k = 0; k < jobs.size(); ++k) {
    controls[k].stop_after_horizon =
        jobs[k].solver.first_horizon * std::pow(2.0, kScreenStages - 1);
  }
  std::vector<double> seconds;
  const std::vector<FitResult> fits = FitConcurrently(jobs, threads, &seconds, controls);
  std::vector<ScreenedFit> out(fits.size());
  for (size_t k = 0; k < fits.size(); ++k) {
    out[k].bound =
        std::isfinite(fits[k].bic) ? fits[k].bic : std::numeric_limits<double>::infinity();
    out[k].seconds = seconds[k];
    out[k].checkpoint = fits[k].checkpoint;
  }
  return out;
}

std::string StoppedText(const FitResult& fit, double level, const std::string& level_name) {
  if (fit.abandoned_horizon == 0.0) return "";
  std::ostringstream out;
  out << std::setprecision(4) << "at the " << fit.abandoned_horizon
      << " s horizon: BIC >= " << fit.bic << " there already, more than " << kStopFactor
      << " times " << level_name << " (" << level << ")";
  return out.str();
}

}  // namespace axis
