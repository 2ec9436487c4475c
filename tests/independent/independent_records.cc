// independent-records: records of a servo axis made by a second, independent
// implementation of MODEL.md, for checking the tool on data it did not make
// (issues 56, 57). Written from MODEL.md's equations alone; it shares no code
// with sim/ (only the model configs' values, which it reads itself):
//
// - the integrator is an adaptive Dormand–Prince 5(4) pair (Dormand & Prince
//   1980; Hairer, Nørsett & Wanner, "Solving ODEs I", §II.5) with error
//   control, not fixed-step RK4; every change of a branch (gear contact of
//   eq. 5, preamp clamp of eq. 2, motor-voltage clamp of eq. 3, static
//   friction band of eq. 6) is located by bisection of the step to 1e-13 s
//   and the step restarted on the new branch;
// - the sensor front end is continuous-time: a first-order and a
//   second-order low-pass are ODE states driven by the plant's signal, the
//   period-mean accelerometer the integral of the (filtered) acceleration,
//   a delay a sample of the state's cubic Hermite interpolant at t − τ_d;
//   the `instant` accelerometer is a point sample of y1' (no window), the
//   period-mean one (the default, MODEL.md §6) the mean of y1' over the
//   output period ending at the sample;
// - noise is Gaussian from std::mt19937_64 through std::normal_distribution.
//
// Usage: independent-records SPEC.yaml --out DIR [--seed N] [--noise-free]
// Writes DIR/<record>.csv for each record of SPEC (columns t, then the
// spec's channels; u is the input as applied). SPEC (paths relative to it):
//   model: ../../configs/axes/x_axis.yaml   # amplifier, coupling, parameters, effects
//   set: {B_a: 200}                         # parameter overrides (optional)
//   effects: {coulomb: {F_c: 40}}           # plant effects added (optional)
//   duration: 4                             # s
//   output_rate: 1000                       # Hz
//   channels: [u, a, tach]
//   front_end:                              # per channel (optional)
//     a: {sampling: instant, delay: 0.003, lowpass: 4.0e-4,   # sampling: period_mean by default
//         lowpass2: {tau: 6.4e-4, zeta: 0.707}, bias: 0.0}
//   noise: {a: 0.02, tach: 0.005}           # σ per channel (channel unit)
//   seed: 7                                 # noise seed (record k: seed + k); --seed adds 1000·N
//   records:
//     - {name: square, input: {type: square, amplitude: 6, period: 1.0, start: 0.1}}
//     - {name: sweep, input: {type: sweep, amplitude: 5, f0: 0.3, f1: 3}}
//     - {name: stairs, input: {type: stairs, amplitude: 5, hold: [0.2, 0.6], seed: 3}}
//     - {name: prbs, input: {type: prbs, amplitude: 4, bit_time: 0.02, seed: 5}}
// Square waves and stairs switch on sample instants (a DAC's command); a
// sweep is continuous. Exit code 2 with a message on a bad spec.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void Fail(const std::string& what) { throw std::runtime_error(what); }

// ------------------------------------------------------------------ model

struct Model {
  std::string amplifier = "analog_velocity_loop";  // or current_source, force_source
  bool rigid = false;
  std::map<std::string, double> p;  // MODEL.md names
  // Effects of MODEL.md §7 in the plant.
  bool coulomb = false, stribeck = false, viscous_asymmetry = false, load_offset = false,
       spring = false, payload = false, motor_coulomb = false, cogging = false;
  int n_cog = 1;
  double P(const std::string& name) const {
    auto it = p.find(name);
    return it == p.end() ? 0.0 : it->second;
  }
};

void ReadEffects(const YAML::Node& effects, Model* m) {
  for (const auto& e : effects) {
    const std::string name = e.first.as<std::string>();
    bool* flag = name == "coulomb"             ? &m->coulomb
                 : name == "stribeck"          ? &m->stribeck
                 : name == "viscous_asymmetry" ? &m->viscous_asymmetry
                 : name == "load_offset"       ? &m->load_offset
                 : name == "spring"            ? &m->spring
                 : name == "payload"           ? &m->payload
                 : name == "motor_coulomb"     ? &m->motor_coulomb
                 : name == "cogging"           ? &m->cogging
                                               : nullptr;
    if (flag == nullptr) Fail("effects: expected a plant effect of MODEL.md section 7, got " + name);
    *flag = true;
    for (const auto& q : e.second) {
      const std::string key = q.first.as<std::string>();
      if (key == "N_cog") {
        m->n_cog = q.second.as<int>();
      } else {
        m->p[key] = q.second.as<double>();
      }
    }
  }
}

Model ReadModel(const std::string& path) {
  const YAML::Node root = YAML::LoadFile(path);
  Model m;
  m.amplifier = root["amplifier"].as<std::string>();
  m.rigid = root["coupling"].as<std::string>() == "rigid";
  for (const auto& q : root["parameters"]) m.p[q.first.as<std::string>()] = q.second.as<double>();
  if (root["effects"]) ReadEffects(root["effects"], &m);
  // MODEL.md defaults the configs may leave out.
  for (const auto& [k, v] : std::map<std::string, double>{{"w", 1e-3}, {"v_eps", 1e-3},
                                                          {"omega_eps", 1e-3}}) {
    if (!m.p.count(k)) m.p[k] = v;
  }
  return m;
}

// ------------------------------------------------------------------ inputs

struct Input {
  std::string type = "zero";
  double amplitude = 0.0, period = 1.0, start = 0.0, f0 = 0.0, f1 = 0.0, duration = 1.0;
  double bit_time = 0.02;
  std::vector<double> switch_times, levels;  // piecewise-constant inputs
  bool piecewise = false;

  double At(double t) const {
    if (type == "sweep") {
      const double phase = 2.0 * kPi * (f0 * t + 0.5 * (f1 - f0) * t * t / duration);
      return amplitude * std::sin(phase);
    }
    if (!piecewise) return 0.0;
    // Left-closed: the level applies from its switch time on.
    const auto it = std::upper_bound(switch_times.begin(), switch_times.end(), t);
    const size_t k = static_cast<size_t>(it - switch_times.begin());
    return k == 0 ? 0.0 : levels[k - 1];
  }
};

// Rounds t to the sample grid (a DAC switches on its sample instants).
double OnGrid(double t, double period) { return std::round(t / period) * period; }

Input ReadInput(const YAML::Node& n, double duration, double period) {
  Input in;
  in.type = n["type"].as<std::string>();
  in.amplitude = n["amplitude"].as<double>();
  in.duration = duration;
  if (in.type == "sweep") {
    in.f0 = n["f0"].as<double>();
    in.f1 = n["f1"].as<double>();
    return in;
  }
  in.piecewise = true;
  if (in.type == "square") {
    in.period = n["period"].as<double>();
    in.start = n["start"] ? n["start"].as<double>() : 0.0;
    double level = in.amplitude;
    for (double t = in.start; t < duration; t += 0.5 * in.period) {
      in.switch_times.push_back(OnGrid(t, period));
      in.levels.push_back(level);
      level = -level;
    }
  } else if (in.type == "stairs" || in.type == "prbs") {
    std::mt19937_64 rng(n["seed"] ? n["seed"].as<unsigned long>() : 1UL);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double lo = 0.0, hi = 0.0;
    if (in.type == "stairs") {
      lo = n["hold"][0].as<double>();
      hi = n["hold"][1].as<double>();
    } else {
      lo = hi = n["bit_time"].as<double>();
    }
    double level = in.amplitude;
    for (double t = n["start"] ? n["start"].as<double>() : 0.0; t < duration;
         t += lo + (hi - lo) * unit(rng)) {
      in.switch_times.push_back(OnGrid(t, period));
      if (in.type == "stairs") {
        level = in.amplitude * (2.0 * unit(rng) - 1.0);
      } else {
        level = unit(rng) < 0.5 ? -in.amplitude : in.amplitude;
      }
      in.levels.push_back(level);
    }
  } else {
    Fail("input.type: expected square, sweep, stairs or prbs, got " + in.type);
  }
  return in;
}

// ------------------------------------------------------------------ front end

struct FrontEnd {
  bool period_mean = false;  // `a` only: the mean of y1' over the output period
  double delay = 0.0;        // s, either sign
  double tau1 = 0.0;         // first-order low-pass (s), 0 = none
  double tau2 = 0.0, zeta2 = 0.70710678118654752;  // second order, 0 = none
  double bias = 0.0;
  double sigma = 0.0;
  int state = -1;  // first front-end state of this channel in z
  int n_states() const { return (tau1 > 0) + 2 * (tau2 > 0) + period_mean; }
};

// ------------------------------------------------------------------ the axis

enum { kX, kV, kTheta, kOmega, kY4, kY5, kI, kPlant };

// The branches a step holds: gear contact (−1, 0, +1), preamp side, motor
// voltage side, static-friction band (0 out, 1 in).
struct Mode {
  int contact = 0, preamp = 0, vm = 0, band = 0;
  bool operator==(const Mode& o) const {
    return contact == o.contact && preamp == o.preamp && vm == o.vm && band == o.band;
  }
};

struct Signals {
  double a = 0, i = 0, vc = 0, vm = 0, fg = 0, force = 0, u = 0;
};

class Axis {
 public:
  Axis(const Model& m, const Input& in, std::vector<std::string> channels,
       std::map<std::string, FrontEnd> fe)
      : m_(m), in_(in), channels_(std::move(channels)), fe_(std::move(fe)) {
    int next = kPlant;
    for (const std::string& c : channels_) {
      FrontEnd& f = fe_[c];
      if (f.n_states() > 0) {
        f.state = next;
        next += f.n_states();
      }
    }
    n_ = next;
    mass_ = m.P("M") + (m.payload ? m.P("Delta_M") : 0.0);
  }
  int size() const { return n_; }

  // The branches the state is in (MODEL.md eq. 2, 3, 5, 6).
  Mode ModeOf(const std::vector<double>& z) const {
    Mode md;
    if (!m_.rigid && m_.amplifier != "force_source") {
      const double gap = m_.P("r_g") * z[kTheta] - z[kX];
      const double h = m_.P("H");
      md.contact = gap > h ? 1 : gap < -h ? -1 : 0;
    }
    if (m_.amplifier != "force_source") {
      const double pre = z[kY4] + m_.P("T_z") * z[kY5];
      const double vl = m_.P("V_L");
      md.preamp = pre > vl ? 1 : pre < -vl ? -1 : 0;
      if (m_.amplifier == "analog_velocity_loop") {
        const double vc = md.preamp == 0 ? pre : md.preamp * vl;
        const double raw = m_.P("K_a") * (vc - z[kI] / m_.P("K_i"));
        const double vmax = m_.P("V_M");
        md.vm = raw > vmax ? 1 : raw < -vmax ? -1 : 0;
      }
    }
    const double v = z[kV];
    md.band = m_.P("F_s") != 0.0 && std::abs(v) < m_.P("w") ? 1 : 0;
    return md;
  }

  // dz/dt at (t, z) on the branches `md`; the plant's signals in *s. A
  // piecewise-constant input takes its value at `u_time` (the start of the
  // step: a step never straddles a switch, and its last stages, at the
  // switch, still see the level before it); a smooth one at t.
  void Rhs(double t, const std::vector<double>& z, const Mode& md, std::vector<double>* dz,
           Signals* s, double u_time) const {
    const Model& m = m_;
    const double x = z[kX], v = z[kV];
    const double rg = m.P("r_g");
    const bool follows = m.rigid || m.amplifier == "force_source";  // no motor state
    const double theta = follows ? (rg > 0 ? x / rg : 0.0) : z[kTheta];
    const double omega = follows ? (rg > 0 ? v / rg : 0.0) : z[kOmega];
    const double u = in_.At(in_.piecewise ? u_time : t);
    // Load force F_eff (§7) and static friction (eq. 6), motor torque T_eff.
    double f_load = 0.0;
    if (md.band && v != 0.0) f_load += v > 0 ? m.P("F_s") : -m.P("F_s");
    const double sgn = std::tanh(v / m.P("v_eps"));
    if (m.coulomb) f_load += m.P("F_c") * sgn;
    if (m.stribeck) {
      const double r = v / m.P("v_st");
      f_load += (m.P("F_st") - m.P("F_c")) * std::exp(-r * r) * sgn;
    }
    if (m.viscous_asymmetry) f_load += m.P("Delta_B") * v * (1.0 - sgn) / 2.0;
    if (m.load_offset) f_load += m.P("F_0");
    if (m.spring) f_load += m.P("k_x") * (x - m.P("x_0"));
    double t_motor = 0.0;
    if (m.motor_coulomb) t_motor += m.P("T_c") * std::tanh(omega / m.P("omega_eps"));
    if (m.cogging) t_motor += m.P("A_cog") * std::sin(m.n_cog * theta + m.P("phi_cog"));
    // Amplifier (eq. 2, 3; §4).
    std::fill(dz->begin(), dz->end(), 0.0);
    double i = 0.0, vc = 0.0, vm = 0.0;
    if (m.amplifier != "force_source") {
      const double pre = z[kY4] + m.P("T_z") * z[kY5];
      vc = md.preamp == 0 ? pre : md.preamp * m.P("V_L");
      (*dz)[kY4] = z[kY5];
      (*dz)[kY5] = (m.P("K1") * u - m.P("K2") * m.P("K_t") * omega - z[kY4] -
                    (m.P("T_p") + m.P("T_r")) * z[kY5]) /
                   (m.P("T_p") * m.P("T_r"));
      if (m.amplifier == "analog_velocity_loop") {
        i = z[kI];
        vm = md.vm == 0 ? m.P("K_a") * (vc - i / m.P("K_i")) : md.vm * m.P("V_M");
        (*dz)[kI] = (vm - m.P("R") * i - m.P("K_e") * omega) / m.P("L");
      } else {
        i = m.P("K_i") * vc;
        vm = m.P("R") * i + m.P("K_e") * omega;
      }
    }
    // Mechanics (eq. 1, 4, 5; the rigid reduction and the force source of §4).
    double a = 0.0, fg = 0.0, force = 0.0;
    if (m.amplifier == "force_source") {
      force = m.P("g_F") * u;
      a = (force - m.P("B_a") * v - f_load - (rg > 0 ? t_motor / rg : 0.0)) / mass_;
      fg = force;
    } else if (m.rigid) {
      const double j = m.P("J_m") + rg * rg * mass_;
      const double b = m.P("B_m") + rg * rg * m.P("B_a");
      const double domega = (m.P("K_tau") * i - b * omega - rg * f_load - t_motor) / j;
      a = rg * domega;
      force = m.P("K_tau") * i / rg;
      fg = a * mass_ + m.P("B_a") * v + f_load;
      (*dz)[kTheta] = omega;
      (*dz)[kOmega] = domega;
    } else {
      const double gap = rg * theta - x;
      const double h = m.P("H");
      if (md.contact != 0) {
        fg = (gap - md.contact * h) * m.P("k_g") + (rg * omega - v) * m.P("b_g");
      }
      a = (fg - m.P("B_a") * v - f_load) / mass_;
      force = fg;
      (*dz)[kTheta] = omega;
      (*dz)[kOmega] = (m.P("K_tau") * i - m.P("B_m") * omega - rg * fg - t_motor) / m.P("J_m");
    }
    (*dz)[kX] = v;
    (*dz)[kV] = a;
    Signals sig{a, i, vc, vm, fg, force, u};
    if (s != nullptr) *s = sig;
    // Front-end states: low-pass filters in series, then the period-mean integral.
    for (const std::string& c : channels_) {
      const FrontEnd& f = fe_.at(c);
      if (f.state < 0) continue;
      double r = Raw(c, z, sig);
      int k = f.state;
      if (f.tau1 > 0) {
        (*dz)[k] = (r - z[k]) / f.tau1;
        r = z[k];
        ++k;
      }
      if (f.tau2 > 0) {
        const double w = 1.0 / f.tau2;
        (*dz)[k] = z[k + 1];
        (*dz)[k + 1] = w * w * (r - z[k]) - 2.0 * f.zeta2 * w * z[k + 1];
        r = z[k];
        k += 2;
      }
      if (f.period_mean) (*dz)[k] = r;
    }
  }

  // The plant's signal of channel c (before the front end).
  double Raw(const std::string& c, const std::vector<double>& z, const Signals& s) const {
    const double rg = m_.P("r_g");
    const double omega = m_.rigid || m_.amplifier == "force_source" ? z[kV] / rg : z[kOmega];
    if (c == "u") return s.u;
    if (c == "x") return z[kX];
    if (c == "v") return z[kV];
    if (c == "a") return s.a;
    if (c == "theta") return m_.rigid || m_.amplifier == "force_source" ? z[kX] / rg : z[kTheta];
    if (c == "omega") return omega;
    if (c == "tach") return m_.P("K_t") * omega;
    if (c == "i") return s.i;
    if (c == "vc") return s.vc;
    if (c == "vm") return s.vm;
    if (c == "fg") return s.fg;
    if (c == "force") return s.force;
    Fail("channels: expected a channel of MODEL.md section 6, got " + c);
  }

  // The front end's signal of channel c at state z (after its filters,
  // before the period mean, the delay and the bias).
  double Filtered(const std::string& c, double t, const std::vector<double>& z) const {
    const FrontEnd& f = fe_.at(c);
    const int filters = (f.tau1 > 0) + 2 * (f.tau2 > 0);
    if (filters > 0) return z[f.state + (f.tau2 > 0 ? filters - 2 : 0)];
    std::vector<double> dz(n_);
    Signals s;
    Rhs(t, z, ModeOf(z), &dz, &s, t);
    return Raw(c, z, s);
  }
  // The integral of Filtered from 0 to t (the period-mean channel's state).
  double Integral(const std::string& c, const std::vector<double>& z) const {
    const FrontEnd& f = fe_.at(c);
    return z[f.state + (f.tau1 > 0) + 2 * (f.tau2 > 0)];
  }

  const Input& input() const { return in_; }
  const std::map<std::string, FrontEnd>& front_end() const { return fe_; }
  const std::vector<std::string>& channels() const { return channels_; }

 private:
  const Model& m_;
  const Input& in_;
  std::vector<std::string> channels_;
  std::map<std::string, FrontEnd> fe_;
  int n_ = kPlant;
  double mass_ = 1.0;
};

// ------------------------------------------------------------------ integrator

// One accepted point of the solution: time, state, derivative (on the
// branch the step ending here used, and the one starting here).
struct Knot {
  double t;
  std::vector<double> z, dz;
};

class Integrator {
 public:
  explicit Integrator(const Axis& axis) : axis_(axis), n_(axis.size()) {}

  // Integrates from z0 at 0 to t_end, stopping at every time in `stops`
  // (input switches), and returns the knots (a knot on each side of a
  // branch change or an input switch, at the same time).
  std::vector<Knot> Run(std::vector<double> z, double t_end, std::vector<double> stops) {
    std::sort(stops.begin(), stops.end());
    std::vector<Knot> knots;
    double t = 0.0;
    double h = 1e-6;
    size_t next_stop = 0;
    while (next_stop < stops.size() && stops[next_stop] <= 0.0) ++next_stop;
    Mode md = axis_.ModeOf(z);
    Push(t, z, md, &knots, t);
    while (t < t_end) {
      const double limit = next_stop < stops.size() ? std::min(stops[next_stop], t_end) : t_end;
      h = std::min(h, limit - t);
      std::vector<double> z1, err;
      Step(t, z, md, h, &z1, &err);
      const double e = ErrorNorm(z, z1, err);
      if (!(e <= 1.0)) {
        h *= std::max(0.1, 0.9 * std::pow(e, -0.2));
        if (h < 1e-14) {
          std::ostringstream why;
          why << "integration: the step fell below 1e-14 s at t = " << t << " (error norm " << e << ")";
          Fail(why.str());
        }
        continue;
      }
      const Mode md1 = axis_.ModeOf(z1);
      if (!(md1 == md)) {
        // A branch changes inside the step: bisect the step length for the
        // first point where the state leaves the branch `md`.
        double lo = 0.0, hi = h;
        std::vector<double> zl = z;
        while (hi - lo > 1e-13) {
          const double mid = 0.5 * (lo + hi);
          std::vector<double> zm, em;
          Step(t, z, md, mid, &zm, &em);
          if (axis_.ModeOf(zm) == md) {
            lo = mid;
            zl = zm;
          } else {
            hi = mid;
          }
        }
        std::vector<double> zh, eh;
        Step(t, z, md, hi, &zh, &eh);
        const double t0 = t;
        t += hi;
        z = zh;
        Push(t, z, md, &knots, t0);  // the end of the old branch
        md = axis_.ModeOf(z);
        Push(t, z, md, &knots, t0);  // the start of the new one
        h = std::max(hi, 1e-9);
        continue;
      }
      const bool at_limit = h == limit - t;
      const double t0 = t;
      t = at_limit ? limit : t + h;
      z = z1;
      Push(t, z, md, &knots, t0);
      if (at_limit && next_stop < stops.size() && stops[next_stop] <= t) {
        // The input switches here: the derivative after it starts the next
        // segment.
        while (next_stop < stops.size() && stops[next_stop] <= t) ++next_stop;
        md = axis_.ModeOf(z);
        Push(t, z, md, &knots, t);
      }
      h *= std::min(5.0, 0.9 * std::pow(std::max(e, 1e-10), -0.2));
      h = std::min(h, kMaxStep);
    }
    return knots;
  }

 private:
  static constexpr double kMaxStep = 2e-4;

  // A knot at t whose derivative takes a piecewise input at `u_time`.
  void Push(double t, const std::vector<double>& z, const Mode& md, std::vector<Knot>* knots,
            double u_time) {
    Knot k{t, z, std::vector<double>(n_)};
    axis_.Rhs(t, z, md, &k.dz, nullptr, u_time);
    knots->push_back(std::move(k));
  }

  // Dormand–Prince 5(4): the fifth-order solution and the error estimate.
  void Step(double t, const std::vector<double>& z, const Mode& md, double h,
            std::vector<double>* z5, std::vector<double>* err) const {
    static const double c[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
    static const double a[7][6] = {
        {0, 0, 0, 0, 0, 0},
        {1.0 / 5, 0, 0, 0, 0, 0},
        {3.0 / 40, 9.0 / 40, 0, 0, 0, 0},
        {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0},
        {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0},
        {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0},
        {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
    static const double b5[7] = {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784,
                                 11.0 / 84, 0};
    static const double b4[7] = {5179.0 / 57600, 0, 7571.0 / 16695, 393.0 / 640,
                                 -92097.0 / 339200, 187.0 / 2100, 1.0 / 40};
    std::vector<std::vector<double>> k(7, std::vector<double>(n_));
    std::vector<double> y(n_);
    for (int s = 0; s < 7; ++s) {
      for (int i = 0; i < n_; ++i) {
        double acc = z[i];
        for (int j = 0; j < s; ++j) acc += h * a[s][j] * k[j][i];
        y[i] = acc;
      }
      axis_.Rhs(t + c[s] * h, y, md, &k[s], nullptr, t);
    }
    z5->assign(n_, 0.0);
    err->assign(n_, 0.0);
    for (int i = 0; i < n_; ++i) {
      double s5 = 0, s4 = 0;
      for (int s = 0; s < 7; ++s) {
        s5 += b5[s] * k[s][i];
        s4 += b4[s] * k[s][i];
      }
      (*z5)[i] = z[i] + h * s5;
      (*err)[i] = h * (s5 - s4);
    }

  }

  double ErrorNorm(const std::vector<double>& z0, const std::vector<double>& z1,
                   const std::vector<double>& err) const {
    double e = 0.0;
    for (int i = 0; i < n_; ++i) {
      const double scale = kAbs + kRel * std::max(std::abs(z0[i]), std::abs(z1[i]));
      e = std::max(e, std::abs(err[i]) / scale);
    }
    return e;
  }

  static constexpr double kAbs = 1e-11;
  static constexpr double kRel = 1e-9;
  const Axis& axis_;
  const int n_;
};

// The state at time t from the knots (cubic Hermite on the segment holding
// t; a knot pair at one time is a branch change: the later one starts the
// segment after it). Before the first knot the first state, after the last
// the last.
std::vector<double> StateAt(const std::vector<Knot>& knots, double t, size_t* cursor) {
  if (t <= knots.front().t) return knots.front().z;
  if (t >= knots.back().t) return knots.back().z;
  size_t k = std::min(*cursor, knots.size() - 2);
  while (k > 0 && knots[k].t > t) --k;
  while (k + 1 < knots.size() && knots[k + 1].t <= t) ++k;
  while (k + 1 < knots.size() && knots[k + 1].t == knots[k].t) ++k;
  *cursor = k;
  const Knot& a = knots[k];
  const Knot& b = knots[k + 1];
  const double h = b.t - a.t;
  const double s = (t - a.t) / h;
  const double h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s);
  const double h01 = s * s * (3 - 2 * s), h11 = s * s * (s - 1);
  std::vector<double> z(a.z.size());
  for (size_t i = 0; i < z.size(); ++i) {
    z[i] = h00 * a.z[i] + h10 * h * a.dz[i] + h01 * b.z[i] + h11 * h * b.dz[i];
  }
  return z;
}

// ------------------------------------------------------------------ spec

struct Spec {
  Model model;
  double duration = 4.0, rate = 1000.0;
  std::vector<std::string> channels;
  std::map<std::string, FrontEnd> front_end;
  unsigned long seed = 1;
  std::vector<std::pair<std::string, YAML::Node>> records;
};

std::string DirOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

Spec ReadSpec(const std::string& path) {
  const YAML::Node root = YAML::LoadFile(path);
  Spec s;
  const std::string model = root["model"].as<std::string>();
  s.model = ReadModel(model[0] == '/' ? model : DirOf(path) + "/" + model);
  if (root["set"]) {
    for (const auto& q : root["set"]) s.model.p[q.first.as<std::string>()] = q.second.as<double>();
  }
  if (root["effects"]) ReadEffects(root["effects"], &s.model);
  s.duration = root["duration"].as<double>();
  s.rate = root["output_rate"] ? root["output_rate"].as<double>() : 1000.0;
  for (const auto& c : root["channels"]) s.channels.push_back(c.as<std::string>());
  for (const std::string& c : s.channels) s.front_end[c] = FrontEnd{};
  // MODEL.md §6: the accelerometer's samples are period means unless the
  // spec says `sampling: instant`.
  if (s.front_end.count("a")) s.front_end["a"].period_mean = true;
  if (root["front_end"]) {
    for (const auto& e : root["front_end"]) {
      FrontEnd& f = s.front_end[e.first.as<std::string>()];
      const YAML::Node n = e.second;
      if (n["sampling"]) f.period_mean = n["sampling"].as<std::string>() == "period_mean";
      if (n["delay"]) f.delay = n["delay"].as<double>();
      if (n["lowpass"]) f.tau1 = n["lowpass"].as<double>();
      if (n["lowpass2"]) {
        f.tau2 = n["lowpass2"]["tau"].as<double>();
        if (n["lowpass2"]["zeta"]) f.zeta2 = n["lowpass2"]["zeta"].as<double>();
      }
      if (n["bias"]) f.bias = n["bias"].as<double>();
    }
  }
  if (root["noise"]) {
    for (const auto& q : root["noise"]) s.front_end[q.first.as<std::string>()].sigma = q.second.as<double>();
  }
  if (root["seed"]) s.seed = root["seed"].as<unsigned long>();
  for (const auto& r : root["records"]) s.records.push_back({r["name"].as<std::string>(), r["input"]});
  return s;
}

// One record: simulate, sample through the front end, add noise, write.
void WriteRecord(const Spec& spec, const YAML::Node& input_node, unsigned long seed, bool noise,
                 const std::string& out) {
  const double period = 1.0 / spec.rate;
  const Input input = ReadInput(input_node, spec.duration, period);
  const Axis axis(spec.model, input, spec.channels, spec.front_end);
  double advance = 0.0;
  for (const auto& [c, f] : spec.front_end) advance = std::max(advance, -f.delay);
  const long samples = static_cast<long>(std::floor(spec.duration * spec.rate + 1e-9)) + 1;
  std::vector<double> z0(axis.size(), 0.0);
  Integrator integrator(axis);
  const std::vector<Knot> knots =
      integrator.Run(z0, spec.duration + advance + 2 * period, input.switch_times);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::ofstream f(out);
  f.precision(17);
  f << "t";
  for (const std::string& c : spec.channels) f << "," << c;
  f << "\n";
  std::map<std::string, size_t> cursors;
  for (long k = 0; k < samples; ++k) {
    const double t = k * period;
    f << t;
    for (const std::string& c : spec.channels) {
      const FrontEnd& fe = spec.front_end.at(c);
      double value;
      if (c == "u") {
        value = input.At(t);  // the command as applied (a DAC's)
      } else {
        const double ts = t - fe.delay;
        if (!fe.period_mean) {
          value = axis.Filtered(c, ts, StateAt(knots, ts, &cursors[c]));
        } else {
          // The mean over the period ending at the sample: the difference of
          // the integral; before t = 0 the signal is held at its value at 0
          // (MODEL.md section 6: the motion continued back).
          const double at0 = axis.Filtered(c, 0.0, knots.front().z);
          const auto integral = [&](double tq) {
            if (tq <= 0.0) return at0 * tq;
            size_t cur = 0;
            return axis.Integral(c, StateAt(knots, tq, &cur));
          };
          value = (integral(ts) - integral(ts - period)) / period;
        }
      }
      value += fe.bias;
      if (noise && c != "u") value += fe.sigma * gauss(rng);
      f << "," << value;
    }
    f << "\n";
  }
  if (!f) Fail(out + ": cannot write");
}

}  // namespace

int main(int argc, char** argv) {
  std::string spec_path, out;
  long seed_offset = 0;
  bool noise = true;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--out" && k + 1 < argc) {
      out = argv[++k];
    } else if (a == "--seed" && k + 1 < argc) {
      seed_offset = std::atol(argv[++k]);
    } else if (a == "--noise-free") {
      noise = false;
    } else if (spec_path.empty()) {
      spec_path = a;
    } else {
      std::cerr << "independent-records: unexpected argument '" << a << "'\n";
      return 2;
    }
  }
  if (spec_path.empty() || out.empty()) {
    std::cerr << "usage: independent-records SPEC.yaml --out DIR [--seed N] [--noise-free]\n";
    return 2;
  }
  try {
    const Spec spec = ReadSpec(spec_path);
    for (size_t r = 0; r < spec.records.size(); ++r) {
      const unsigned long seed = spec.seed + static_cast<unsigned long>(r) +
                                 1000UL * static_cast<unsigned long>(seed_offset);
      WriteRecord(spec, spec.records[r].second, seed, noise,
                  out + "/" + spec.records[r].first + ".csv");
    }
  } catch (const std::exception& e) {
    std::cerr << "independent-records: " << spec_path << ": " << e.what() << "\n";
    return 2;
  }
  return 0;
}
