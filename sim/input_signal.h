// Input signals U(t) for open-loop experiments (set-velocity voltage, V) and
// for additive injection in closed loop: step, ramp, sine, chirp, PRBS,
// piecewise-linear table, and a column of a data file.
#ifndef SIM_INPUT_SIGNAL_H_
#define SIM_INPUT_SIGNAL_H_

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace axis {

// The cubic B-spline of a uniformly sampled table (MakeCubic; defined in
// input_signal.cc around boost::math::interpolators::cardinal_cubic_b_spline).
struct CubicSpline;

// One input signal; `kind` picks which fields matter. Times in s, values in
// the input's unit (V for U). Built by the config loader or the Make*
// functions below; Evaluate never throws.
struct InputSignal {
  enum class Kind { kZero, kStep, kRamp, kSine, kChirp, kTable };
  Kind kind = Kind::kZero;
  double offset = 0.0;     // added to every kind
  double start = 0.0;      // s: step time, ramp/sine/chirp start
  double amplitude = 0.0;  // step height, sine/chirp amplitude
  double slope = 0.0;      // ramp, unit/s
  double frequency = 0.0;  // sine, Hz
  double phase = 0.0;      // sine, rad
  double f0 = 0.0, f1 = 0.0, sweep_time = 0.0;  // linear chirp f0 → f1 Hz over sweep_time s
  // kTable: sample times (strictly increasing) and values; linear
  // interpolation, or zero-order hold if `hold` (a sample applies from its
  // time on; within 1e-9 mean periods before it counts as reached, against
  // clock rounding); constant outside the range.
  // PRBS and data-file columns are tables.
  std::vector<double> times, values;
  bool hold = false;
  // Set by MakeCubic: a cubic B-spline through the samples instead of
  // straight lines (a smooth signal sampled at h: error O(h⁴) against
  // linear's O(h²)); constant outside the range as the others.
  std::shared_ptr<const CubicSpline> cubic;

  // U(t).
  double Evaluate(double t) const;
  // U(t) for non-decreasing t: `cursor` (start at 0) remembers the table
  // segment of the last call, making a table lookup O(1) instead of a
  // binary search in the simulation loop. Same values as Evaluate(t).
  double Evaluate(double t, size_t* cursor) const;
};

// Makes the table `s` interpolate by a cubic B-spline through its samples
// (boost::math::interpolators::cardinal_cubic_b_spline, end derivatives
// estimated from the data): the reconstruction for a smooth input sampled
// by a recorder (issue 10: linear interpolation of a 1 kHz sine leaves an
// input error that a microsecond sensor delay absorbs). Throws
// std::invalid_argument "expected …, got …" unless `s` is a table of at
// least 5 samples uniformly spaced (every spacing within 1e-6 of the median)
// and not held.
void MakeCubic(InputSignal* s);

// The most bits a PRBS table may hold: 10⁸ (1.6 GB of times and values;
// e.g. 28 h of 1 ms bits, or 1000 s of 10 µs bits, the default RK4 step).
// A bit_time of 1e-11 s over 4 s (found by fuzzing the experiment loader)
// asked for 4·10¹¹ bits.
constexpr double kMaxPrbsBits = 1e8;

// The number of bits MakePrbs stores for `duration` s of `bit_time` s bits:
// ceil(duration / bit_time) + 1 (a double: it may exceed every integer
// type; +inf or NaN for a zero or non-finite bit_time). Never throws.
double PrbsTableBits(double duration, double bit_time);

// A maximum-length pseudo-random binary sequence of ±amplitude (plus
// offset) switching every `bit_time` s from t = 0 to `duration`, from a
// Fibonacci LFSR of `order` bits (2..20) seeded with `seed` (non-zero in the
// low `order` bits; 0 is replaced by 1). The sequence is stored as a held
// table of ceil(duration / bit_time) + 1 bits, at most kMaxPrbsBits. Throws
// std::invalid_argument on an order outside 2..20, non-positive
// bit_time/duration, or more than kMaxPrbsBits bits (checked before
// allocating).
InputSignal MakePrbs(double amplitude, double offset, double bit_time,
                     int order, std::uint32_t seed, double duration);

}  // namespace axis

#endif  // SIM_INPUT_SIGNAL_H_
