// The sampled-data position controller of MODEL.md §5 (the AID 600 "slave
// control unit", also used for the EMPS rig): encoder quantisation, track
// interpolation, a PID-type law with feed-forward and filtered velocity,
// saturation and a delay of whole control periods.
#ifndef SIM_CONTROLLER_H_
#define SIM_CONTROLLER_H_

#include <cmath>
#include <vector>

#include "sim/axis_params.h"
#include "sim/input_shaper.h"
#include "sim/input_signal.h"
#include "sim/scalar.h"

namespace axis {

// A smart servo's position loop as its firmware runs it (MODEL.md §5,
// `type: servo_firmware`; e.g. a Dynamixel's "Position P/I/D Gain"
// registers): every T_s the error in encoder counts, e = (x_ref − x)·
// counts_per_rev/2π, gives the PWM value kp/kp_divisor·e + ki/ki_divisor·Σe
// − kd/kd_divisor·Δx_counts, clamped to ±pwm_limit; the duty cycle is that
// over pwm_full_scale, and the bridge applies duty·V_in to the motor
// (Drive::supply). The encoder is on the load (output shaft). The
// derivative acts on the measured position (on the error, as some firmware
// has it, it would also kick at reference steps). Gains ≥ 0 in firmware
// units; divisors and the PWM scale > 0, pwm_limit in (0, pwm_full_scale].
struct ServoFirmware {
  bool enabled = false;
  double kp = 0.0, ki = 0.0, kd = 0.0;
  double kp_divisor = 128.0, ki_divisor = 65536.0, kd_divisor = 16.0;
  double pwm_full_scale = 885.0;
  double pwm_limit = 885.0;
  double counts_per_rev = 4096.0;
  // false: the loop sees the position unquantised (a fit's cost is then
  // smooth in the parameters; the count is below the noise).
  bool quantized = true;
};

// Controller settings, MODEL.md §5. Defaults are the AID 600 values
// (assumed there). Times in s, gains in the units given.
struct ControllerConfig {
  double T_s = 0.005;      // control period (s), > 0
  double T_track = 0.08;   // track period of the master (s), > 0
  double G_ff = 10.0;      // velocity feed-forward (V·s/m)
  double G_p = 300.0;      // proportional gain (V/m)
  double G_i = 0.0;        // integral gain (V/(m·s))
  double G_v = 0.0;        // velocity feedback gain (V·s/m)
  double alpha = 1.0;      // position filter weight α, in [0, 1]
  double U_max = 10.0;     // output saturation (V), > 0
  int delay_samples = 0;   // output delay in control periods, ≥ 0
  // Position feedback: a motor encoder with counts_per_rev counts per motor
  // revolution (x_meas = r_g·θ quantised), or, if load_quantum > 0, a
  // load-side encoder with that quantum (m). counts_per_rev = 0 with
  // load_quantum = 0 means an ideal load-side measurement.
  double counts_per_rev = 8000.0;
  double load_quantum = 0.0;
  // The firmware loop these gains were made from (FirmwareLaw), if any:
  // the gains above are then in duty per rad of load travel.
  ServoFirmware firmware;
};

// The law of MODEL.md §5 that runs `f` with control period T_s (s, > 0):
// G_p = kp/kp_divisor·c/pwm_full_scale, G_i = ki/ki_divisor·c/
// pwm_full_scale/T_s, G_v = kd/kd_divisor·c/pwm_full_scale·T_s with c =
// counts_per_rev/2π counts per rad, U_max = pwm_limit/pwm_full_scale (a
// duty cycle), no feed-forward, α = 1, track period T_s, a load-side
// encoder of quantum 2π/counts_per_rev (none unless quantized); `delay`
// control periods of output delay. Never throws (the loader checks the
// ranges).
ControllerConfig FirmwareLaw(const ServoFirmware& f, double T_s, int delay);

// The quantum of the position the controller sees, in m of load travel:
// load_quantum if > 0, else r_g·2π/counts_per_rev for the motor encoder
// (r_g in m/rad), 0 for an ideal measurement (ControllerUpdate below).
double PositionQuantum(const ControllerConfig& c, double r_g);

// The reference the controller tracks, MODEL.md §5: a move (trapezoidal,
// or minimum-jerk) sampled by the master every T_track and interpolated
// linearly by the slave, or a reference position column read at every
// control sample.
struct Reference {
  enum class Kind { kTrapezoid, kMinJerk, kTable };
  Kind kind = Kind::kTrapezoid;
  // A move: signed distance D (m), start time (s), starting position (m),
  // and its limits: set velocity v_s (m/s, > 0), acceleration a_s (m/s²,
  // > 0) and, for the minimum-jerk move, jerk j_s (m/s³, > 0; +inf: none).
  double distance = 0.0, velocity = 1.0, acceleration = 1.0, start = 0.0,
         origin = 0.0;
  double jerk = HUGE_VAL;
  // Table: reference position samples (m), linearly interpolated.
  InputSignal table;
  // A move's input shaper (sim/input_shaper.h; none by default): the
  // profile convolved with its impulses, Σ A_i·P(t − t_i).
  InputShaper shaper;

  // Continuous profile position at time t (m; a move only): the trapezoid
  // (triangular where v_s is not reached), or the minimum-jerk quintic
  // D·(10τ³ − 15τ⁴ + 6τ⁵), τ = (t − start)/T, over the shortest T whose
  // peaks 1.875·D/T, (10/√3)·D/T² and 60·D/T³ respect v_s, a_s and j_s
  // (Flash & Hogan 1985, the minimum of ∫ jerk² dt between rests); with a
  // shaper, Σ A_i·(UnshapedProfile(t − t_i) − origin) + origin.
  double Profile(double t) const;
  // The profile without the shaper (m).
  double UnshapedProfile(double t) const;
  // s from start to the end of the move (a move only), the shaper's
  // duration included.
  double MoveDuration() const;
};

// Reference position and velocity seen by the slave at control time t_k.
struct ReferenceSample {
  double x_ref = 0.0;  // m
  double v_ref = 0.0;  // m/s
};

// The slave's reference at control sample k (time t = k·T_s): for a
// trapezoid, linear interpolation between the track points p_j =
// Profile(j·T_track) with v_ref the slope of the current segment; for a table,
// the interpolated column with v_ref the backward difference over T_s.
ReferenceSample SampleReference(const Reference& ref,
                                const ControllerConfig& c, long k);

// Controller memory between samples.
template <typename T>
struct ControllerState {
  long k = 0;          // next sample index
  T integral{0.0};     // Σ e_j (m)
  T x_meas_prev{0.0};  // x_meas,k−1
  T x_f_prev{0.0};     // x_f,k−1
  std::vector<T> pending;  // outputs waiting out the delay, oldest first
};

// Runs one control sample: measures the position from state y (motor angle
// y2 through r_g, or arm position y0 for a load-side encoder), applies the
// law of MODEL.md §5 and returns the output that reaches the plant now (the
// one computed delay_samples periods ago, 0 before that). Never throws.
template <typename T>
T ControllerUpdate(const ControllerConfig& c, const AxisParams<T>& p,
                   const Eigen::Matrix<T, 7, 1>& y, const ReferenceSample& ref,
                   ControllerState<T>* s) {
  constexpr double kTwoPi = 6.283185307179586476925;
  T x_meas;
  if (c.load_quantum > 0.0) {
    x_meas = Quantize(y[0], c.load_quantum);
  } else if (c.counts_per_rev > 0.0) {
    x_meas = p.r_g * Quantize(y[2], kTwoPi / c.counts_per_rev);
  } else {
    x_meas = y[0];
  }
  const bool first = s->k == 0;
  const T x_prev = first ? x_meas : s->x_meas_prev;
  const T x_f = T(c.alpha) * x_meas + T(1.0 - c.alpha) * x_prev;
  const T v_meas = first ? T(0.0) : T((x_f - s->x_f_prev) / T(c.T_s));
  const T e = T(ref.x_ref) - x_meas;
  s->integral += e;
  T u = T(c.G_ff * ref.v_ref) + T(c.G_p) * e +
        T(c.G_i * c.T_s) * s->integral - T(c.G_v) * v_meas;
  if (u > T(c.U_max)) u = T(c.U_max);
  if (u < T(-c.U_max)) u = T(-c.U_max);
  s->x_meas_prev = x_meas;
  s->x_f_prev = x_f;
  ++s->k;
  if (c.delay_samples == 0) return u;
  s->pending.push_back(u);
  if (static_cast<int>(s->pending.size()) <= c.delay_samples) return T(0.0);
  const T out = s->pending.front();
  s->pending.erase(s->pending.begin());
  return out;
}

}  // namespace axis

#endif  // SIM_CONTROLLER_H_
