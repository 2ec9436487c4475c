#include "sim/input_signal.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <string>

#include <boost/math/interpolators/cardinal_cubic_b_spline.hpp>

namespace axis {

struct CubicSpline {
  boost::math::interpolators::cardinal_cubic_b_spline<double> spline;
};

namespace {

constexpr double kTwoPi = 6.283185307179586476925;

// Zero-order hold: a sample applies from its time stamp on; a time within
// 1e-9 mean sample periods before it counts as reached, so that a simulation
// clock that lands an ulp short of a sample time (k·h summed or multiplied
// differently) still takes the new sample.
double HoldSlack(const std::vector<double>& times) {
  return 1e-9 * (times.back() - times.front()) / static_cast<double>(times.size() - 1);
}

double EvaluateTable(const std::vector<double>& times,
                     const std::vector<double>& values, bool hold, double t) {
  if (times.empty()) return 0.0;
  if (hold && times.size() > 1) t += HoldSlack(times);
  if (t <= times.front()) return values.front();
  if (t >= times.back()) return values.back();
  const auto upper = std::upper_bound(times.begin(), times.end(), t);
  const size_t k = static_cast<size_t>(upper - times.begin()) - 1;
  if (hold) return values[k];
  const double s = (t - times[k]) / (times[k + 1] - times[k]);
  return values[k] + s * (values[k + 1] - values[k]);
}

}  // namespace

double InputSignal::Evaluate(double t) const {
  const double tau = t - start;
  switch (kind) {
    case Kind::kZero:
      return offset;
    case Kind::kStep:
      return offset + (tau >= 0.0 ? amplitude : 0.0);
    case Kind::kRamp:
      return offset + (tau > 0.0 ? slope * tau : 0.0);
    case Kind::kSine:
      return offset +
             (tau >= 0.0 ? amplitude * std::sin(kTwoPi * frequency * tau + phase)
                         : 0.0);
    case Kind::kChirp: {
      if (tau < 0.0 || tau > sweep_time) return offset;
      const double cycles =
          f0 * tau + 0.5 * (f1 - f0) * tau * tau / sweep_time;
      return offset + amplitude * std::sin(kTwoPi * cycles);
    }
    case Kind::kTable:
      if (cubic && t > times.front() && t < times.back()) return offset + cubic->spline(t);
      return offset + EvaluateTable(times, values, hold, t);
  }
  return offset;
}

double InputSignal::Evaluate(double t, size_t* cursor) const {
  if (kind != Kind::kTable || times.size() < 2 || cubic) return Evaluate(t);
  if (hold) t += HoldSlack(times);
  if (t <= times.front() || t >= times.back()) {
    return offset + EvaluateTable(times, values, false, t);
  }
  size_t k = *cursor < times.size() - 1 ? *cursor : 0;
  while (k > 0 && times[k] > t) --k;  // event sub-steps look back
  while (times[k + 1] <= t) ++k;
  *cursor = k;
  if (hold) return offset + values[k];
  const double s = (t - times[k]) / (times[k + 1] - times[k]);
  // Same association as EvaluateTable + offset in Evaluate(t): bit-identical.
  return offset + (values[k] + s * (values[k + 1] - values[k]));
}

void MakeCubic(InputSignal* s) {
  if (s->kind != InputSignal::Kind::kTable || s->hold) {
    throw std::invalid_argument(
        "cubic interpolation: expected a table or data column read without hold, got " +
        std::string(s->hold ? "a held table" : "a profile"));
  }
  const size_t n = s->times.size();
  if (n < 5) {
    throw std::invalid_argument("cubic interpolation: expected at least 5 samples, got " +
                                std::to_string(n));
  }
  const double h = (s->times.back() - s->times.front()) / static_cast<double>(n - 1);
  // Each spacing against the median one, not the mean h: one dropped sample
  // skews h, and every spacing then looked wrong but the gap's.
  std::vector<double> spacings(n - 1);
  for (size_t k = 1; k < n; ++k) spacings[k - 1] = s->times[k] - s->times[k - 1];
  const auto middle = spacings.begin() + static_cast<std::ptrdiff_t>(spacings.size() / 2);
  std::nth_element(spacings.begin(), middle, spacings.end());
  const double median = *middle;
  for (size_t k = 1; k < n; ++k) {
    const double spacing = s->times[k] - s->times[k - 1];
    if (!(std::abs(spacing - median) <= 1e-6 * median)) {
      throw std::invalid_argument(
          "cubic interpolation: expected uniformly spaced samples (median spacing " +
          std::to_string(median) + " s), got a spacing of " + std::to_string(spacing) +
          " s at sample " + std::to_string(k));
    }
  }
  s->cubic = std::make_shared<const CubicSpline>(CubicSpline{
      boost::math::interpolators::cardinal_cubic_b_spline<double>(
          s->values.data(), n, s->times.front(), h)});
}

double PrbsTableBits(double duration, double bit_time) {
  return std::ceil(duration / bit_time) + 1.0;
}

InputSignal MakePrbs(double amplitude, double offset, double bit_time,
                     int order, std::uint32_t seed, double duration) {
  // Feedback taps of maximum-length Fibonacci LFSRs (Xilinx XAPP052 table),
  // 1-based bit positions, for orders 2..20; 0 pads the two-tap entries.
  // Orders 8, 12, 13, 14, 16 and 19 have no primitive trinomial and need
  // four taps.
  static const int kTaps[21][4] = {
      {0, 0, 0, 0},      {0, 0, 0, 0},     {2, 1, 0, 0},    {3, 2, 0, 0},
      {4, 3, 0, 0},      {5, 3, 0, 0},     {6, 5, 0, 0},    {7, 6, 0, 0},
      {8, 6, 5, 4},      {9, 5, 0, 0},     {10, 7, 0, 0},   {11, 9, 0, 0},
      {12, 6, 4, 1},     {13, 4, 3, 1},    {14, 5, 3, 1},   {15, 14, 0, 0},
      {16, 15, 13, 4},   {17, 14, 0, 0},   {18, 11, 0, 0},  {19, 6, 2, 1},
      {20, 17, 0, 0}};
  if (order < 2 || order > 20) {
    throw std::invalid_argument("PRBS: expected order in 2..20, got " +
                                std::to_string(order));
  }
  if (!(bit_time > 0.0) || !(duration > 0.0)) {
    throw std::invalid_argument(
        "PRBS: expected positive bit_time and duration, got " +
        std::to_string(bit_time) + " and " + std::to_string(duration));
  }
  const double table_bits = PrbsTableBits(duration, bit_time);
  if (!(table_bits <= kMaxPrbsBits)) {
    std::ostringstream message;
    message << std::setprecision(3) << "PRBS: expected at most " << kMaxPrbsBits
            << " bits (duration / bit_time), got " << table_bits << " (duration " << duration
            << " s, bit_time " << bit_time << " s): lengthen bit_time or shorten the duration";
    throw std::invalid_argument(message.str());
  }
  const std::uint32_t mask = (1u << order) - 1u;
  std::uint32_t reg = seed & mask;
  if (reg == 0) reg = 1;
  InputSignal s;
  s.kind = InputSignal::Kind::kTable;
  s.hold = true;
  s.offset = offset;
  const long bits = static_cast<long>(table_bits);
  s.times.reserve(static_cast<size_t>(bits));
  s.values.reserve(static_cast<size_t>(bits));
  for (long k = 0; k < bits; ++k) {
    s.times.push_back(k * bit_time);
    s.values.push_back((reg & 1u) ? amplitude : -amplitude);
    std::uint32_t feedback = 0;
    for (int tap : kTaps[order]) {
      if (tap > 0) feedback ^= (reg >> (tap - 1)) & 1u;
    }
    reg = ((reg << 1) | feedback) & mask;
  }
  return s;
}

}  // namespace axis
