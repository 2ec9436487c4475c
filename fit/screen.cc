#include "fit/screen.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "fit/fit.h"

namespace axis {

std::vector<ScreenedFit> ScreenFits(std::vector<FitJob> jobs, int threads) {
  for (FitJob& j : jobs) {
    if (!(j.solver.first_horizon > 0.0)) {
      throw std::invalid_argument(
          "ScreenFits: expected jobs with solver.first_horizon > 0 (a horizon continuation), "
          "got " + std::to_string(j.solver.first_horizon) + " s");
    }
    j.solver.stop_after_horizon = j.solver.first_horizon * std::pow(2.0, kScreenStages - 1);
  }
  std::vector<double> seconds;
  const std::vector<FitResult> fits = FitConcurrently(jobs, threads, &seconds);
  std::vector<ScreenedFit> out(fits.size());
  for (size_t k = 0; k < fits.size(); ++k) {
    out[k].bound =
        std::isfinite(fits[k].bic) ? fits[k].bic : std::numeric_limits<double>::infinity();
    out[k].seconds = seconds[k];
    out[k].checkpoint = fits[k].checkpoint;
  }
  return out;
}

SharedLevel::SharedLevel(double factor) : factor_(factor) {
  if (!(factor > 0.0)) {
    throw std::invalid_argument("SharedLevel: expected a factor > 0, got " +
                                std::to_string(factor));
  }
}

void SharedLevel::Publish(double bic) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (known_) return;
    known_ = true;
    bic_ = bic;
  }
  published_.notify_all();
}

double SharedLevel::Threshold() const {
  return std::isfinite(bic_) ? factor_ * bic_ : std::numeric_limits<double>::infinity();
}

std::optional<double> SharedLevel::TryAbandonAbove() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!known_) return std::nullopt;
  return Threshold();
}

double SharedLevel::AbandonAbove() const {
  std::unique_lock<std::mutex> lock(mutex_);
  published_.wait(lock, [this] { return known_; });
  return Threshold();
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
