#include "estimation/internal/fit_callbacks.h"

#include <algorithm>
#include <iomanip>
#include <optional>
#include <sstream>

namespace axis {

ceres::CallbackReturnType ProgressPrinter::operator()(const ceres::IterationSummary& s) {
  if (progress_ != nullptr && progress_->terminal()) {
    std::ostringstream detail;
    detail << "iter " << s.iteration << ", cost " << std::setprecision(6) << s.cost;
    progress_->Detail(detail.str());
  } else if (out_ != nullptr && plain_lines_) {
    *out_ << "start " << std::setw(2) << start_ << "  horizon "
          << std::fixed << std::setprecision(3) << horizon_ << " s  iter "
          << std::setw(3) << s.iteration << "  cost " << std::scientific
          << std::setprecision(6) << s.cost << "  rel.decrease "
          << std::setprecision(3) << s.relative_decrease << "  step "
          << s.step_norm << std::defaultfloat << "\n";
    out_->flush();
  }
  return ceres::SOLVER_CONTINUE;
}

const std::pair<size_t, double>* FirstPassed(
    const std::vector<std::pair<size_t, double>>& bounds, double above) {
  for (const auto& entry : bounds) {
    if (entry.second > above) return &entry;
  }
  return nullptr;
}

}  // namespace axis
