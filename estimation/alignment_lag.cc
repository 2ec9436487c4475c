#include "estimation/alignment_lag.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One experiment's measured and simulated samples of the channel.
struct Pair {
  const std::vector<double>* y;
  const std::vector<double>* yhat;
};

// Mean of (y_k − ŷ_{k−L})² over the overlap of every pair.
double MisfitAtLag(const std::vector<Pair>& pairs, long lag) {
  double sum = 0.0;
  long count = 0;
  for (const Pair& p : pairs) {
    const long n = static_cast<long>(p.y->size());
    for (long k = std::max(0L, lag); k < std::min(n, n + lag); ++k) {
      const double d = (*p.y)[k] - (*p.yhat)[k - lag];
      sum += d * d;
      ++count;
    }
  }
  return count > 0 ? sum / count : kNaN;
}

}  // namespace

double AlignmentLag(const FitResult& fit, const std::string& channel, double max_lag) {
  std::vector<Pair> pairs;
  double period = 0.0;
  long shortest = std::numeric_limits<long>::max();
  for (const ExperimentFit& e : fit.experiments) {
    if (e.role != "fit" || e.t.size() < 2) continue;
    for (const ChannelFit& c : e.channels) {
      if (!c.fitted || c.channel != channel || c.measured.size() != c.simulated.size()) continue;
      pairs.push_back({&c.measured, &c.simulated});
      if (period == 0.0) period = e.t[1] - e.t[0];
      shortest = std::min(shortest, static_cast<long>(c.measured.size()));
    }
  }
  if (pairs.empty() || shortest < 8 || !(period > 0.0)) return kNaN;
  // Whole lags up to max_lag, and never more than half the shortest record
  // (the overlap must hold most of it).
  const long reach =
      std::min(static_cast<long>(std::floor(std::abs(max_lag) / period)), shortest / 2);
  long best = 0;
  double best_misfit = MisfitAtLag(pairs, 0);
  for (long lag = -reach; lag <= reach; ++lag) {
    const double m = MisfitAtLag(pairs, lag);
    if (m < best_misfit) {
      best_misfit = m;
      best = lag;
    }
  }
  // The parabola through the best lag and its neighbours.
  double fraction = 0.0;
  if (best > -reach && best < reach) {
    const double below = MisfitAtLag(pairs, best - 1), above = MisfitAtLag(pairs, best + 1);
    const double curvature = below - 2.0 * best_misfit + above;
    if (curvature > 0.0) fraction = std::clamp(0.5 * (below - above) / curvature, -0.5, 0.5);
  }
  return (static_cast<double>(best) + fraction) * period;
}

}  // namespace axis
