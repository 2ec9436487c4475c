// One simulated experiment: the axis model (sim/axis_model.h) integrated by
// fixed-step RK4 (sim/rk4.h), driven open loop by U(t) or in closed loop by
// the sampled controller of MODEL.md §5, with the channels of MODEL.md §6
// recorded at a fixed output rate and the sensor effects of §7 applied.
// Templated on the scalar (double or ceres::Jet).
#ifndef SIM_SIMULATE_H_
#define SIM_SIMULATE_H_

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

#include "sim/axis_model.h"
#include "sim/channels.h"
#include "sim/controller.h"
#include "sim/input_signal.h"
#include "sim/rk4.h"
#include "sim/scalar.h"
#include "sim/sensor_front_end.h"
#include "sim/simulation_count.h"
#include "sim/switched_rk4.h"

namespace axis {

// An open-loop input U (V) sampled once at the times every RK4 step of a
// grid evaluates it (sim/rk4.h: t, t + h/2, t + h with t = n·h, n = 0 …
// num_steps), with the very expressions Simulate uses for those times, so
// that a lookup returns the same double as evaluating U there. A fit
// simulates one experiment hundreds of times on the same grid; the lookup
// replaces U's evaluation at every stage (a table's interpolation, a sine),
// 7–8 % of a fit's samples (perf, issue 11).
struct StageInputs {
  double step = 0.0;               // h (s) of the grid it was sampled on
  std::vector<double> at_start;    // U(n·h), num_steps + 1 entries
  std::vector<double> at_half;     // U(n·h + 0.5·h)
  std::vector<double> at_end;      // U(n·h + h)
};

// What drives the axis.
struct Drive {
  // Open loop: U(t), the set-velocity voltage (V).
  InputSignal input;
  // Closed loop (MODEL.md §5): the controller computes U from `reference`;
  // `injection`, if any, is added to its output (sampled at the control
  // instants and held), and the channel u shows the sum.
  bool closed_loop = false;
  ControllerConfig controller;
  Reference reference;
  bool has_injection = false;
  InputSignal injection;
  // Closed loop, optional: the controller's output is a duty cycle that a
  // PWM bridge turns into volts from this supply voltage (V), read at the
  // control instants (a smart servo's firmware loop, MODEL.md §5); U is
  // their product.
  bool has_supply = false;
  InputSignal supply;
  // Optional (MODEL.md §4 drive enable): the drive is on where this signal
  // is at least 0.5, off elsewhere; read at the start of each RK4 step and
  // held over it (a switch between grid points applies from the next step).
  bool has_enable = false;
  InputSignal enable;
  // Optional, open loop only: `input` at the stage times of the grid
  // (MakeStageInputs). Simulate uses it where its step equals the grid's
  // and it covers the grid, and evaluates `input` otherwise (and at the
  // sub-steps of located events); for a table made from this drive's
  // `input` the trace is the same either way. Nothing ties the two: a
  // drive whose `input` changes must drop or remake it.
  std::shared_ptr<const StageInputs> stage_inputs;
};

// Time grid of a run (s). step must divide output_period and, in closed
// loop, the control period T_s.
struct SimulationOptions {
  double duration = 1.0;        // s, > 0
  double step = 1e-5;           // RK4 step h, s, > 0
  double output_period = 1e-3;  // s, multiple of step
  std::vector<Channel> channels;  // recorded channels (t is always recorded)
  // With the instant accelerometer (MODEL.md §6) and `a` recorded: also
  // record y1' itself at the sample instants, through the same front end
  // (Trace::a_point), for the window's spread (estimation/
  // instant_sample_sigma.h). Costs a derivative evaluation per RK4 step.
  bool point_acceleration = false;
  // A record that starts in motion (`initial_state: from_samples` or
  // `estimate`): an inductive voltage drive's winding current y6 starts at
  // its steady value for the first input and speed, (U(0) − K_e·ω(0))/R
  // with the drive on (0 with it off), instead of the initial state's y6 —
  // the drive was running before the record began (MODEL.md §4). No effect
  // on any other drive.
  bool settled_current = false;
};

// The integer grid derived from SimulationOptions.
struct SimulationGrid {
  double step = 0.0;
  long num_steps = 0;           // duration / step
  long steps_per_output = 1;
  long steps_per_control = 0;   // 0 in open loop
  long num_outputs = 0;         // samples at 0, output_period, ... ≤ duration
};

// Checks the options against the drive and derives the grid. Throws
// std::invalid_argument ("expected …, got …") on a non-positive duration or
// step, or an output or control period that is not a whole number of steps.
SimulationGrid MakeGrid(const SimulationOptions& options, const Drive& drive);

// `drive.input` at the stage times of `grid` (StageInputs), or null where
// Simulate would not evaluate it at the stage times: closed loop, or an
// input held over each step (zero, a step, a held table). 24 bytes per
// step (a 2 s record at 10 µs: 4.8 MB). Throws only std::bad_alloc.
std::shared_ptr<const StageInputs> MakeStageInputs(const Drive& drive,
                                                   const SimulationGrid& grid);

// Recorded channels: values[c][k] at time t[k] for every requested c; the
// others are empty. `finite` is false if the state left the finite numbers,
// in which case the remaining samples are NaN.
template <typename T>
struct Trace {
  std::vector<double> t;
  std::array<std::vector<T>, kNumChannels> values;
  bool finite = true;
  // SimulationOptions::point_acceleration: y1' at t[k] (m/s², no window),
  // through the delay, low-pass filters and bias of `a`; else empty.
  std::vector<T> a_point;

  const std::vector<T>& operator[](Channel c) const {
    return values[static_cast<int>(c)];
  }
};

// What the integration of the plant records before the sensor front end of
// MODEL.md §6 (SimulatePlant): `trace` holds t and every wanted channel at
// the output samples as the plant gives it (for `a`, v where the front end
// or the period mean forms it from v); `fine` the per-step history of the
// channels read between output samples (HasGridFrontEnd), `fine_point` y1'
// at every step for Trace::a_point, `a_initial` y1'(0). Only the sensor
// parameters (tau_d, b, tau_lp, tau_lp2, zeta_lp2) act after it
// (ApplySensorFrontEnd), so a fit may integrate the plant with derivatives
// of the plant's parameters alone (estimation/experiment_cost.h).
template <typename T>
struct PlantRecord {
  Trace<T> trace;
  std::array<bool, kNumChannels> wanted{};
  std::array<bool, kNumChannels> on_grid{};
  std::array<std::vector<T>, kNumChannels> fine;
  std::vector<T> fine_point;
  bool point = false;  // Trace::a_point wanted
  T a_initial = T(0.0);
};

// The record with every value mapped by f (From → To), e.g. to change the
// derivative parts of Jets; flags and times copied.
template <typename To, typename From, typename F>
PlantRecord<To> MapPlantRecord(const PlantRecord<From>& in, const F& f) {
  const auto map = [&f](const std::vector<From>& v) {
    std::vector<To> out;
    out.reserve(v.size());
    for (const From& x : v) out.push_back(f(x));
    return out;
  };
  PlantRecord<To> out;
  out.trace.t = in.trace.t;
  out.trace.finite = in.trace.finite;
  for (int c = 0; c < kNumChannels; ++c) {
    out.trace.values[c] = map(in.trace.values[c]);
    out.fine[c] = map(in.fine[c]);
  }
  out.trace.a_point = map(in.trace.a_point);
  out.wanted = in.wanted;
  out.on_grid = in.on_grid;
  out.fine_point = map(in.fine_point);
  out.point = in.point;
  out.a_initial = f(in.a_initial);
  return out;
}

// Whether channel c's recorded samples are read off its values at every RK4
// step (sim/sensor_front_end.h): a delay or a low-pass on it, or the
// instant accelerometer (the mean of y1' over ±instant_window, from v). A bias alone,
// and the period-mean accelerometer alone, work on the output samples.
inline bool HasGridFrontEnd(const AxisStructure& structure, Channel c) {
  const int k = static_cast<int>(c);
  const SensorSwitches& s = structure.sensors;
  return s.delay[k] || s.lowpass[k] || s.lowpass2[k] ||
         (c == Channel::kA && structure.accelerometer == AccelerometerSampling::kInstant);
}

// True if Simulate holds `input` over each RK4 step at its value at the
// step's start (open loop): zero, a step, or a table read with hold.
inline bool IsHeldInput(const InputSignal& input) {
  return input.kind == InputSignal::Kind::kZero || input.kind == InputSignal::Kind::kStep ||
         (input.kind == InputSignal::Kind::kTable && input.hold);
}

// True if `s` (may be null) was sampled on `grid`'s step and covers its
// steps: a table of a longer record on the same step serves a shorter one
// (the horizon stages of a fit share their experiment's).
inline bool StageInputsCover(const StageInputs* s, const SimulationGrid& grid) {
  return s != nullptr && s->step == grid.step &&
         s->at_start.size() > static_cast<size_t>(grid.num_steps) &&
         s->at_half.size() == s->at_start.size() && s->at_end.size() == s->at_start.size();
}

namespace internal {

// Channel c's samples at `times` from its values `s` on the RK4 grid (step
// h): the low-pass filters, then the delay, of MODEL.md §6.
template <typename T>
std::vector<T> FrontEndSamples(const AxisStructure& structure, const AxisParams<T>& params,
                               int c, double h, const std::vector<double>& times,
                               std::vector<T> s) {
  if (structure.sensors.lowpass[c]) s = LowPassOnGrid(s, h, 1, params.tau_lp[c], T(1.0));
  if (structure.sensors.lowpass2[c]) {
    s = LowPassOnGrid(s, h, 2, params.tau_lp2[c], params.zeta_lp2[c]);
  }
  std::vector<T> out(times.size());
  for (size_t j = 0; j < times.size(); ++j) {
    T time(times[j]);
    if (structure.sensors.delay[c]) time -= params.tau_d[c];
    out[j] = ValueOnGrid(s, h, time);
  }
  return out;
}

template <typename T>
T ChannelValue(Channel c, const AxisStructure& s, const AxisParams<T>& p,
               const AxisState<T>& y, const AxisAux<T>& aux, const T& u,
               const ReferenceSample& ref, double t) {
  const bool rigid = s.coupling == Coupling::kRigid;
  switch (c) {
    case Channel::kT: return T(t);
    case Channel::kU: return u;
    case Channel::kX: return y[0];
    case Channel::kV: return y[1];
    case Channel::kA: return aux.a;
    case Channel::kTheta: return rigid ? T(y[0] / p.r_g) : y[2];
    case Channel::kOmega: return rigid ? T(y[1] / p.r_g) : y[3];
    case Channel::kI: return aux.i;
    case Channel::kTach:
      return p.K_t * (rigid ? T(y[1] / p.r_g) : y[3]);
    case Channel::kVc: return aux.vc;
    case Channel::kVm: return aux.vm;
    case Channel::kFg: return aux.fg;
    case Channel::kForce: return aux.force;
    case Channel::kXRef: return T(ref.x_ref);
    case Channel::kVRef: return T(ref.v_ref);
  }
  return T(0.0);
}

template <typename T>
bool StateIsFinite(const AxisState<T>& y) {
  for (int k = 0; k < kNumStates; ++k) {
    if (!std::isfinite(ScalarValue(y[k]))) return false;
  }
  return true;
}

// The values of a parameter set as another scalar: the derivative parts of
// Jets dropped (To = double), or zero (To a Jet).
template <typename To, typename From>
AxisParams<To> ParamsAs(const AxisParams<From>& p) {
  AxisParams<To> out;
  VisitParams([](const char*, const char*, const From& from, To& to) {
    to = To(ScalarValue(from));
  }, p, out);
  return out;
}

// The values of a parameter set (drops the derivative parts of Jets).
template <typename T>
AxisParams<double> ParamValues(const AxisParams<T>& p) {
  return ParamsAs<double>(p);
}

// The axis as a switched system for Rk4SwitchedStep, with two families of
// regions: the branches of MODEL.md eq. 5 (GearContact −1, 0, +1, ordered by
// X; guards X − H and X + H), if `gear` (gear coupling with backlash), and
// the sides of the preamp limit of eq. 2 (PreampRegion −1, 0, +1, ordered by
// y4 + T_z·y5; guards y4 + T_z·y5 ∓ V_L), if `preamp` (analog velocity
// loop: under the quasi-steady current loop the current's rate carries
// V_c', under the full loop V_c has a corner there).
// Guards are negated when crossing downwards. A family that is off stays in
// its middle region and its branch is taken from the state. Mode =
// 3·(contact + 1) + (side + 1). `input_at` maps t (s) to U as a T.
template <typename T, typename Input>
struct SwitchedAxis {
  static constexpr int kFamilies = 2;
  const AxisStructure& structure;
  const AxisParams<T>& params;
  const AxisCoefficients<T>& coeffs;
  const AxisParams<double>& values;
  const AxisCoefficients<double>& value_coeffs;
  // The values again as EventTimeJet (zero derivative part), for the
  // event-time sensitivity of sim/switched_rk4.h.
  const AxisParams<EventTimeJet>& event_params;
  const AxisCoefficients<EventTimeJet>& event_coeffs;
  const Input& input_at;
  bool gear = false;
  bool preamp = false;
  // The event-time rule of sim/switched_rk4.h: the step's own for the
  // preamp limit under the full current loop, where V_c has a corner (the
  // flow's saltation is zero there, but the step's result depends on where
  // the corner falls in it through the stiff current loop, h·λ ≈ −1.4 at
  // 10 µs); the flow's saltation for the gear contacts and under the
  // quasi-steady loop, where the field jumps and the two rules agree to the
  // order of the step.
  bool full_loop = false;
  bool StepOwnEventSensitivity(int from, int to) const {
    return full_loop && FamilyOf(from, to) == 1;
  }

  static int ContactOf(int mode) { return mode / 3 - 1; }
  static int SideOf(int mode) { return mode % 3 - 1; }
  // The branches a mode fixes for AxisDerivative (kFromState where the
  // family is off).
  GearContact ContactIn(int mode) const {
    return gear ? static_cast<GearContact>(ContactOf(mode)) : GearContact::kFromState;
  }
  PreampRegion SideIn(int mode) const {
    return preamp ? static_cast<PreampRegion>(SideOf(mode)) : PreampRegion::kFromState;
  }

  template <typename S>
  void Derivative(double t, const AxisState<S>& y, int mode,
                  AxisState<S>* dy) const {
    const GearContact contact = ContactIn(mode);
    const PreampRegion side = SideIn(mode);
    if constexpr (std::is_same<S, T>::value) {
      AxisDerivative(structure, params, coeffs, y, input_at(t), dy,
                     static_cast<AxisAux<T>*>(nullptr), contact, side, input_at.drive_on());
    } else {
      AxisDerivative(structure, values, value_coeffs, y,
                     ScalarValue(input_at(t)), dy,
                     static_cast<AxisAux<double>*>(nullptr), contact, side,
                     input_at.drive_on());
    }
  }
  void EventDerivative(double t, const EventTimeState<kNumStates>& y,
                       int mode, EventTimeState<kNumStates>* dy) const {
    const GearContact contact = ContactIn(mode);
    const PreampRegion side = SideIn(mode);
    AxisDerivative(structure, event_params, event_coeffs, y,
                   EventTimeJet(ScalarValue(input_at(t))), dy,
                   static_cast<AxisAux<EventTimeJet>*>(nullptr), contact, side,
                   input_at.drive_on());
  }
  double GuardRate(const AxisState<double>& dy, int from, int to) const {
    const double rate = FamilyOf(from, to) == 0 ? values.r_g * dy[2] - dy[0]
                                                : dy[4] + values.T_z * dy[5];
    return to > from ? rate : -rate;
  }
  int Mode(const AxisState<double>& y) const {
    const int contact =
        gear ? static_cast<int>(GearContactOf(values.r_g * y[2] - y[0], values.H)) : 0;
    const int side =
        preamp ? static_cast<int>(PreampRegionOf<double>(y[4] + values.T_z * y[5], values.V_L)) : 0;
    return 3 * (contact + 1) + side + 1;
  }
  int Toward(int from, int to, int family) const {
    const int a = family == 0 ? ContactOf(from) : SideOf(from);
    const int b = family == 0 ? ContactOf(to) : SideOf(to);
    if (a == b) return from;
    const int step = b > a ? 1 : -1;
    return from + (family == 0 ? 3 * step : step);
  }
  // The family in which `from` and `to` (neighbours) differ: 0 or 1.
  static int FamilyOf(int from, int to) { return ContactOf(from) != ContactOf(to) ? 0 : 1; }
  template <typename S>
  S Guard(const AxisState<S>& y, int from, int to) const {
    const AxisParams<S>* p;
    if constexpr (std::is_same<S, T>::value) {
      p = &params;
    } else {
      p = &values;
    }
    S g;
    if (FamilyOf(from, to) == 0) {
      const S gap = p->r_g * y[2] - y[0];
      // Between kFree and kPositive the boundary is X = H, else X = −H.
      g = (ContactOf(from) == 1 || ContactOf(to) == 1) ? S(gap - p->H) : S(gap + p->H);
    } else {
      const S pre_vc = y[4] + p->T_z * y[5];
      // Between kLinear and kHigh the boundary is V_L, else −V_L.
      g = (SideOf(from) == 1 || SideOf(to) == 1) ? S(pre_vc - p->V_L) : S(pre_vc + p->V_L);
    }
    return to > from ? g : S(-g);
  }
};

}  // namespace internal

namespace internal {

// The input U (V) at the stage times of the step being taken, as Simulate
// evaluates it: the controller's held output in closed loop; an open-loop
// piecewise-constant input (a held table: a PRBS, a recorded column; a
// step) held over each RK4 step at its value at the step's start, as the
// controller's output is; a smooth one from Drive::stage_inputs where they
// cover the grid, else evaluated, the last two evaluations remembered (RK4
// asks for U at t, t + h/2 twice and t + h, the next step's t: the memo
// halves the lookups).
//
// Why hold: the value a sample applies on [t_k, t_k+1) is then what every
// stage of a step in that interval sees. Evaluated at the stage times, the
// last stage of the step ending at t_k+1 took the next sample's value,
// which at a reversal moved the preamp across its limits inside the step
// by a stage's weight (y5 jumps by h/6 of K1·ΔU/(T_p·T_r)), where no event
// can be located. A switch between grid points (a step's `start`, a table
// off the grid) applies from the next step.
template <typename T>
class StageInput {
 public:
  StageInput(const Drive& drive, const SimulationGrid& grid)
      : drive_(drive),
        h_(grid.step),
        held_(!drive.closed_loop && IsHeldInput(drive.input)),
        stages_(!drive.closed_loop && !held_ &&
                        StageInputsCover(drive.stage_inputs.get(), grid)
                    ? drive.stage_inputs.get()
                    : nullptr) {}

  // Step n starts at t = n·h: the held input takes its value there.
  void BeginStep(long n, double t) {
    step_n_ = n;
    step_t_ = t;
    if (held_) u_step_ = drive_.input.Evaluate(t, &cursor_);
    if (drive_.has_enable) on_ = drive_.enable.Evaluate(t, &enable_cursor_) >= 0.5;
  }
  // Whether the drive is on over the step being taken (Drive::enable).
  bool drive_on() const { return on_; }
  // The controller's output (closed loop), held until the next update.
  void SetHeld(const T& u) { u_held_ = u; }
  const T& held() const { return u_held_; }

  T operator()(double t) const {
    if (drive_.closed_loop) return u_held_;
    if (held_) return T(u_step_);
    if (stages_ != nullptr) {
      if (t == step_t_) return T(stages_->at_start[step_n_]);
      if (t == step_t_ + 0.5 * h_) return T(stages_->at_half[step_n_]);
      if (t == step_t_ + h_) return T(stages_->at_end[step_n_]);
    }
    if (t == memo_t_[0]) return T(memo_u_[0]);
    if (t == memo_t_[1]) return T(memo_u_[1]);
    const double u = drive_.input.Evaluate(t, &cursor_);
    memo_t_[memo_next_] = t;
    memo_u_[memo_next_] = u;
    memo_next_ ^= 1;
    return T(u);
  }

 private:
  const Drive& drive_;
  const double h_;
  const bool held_;
  const StageInputs* const stages_;
  long step_n_ = 0;      // the step being taken
  double step_t_ = 0.0;  // its start, step_n·h
  double u_step_ = 0.0;  // the held input over it
  T u_held_ = T(0.0);
  bool on_ = true;
  size_t enable_cursor_ = 0;
  mutable size_t cursor_ = 0;
  mutable double memo_t_[2] = {-1.0, -1.0};
  mutable double memo_u_[2] = {0.0, 0.0};
  mutable int memo_next_ = 0;
};

// One run of SimulatePlant as named steps, its state in members: which
// channels are recorded at every RK4 step, the events of the switched
// system, the loop (the controller, the recording, the step) and the padding
// of a run that went non-finite. Internal to SimulatePlant.
template <typename T>
class Simulation {
 public:
  Simulation(const AxisStructure& structure, const AxisParams<T>& params,
             const AxisState<T>& y_init, const Drive& drive, const SimulationOptions& options,
             const SimulationGrid& grid, const std::function<void(double)>& progress)
      : structure_(structure),
        params_(params),
        drive_(drive),
        options_(options),
        grid_(grid),
        progress_(progress),
        h_(grid.step),
        a_mean_(structure.accelerometer == AccelerometerSampling::kPeriodMean),
        settle_current_(options.settled_current &&
                        structure.amplifier == Amplifier::kVoltageDrive && structure.inductance),
        y_(y_init),
        input_(drive, grid),
        coeffs_(MakeAxisCoefficients(structure, params)),
        values_(ParamValues(params)),
        gear_events_(structure.coupling == Coupling::kGear && values_.H > 0.0),
        preamp_events_(structure.amplifier == Amplifier::kAnalogVelocityLoop),
        switched_(gear_events_ || preamp_events_),
        value_coeffs_(switched_ ? MakeAxisCoefficients(structure, values_)
                                : AxisCoefficients<double>{}),
        event_params_(switched_ ? ParamsAs<EventTimeJet>(values_) : AxisParams<EventTimeJet>{}),
        event_coeffs_(switched_ ? MakeAxisCoefficients(structure, event_params_)
                                : AxisCoefficients<EventTimeJet>{}),
        system_{structure,    params,       coeffs_,        values_,
                value_coeffs_, event_params_, event_coeffs_, input_,
                gear_events_, preamp_events_,
                structure.amplifier == Amplifier::kAnalogVelocityLoop &&
                    structure.current_loop == CurrentLoop::kFull} {}
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // The plant's record (PlantRecord); a run that went non-finite is padded
  // with NaN.
  PlantRecord<T> Run() {
    ChooseChannels();
    Integrate();
    if (!record_.trace.finite) PadNonFinite();
    return std::move(record_);
  }

 private:
  static constexpr int kA = static_cast<int>(Channel::kA);

  // A channel with a front end other than a bias is recorded at every RK4
  // step (sim/sensor_front_end.h; for `a` its source, v): a delay, a
  // low-pass, or the instant accelerometer, read between output samples.
  // y1' itself beside the instant accelerometer's window (Trace::a_point).
  void ChooseChannels() {
    record_.trace.t.reserve(grid_.num_outputs);
    for (Channel c : options_.channels) {
      const int k = static_cast<int>(c);
      record_.wanted[k] = true;
      record_.trace.values[k].reserve(grid_.num_outputs);
      if (HasGridFrontEnd(structure_, c)) {
        record_.on_grid[k] = any_on_grid_ = true;
        aux_every_step_ = aux_every_step_ || k != kA;
      }
    }
    record_.point = options_.point_acceleration && record_.wanted[kA] && !a_mean_;
    if (record_.point) aux_every_step_ = any_on_grid_ = true;
    for (int k = 0; k < kNumChannels; ++k) {
      if (record_.on_grid[k]) record_.fine[k].reserve(grid_.num_steps + 1);
    }
  }

  // The steps of the grid: the controller's update at its instants, the
  // recording, the step. Gear contacts with backlash (eq. 5) and the preamp
  // limits of eq. 2 are events located inside the step, with the
  // sensitivities carried across them (sim/switched_rk4.h). Without
  // backlash (H = 0) the gear force is continuous in the state and a plain
  // RK4 step is exact to its order. Under the quasi-steady current loop the
  // current's rate carries V_c', which jumps at the preamp limits; under the
  // full loop V_c is continuous but has a corner, which inside a step made
  // the cost rough at the scale of a standard error on records that
  // saturate the preamp often (a ±6 V square wave: two local solves from
  // nearby starts ended k_g and T_p more than a standard error apart).
  void Integrate() {
    const auto rhs = [&](double t, const AxisState<T>& state, AxisState<T>* dy) {
      AxisDerivative(structure_, params_, coeffs_, state, input_(t), dy,
                     static_cast<AxisAux<T>*>(nullptr), GearContact::kFromState,
                     PreampRegion::kFromState, input_.drive_on());
    };
    const long progress_every = std::max(1L, grid_.num_steps / 100);
    AxisState<double> y_values;
    for (int k = 0; k < kNumStates; ++k) y_values[k] = ScalarValue(y_[k]);
    int mode = system_.Mode(y_values);
    for (long n = 0; n <= grid_.num_steps; ++n) {
      const double t = n * h_;
      input_.BeginStep(n, t);
      if (drive_.closed_loop && n % grid_.steps_per_control == 0) Control(n, t);
      if (n == 0 && settle_current_) SettleCurrent(t);
      if (!Record(n, t)) return;
      if (n == grid_.num_steps) break;
      if (switched_) {
        mode = Rk4SwitchedStep(system_, t, h_, mode, &y_);
      } else {
        Rk4Step(rhs, t, h_, &y_);
      }
      if (progress_ && n % progress_every == 0) {
        progress_(static_cast<double>(n) / grid_.num_steps);
      }
    }
  }

  // SimulationOptions::settled_current: y6 at the winding's steady current
  // for the input and speed at `t` (the record's start).
  void SettleCurrent(double t) {
    y_[6] = input_.drive_on() ? T((input_(t) - params_.K_e * y_[3]) / params_.R) : T(0.0);
  }

  // The controller of MODEL.md §5 at control instant n / steps_per_control,
  // its output held (plus the injection, if any).
  void Control(long n, double t) {
    const long k = n / grid_.steps_per_control;
    ref_ = SampleReference(drive_.reference, drive_.controller, k);
    T u = ControllerUpdate(drive_.controller, params_, y_, ref_, &controller_);
    if (drive_.has_supply) u *= drive_.supply.Evaluate(t);
    if (drive_.has_injection) u += T(drive_.injection.Evaluate(t));
    input_.SetHeld(u);
  }

  // The channels at step n: at an output sample every wanted one, and
  // between them those recorded on the grid. False (trace.finite false) if
  // the state at an output sample is not finite.
  bool Record(long n, double t) {
    const bool record = n % grid_.steps_per_output == 0;
    if (!record && !aux_every_step_) {
      if (any_on_grid_) record_.fine[kA].push_back(y_[1]);  // `a` alone on the grid: v
      return true;
    }
    if (record && !StateIsFinite(y_)) {
      record_.trace.finite = false;
      return false;
    }
    AxisState<T> dy;
    AxisAux<T> aux;
    const T u = input_(t);
    AxisDerivative(structure_, params_, coeffs_, y_, u, &dy, &aux, GearContact::kFromState,
                   PreampRegion::kFromState, input_.drive_on());
    for (int c = 0; c < kNumChannels; ++c) {
      if (!record_.wanted[c] || !(record || record_.on_grid[c])) continue;
      // The accelerometer records v here (its source: AccelerationOnGrid).
      const T value = c == kA && (a_mean_ || record_.on_grid[c])
                          ? y_[1]
                          : ChannelValue(static_cast<Channel>(c), structure_, params_, y_, aux,
                                         u, ref_, t);
      if (c == kA && n == 0) record_.a_initial = aux.a;
      if (c == kA && record_.point) record_.fine_point.push_back(aux.a);
      if (record_.on_grid[c]) record_.fine[c].push_back(value);
      if (record) record_.trace.values[c].push_back(value);
    }
    if (record) record_.trace.t.push_back(t);
    return true;
  }

  // A run that went non-finite: NaN for every output sample it did not
  // reach.
  void PadNonFinite() {
    const T nan(std::numeric_limits<double>::quiet_NaN());
    Trace<T>& trace = record_.trace;
    for (long j = static_cast<long>(trace.t.size()); j < grid_.num_outputs; ++j) {
      trace.t.push_back(j * grid_.steps_per_output * h_);
      for (int c = 0; c < kNumChannels; ++c) {
        if (record_.wanted[c]) trace.values[c].push_back(nan);
      }
    }
  }

  const AxisStructure& structure_;
  const AxisParams<T>& params_;
  const Drive& drive_;
  const SimulationOptions& options_;
  const SimulationGrid& grid_;
  const std::function<void(double)>& progress_;
  const double h_;
  const bool a_mean_;  // the period-mean accelerometer
  const bool settle_current_;  // SimulationOptions::settled_current, an inductive voltage drive

  PlantRecord<T> record_;
  bool any_on_grid_ = false;     // some channel is recorded at every step
  bool aux_every_step_ = false;  // one other than `a` (needs the derivative)

  AxisState<T> y_;
  ReferenceSample ref_;
  ControllerState<T> controller_;
  StageInput<T> input_;
  const AxisCoefficients<T> coeffs_;
  const AxisParams<double> values_;
  const bool gear_events_;
  const bool preamp_events_;
  const bool switched_;
  const AxisCoefficients<double> value_coeffs_;
  // The values as EventTimeJet (zero derivative part) for the event-time
  // sensitivity of sim/switched_rk4.h.
  const AxisParams<EventTimeJet> event_params_;
  const AxisCoefficients<EventTimeJet> event_coeffs_;
  const SwitchedAxis<T, StageInput<T>> system_;
};

}  // namespace internal

// The sensor front end of MODEL.md §6 (sim/sensor_front_end.h) on a
// plant's record made on `grid` (SimulatePlant): the accelerometer's
// convention, the low-pass filters and the delay on the grid, then the
// bias, with the sensor parameters of `params` (the others are not read).
// A record that went non-finite is returned as it is. Never throws.
template <typename T>
Trace<T> ApplySensorFrontEnd(const AxisStructure& structure, const AxisParams<T>& params,
                             const SimulationGrid& grid, PlantRecord<T> record) {
  constexpr int kA = static_cast<int>(Channel::kA);
  if (!record.trace.finite) return std::move(record.trace);
  const double h = grid.step;
  const bool a_mean = structure.accelerometer == AccelerometerSampling::kPeriodMean;
  const double period = grid.steps_per_output * h;
  Trace<T>& trace = record.trace;
  for (int c = 0; c < kNumChannels; ++c) {
    if (!record.wanted[c]) continue;
    std::vector<T>& out = trace.values[c];
    if (record.on_grid[c]) {
      std::vector<T> s =
          c == kA ? AccelerationOnGrid(record.fine[c], h, a_mean ? grid.steps_per_output : 0,
                                       InstantWindowSteps(structure.instant_window, h),
                                       record.a_initial)
                  : std::move(record.fine[c]);
      out = internal::FrontEndSamples(structure, params, c, h, trace.t, std::move(s));
      if (c == kA && record.point) {
        trace.a_point = internal::FrontEndSamples(structure, params, c, h, trace.t,
                                                  std::move(record.fine_point));
      }
    } else if (c == kA && a_mean) {
      // The period mean from v at the output samples; y1'(0) at t = 0.
      for (size_t j = out.size(); j-- > 1;) out[j] = (out[j] - out[j - 1]) / T(period);
      if (!out.empty()) out[0] = record.a_initial;
    }
    if (structure.sensors.bias[c]) {
      for (T& value : out) value += params.b[c];
      if (c == kA) {
        for (T& value : trace.a_point) value += params.b[c];
      }
    }
  }
  return std::move(record.trace);
}

// The plant of one experiment integrated from y_init on the grid of
// MakeGrid(), before the sensor front end (PlantRecord; Simulate is
// ApplySensorFrontEnd of it). The sensor parameters of `params` are not
// read. Counted once (sim/simulation_count.h), with derivatives if
// `counted_with_derivatives` (by default where T is a Jet: a Jacobian whose
// plant has no free parameter integrates it in double). Never throws; a run
// that goes non-finite has trace.finite false and NaN for the samples it
// did not reach.
template <typename T>
PlantRecord<T> SimulatePlant(const AxisStructure& structure, const AxisParams<T>& params,
                             const AxisState<T>& y_init, const Drive& drive,
                             const SimulationOptions& options, const SimulationGrid& grid,
                             const std::function<void(double)>& progress = nullptr,
                             bool counted_with_derivatives = !std::is_same_v<T, double>) {
  internal::CountSimulation(counted_with_derivatives);
  return internal::Simulation<T>(structure, params, y_init, drive, options, grid, progress).Run();
}

// Simulates one experiment from initial state y_init on the grid of
// MakeGrid(). A smooth open-loop input is evaluated at the RK4 stage times;
// a piecewise-constant one (a held table, a step, zero) is held over each
// step at its value at the step's start, as the controller output is (a
// switch between grid points applies from the next step;
// internal::StageInput). Gear contacts and, with the analog velocity loop,
// the preamp limits are events located inside the step
// (sim/switched_rk4.h). The sensor effects enabled in structure.sensors
// act on the recorded channels: sensor_bias adds b.<channel>; sensor_delay
// records the channel at t − tau_d.<channel> (linear interpolation between
// RK4 steps, the value at t = 0 before the start). `progress`, if set, is
// called with the completed fraction about every 1 % of the run. The steps:
// internal::Simulation. Never throws (the grid is checked by MakeGrid); a
// run that goes non-finite returns early with finite = false.
template <typename T>
Trace<T> Simulate(const AxisStructure& structure, const AxisParams<T>& params,
                  const AxisState<T>& y_init, const Drive& drive,
                  const SimulationOptions& options, const SimulationGrid& grid,
                  const std::function<void(double)>& progress = nullptr) {
  return ApplySensorFrontEnd(
      structure, params, grid,
      SimulatePlant(structure, params, y_init, drive, options, grid, progress));
}

// Instantiated once, in sim/simulate.cc, for double and for the
// one-direction Jet (EventTimeJet: the score test's candidate columns and
// the residual-only evaluations' guard, estimation/experiment_cost.h): the
// translation units that simulate in those link to that copy instead of
// compiling their own (each saved about 4 s of a build). The wider Jets are
// instantiated where a fit's costs are built (estimation/experiment_cost.cc).
#define AXIS_SIMULATE_INSTANCES(PREFIX, T)                                                    \
  PREFIX template PlantRecord<T> SimulatePlant<T>(                                           \
      const AxisStructure&, const AxisParams<T>&, const AxisState<T>&, const Drive&,         \
      const SimulationOptions&, const SimulationGrid&, const std::function<void(double)>&,   \
      bool);                                                                                 \
  PREFIX template Trace<T> ApplySensorFrontEnd<T>(const AxisStructure&, const AxisParams<T>&, \
                                                  const SimulationGrid&, PlantRecord<T>);    \
  PREFIX template Trace<T> Simulate<T>(const AxisStructure&, const AxisParams<T>&,            \
                                       const AxisState<T>&, const Drive&,                    \
                                       const SimulationOptions&, const SimulationGrid&,      \
                                       const std::function<void(double)>&);
AXIS_SIMULATE_INSTANCES(extern, double)
AXIS_SIMULATE_INSTANCES(extern, EventTimeJet)

}  // namespace axis

#endif  // SIM_SIMULATE_H_
