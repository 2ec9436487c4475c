#include "sim/controller.h"

#include <algorithm>
#include <cmath>

namespace axis {

namespace {

// The minimum-jerk move's duration for distance d > 0 within the limits.
double MinJerkDuration(double d, double v, double a, double j) {
  double T = 1.875 * d / v;
  T = std::max(T, std::sqrt(10.0 / std::sqrt(3.0) * d / a));
  if (std::isfinite(j)) T = std::max(T, std::cbrt(60.0 * d / j));
  return T;
}

}  // namespace

double Reference::MoveDuration() const {
  const double d = std::abs(distance);
  if (d == 0.0) return 0.0;
  const double shaping = shaper.Duration();
  if (kind == Kind::kMinJerk) return MinJerkDuration(d, velocity, acceleration, jerk) + shaping;
  const double v_peak = std::min(velocity, std::sqrt(d * acceleration));
  return 2.0 * v_peak / acceleration + (d - v_peak * v_peak / acceleration) / v_peak + shaping;
}

double Reference::Profile(double t) const {
  if (shaper.type == ShaperType::kNone) return UnshapedProfile(t);
  double x = origin;
  for (size_t i = 0; i < shaper.amplitudes.size(); ++i) {
    x += shaper.amplitudes[i] * (UnshapedProfile(t - shaper.times[i]) - origin);
  }
  return x;
}

double Reference::UnshapedProfile(double t) const {
  const double tau = t - start;
  if (tau <= 0.0 || distance == 0.0) return origin;
  const double d = std::abs(distance);
  const double sign = distance > 0.0 ? 1.0 : -1.0;
  if (kind == Kind::kMinJerk) {
    const double T = MinJerkDuration(d, velocity, acceleration, jerk);
    const double u = std::min(1.0, tau / T);
    return origin + sign * d * u * u * u * (10.0 - 15.0 * u + 6.0 * u * u);
  }
  // Triangular if the set velocity cannot be reached.
  const double v_peak = std::min(velocity, std::sqrt(d * acceleration));
  const double t_acc = v_peak / acceleration;
  const double d_acc = 0.5 * acceleration * t_acc * t_acc;
  const double t_cruise = (d - 2.0 * d_acc) / v_peak;
  const double t_end = 2.0 * t_acc + t_cruise;
  double s;
  if (tau < t_acc) {
    s = 0.5 * acceleration * tau * tau;
  } else if (tau < t_acc + t_cruise) {
    s = d_acc + v_peak * (tau - t_acc);
  } else if (tau < t_end) {
    const double r = t_end - tau;
    s = d - 0.5 * acceleration * r * r;
  } else {
    s = d;
  }
  return origin + sign * s;
}

double PositionQuantum(const ControllerConfig& c, double r_g) {
  constexpr double kTwoPi = 6.283185307179586476925;
  if (c.load_quantum > 0.0) return c.load_quantum;
  if (c.counts_per_rev > 0.0) return r_g * kTwoPi / c.counts_per_rev;
  return 0.0;
}

ReferenceSample SampleReference(const Reference& ref,
                                const ControllerConfig& c, long k) {
  const double t = k * c.T_s;
  ReferenceSample out;
  if (ref.kind != Reference::Kind::kTable) {
    const double j = std::floor(t / c.T_track + 1e-9);
    const double t0 = j * c.T_track;
    const double p0 = ref.Profile(t0);
    const double p1 = ref.Profile(t0 + c.T_track);
    out.v_ref = (p1 - p0) / c.T_track;
    out.x_ref = p0 + out.v_ref * (t - t0);
  } else {
    out.x_ref = ref.table.Evaluate(t);
    out.v_ref = k == 0 ? 0.0
                       : (out.x_ref - ref.table.Evaluate(t - c.T_s)) / c.T_s;
  }
  return out;
}

ControllerConfig FirmwareLaw(const ServoFirmware& f, double T_s, int delay) {
  constexpr double kTwoPi = 6.283185307179586476925;
  const double counts_per_rad = f.counts_per_rev / kTwoPi;
  const double duty_per_count = 1.0 / f.pwm_full_scale;
  ControllerConfig c;
  c.T_s = T_s;
  c.T_track = T_s;
  c.G_ff = 0.0;
  c.G_p = f.kp / f.kp_divisor * counts_per_rad * duty_per_count;
  c.G_i = f.ki / f.ki_divisor * counts_per_rad * duty_per_count / T_s;
  c.G_v = f.kd / f.kd_divisor * counts_per_rad * duty_per_count * T_s;
  c.alpha = 1.0;
  c.U_max = f.pwm_limit / f.pwm_full_scale;
  c.delay_samples = delay;
  c.counts_per_rev = 0.0;
  c.load_quantum = f.quantized ? kTwoPi / f.counts_per_rev : 0.0;
  c.firmware = f;
  c.firmware.enabled = true;
  return c;
}

}  // namespace axis
