#include "estimation/shared_level.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace axis {

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

}  // namespace axis
