#include "sim/input_shaper.h"

#include <cctype>
#include <cmath>
#include <complex>
#include <stdexcept>

namespace axis {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Amplitudes scaled to sum to 1.
std::vector<double> Normalised(std::vector<double> a) {
  double sum = 0.0;
  for (double x : a) sum += x;
  for (double& x : a) x /= sum;
  return a;
}

// Impulse i of a shaper with impulses every half damped period, each
// scaled by K^i: the undamped closed form a_i carried to ζ > 0.
std::vector<double> Decayed(std::vector<double> a, double K) {
  double k = 1.0;
  for (double& x : a) {
    x *= k;
    k *= K;
  }
  return a;
}

std::vector<double> HalfPeriods(size_t n, double T_d) {
  std::vector<double> t(n);
  for (size_t i = 0; i < n; ++i) t[i] = 0.5 * T_d * static_cast<double>(i);
  return t;
}

// Throws std::invalid_argument "<who>: expected …, got …" unless the mode
// has a finite frequency > 0 Hz and a damping ratio in [0, 1).
void CheckMode(const char* who, double frequency, double damping) {
  if (!(std::isfinite(frequency) && frequency > 0.0)) {
    throw std::invalid_argument(std::string(who) + ": expected a finite frequency > 0 Hz, got " +
                                std::to_string(frequency));
  }
  if (!(damping >= 0.0 && damping < 1.0)) {
    throw std::invalid_argument(std::string(who) + ": expected a damping ratio in [0, 1), got " +
                                std::to_string(damping));
  }
}

}  // namespace

InputShaper MakeInputShaper(ShaperType type, double frequency, double damping) {
  InputShaper s;
  s.type = type;
  if (type == ShaperType::kNone) return s;
  CheckMode("MakeInputShaper", frequency, damping);
  s.frequency = frequency;
  s.damping = damping;
  const double df = std::sqrt(1.0 - damping * damping);
  const double K = std::exp(-damping * kPi / df);
  const double T_d = 1.0 / (frequency * df);
  const double V = kShaperVibrationTolerance;
  switch (type) {
    case ShaperType::kZV:
      s.amplitudes = {1.0, K};
      s.times = HalfPeriods(2, T_d);
      break;
    case ShaperType::kZVD:
      s.amplitudes = {1.0, 2.0 * K, K * K};
      s.times = HalfPeriods(3, T_d);
      break;
    case ShaperType::kMZV: {
      const double Km = std::pow(K, 0.75);  // the decay over 3/8 of T_d
      const double a = 1.0 - 1.0 / std::sqrt(2.0);
      s.amplitudes = {a, (std::sqrt(2.0) - 1.0) * Km, a * Km * Km};
      s.times = {0.0, 0.375 * T_d, 0.75 * T_d};
      break;
    }
    case ShaperType::kEI:
      s.amplitudes = Decayed({0.25 * (1.0 + V), 0.5 * (1.0 - V), 0.25 * (1.0 + V)}, K);
      s.times = HalfPeriods(3, T_d);
      break;
    case ShaperType::k2HumpEI: {
      const double V2 = V * V;
      const double X = std::cbrt(V2 * (std::sqrt(1.0 - V2) + 1.0));
      const double a = (3.0 * X * X + 2.0 * X + 3.0 * V2) / (16.0 * X);
      s.amplitudes = Decayed({a, 0.5 - a, 0.5 - a, a}, K);
      s.times = HalfPeriods(4, T_d);
      break;
    }
    case ShaperType::k3HumpEI: {
      const double a = (1.0 + 3.0 * V + 2.0 * std::sqrt(2.0 * V * (V + 1.0))) / 16.0;
      const double b = 0.25 * (1.0 - V);
      s.amplitudes = Decayed({a, b, 1.0 - 2.0 * (a + b), b, a}, K);
      s.times = HalfPeriods(5, T_d);
      break;
    }
    case ShaperType::kNone:
      break;
  }
  s.amplitudes = Normalised(s.amplitudes);
  return s;
}

double ShaperVibration(const InputShaper& s, double frequency, double damping) {
  CheckMode("ShaperVibration", frequency, damping);
  const double w = 2.0 * kPi * frequency;
  const double wd = w * std::sqrt(1.0 - damping * damping);
  const double t_end = s.times.back();
  std::complex<double> sum = 0.0;
  for (size_t i = 0; i < s.amplitudes.size(); ++i) {
    // e^(−ζω(t_N − t_i)): each impulse's ringing has decayed by the end.
    sum += s.amplitudes[i] * std::exp(-damping * w * (t_end - s.times[i])) *
           std::polar(1.0, wd * s.times[i]);
  }
  return std::abs(sum);
}

const std::vector<std::string>& ShaperNames() {
  static const std::vector<std::string> names = {"none", "ZV",       "MZV",     "ZVD",
                                                 "EI",   "2HUMP_EI", "3HUMP_EI"};
  return names;
}

std::string ShaperName(ShaperType type) { return ShaperNames()[static_cast<size_t>(type)]; }

bool ParseShaperType(const std::string& name, ShaperType* type) {
  std::string upper;
  for (char c : name) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const std::vector<std::string>& names = ShaperNames();
  for (size_t k = 0; k < names.size(); ++k) {
    std::string n;
    for (char c : names[k]) n += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (n == upper) {
      *type = static_cast<ShaperType>(k);
      return true;
    }
  }
  return false;
}

}  // namespace axis
