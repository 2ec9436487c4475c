// Fixed-step RK4 across the switching surfaces of a piecewise-smooth system
// (the backlash contacts of MODEL.md eq. 5, the preamp limit of eq. 2),
// with each event located inside the step and the sensitivities carried
// across it by the saltation rule of Hiskens & Pai, "Trajectory sensitivity
// analysis of hybrid systems", IEEE Trans. Circuits Syst. I 47(2), 2000,
// eq. (13)–(15), or by its discrete counterpart, the step's own event-time
// sensitivity.
//
// Why: eq. 5 switches f_g between 0 and k_g·(X ∓ H) + b_g·(r_g·ω − v) when
// the pinion–rack difference X crosses ±H, so the right-hand side jumps by
// b_g·(r_g·ω − v). A plain RK4 step that straddles the contact mixes the two
// branches stage by stage, and its ceres::Jet derivative is pathwise: it
// misses the term from the contact time moving with the parameters, and the
// Jacobian is not the derivative of the cost. Worse, which stages fall on
// which side is decided by the stage times, so the simulated trace jumps
// when a parameter moves an event across one: the cost has steps, and a
// solver or a profile refit stops at their edges (issue 10, coverage_prbs:
// the preamp output crossing ±V_L within one step). Here each mode's smooth
// field is integrated up to the first located event, the mode is switched
// there, and the sensitivities S = ∂y/∂p jump by the flow's saltation
//     S⁺ = S⁻ + (f⁺ − f⁻)·(g_y·S⁻ + g_p)/(g_y·f⁻)
// (g the guard, the switching function; f⁻, f⁺ the fields before and
// after), or, where the system asks for it (StepOwnEventSensitivity), by
// the step's own rule: the event's time s solves g(Φ_s(y)) = 0 for the
// step's RK4 sub-step Φ_s, so ∂s/∂p = −(g_y·S + g_p)/(g_y·∂Φ_s/∂s); the
// state at the event gains ∂Φ_s/∂s·∂s/∂p and the rest of the step, of
// length h − s, is integrated with that length's derivative
// (Rk4StepOfLength, sim/rk4.h). The step's own rule is the derivative of
// the RK4 trace, which matters where f is continuous across the guard (the
// saltation is zero) but the step's result depends on where a corner of f
// falls in it through a stiff mode (the full current loop's preamp limit).
// Where f⁺ = f⁻ it also gives a parameter that only moves the event a tiny,
// non-physical column, which a trust-region step then follows far along a
// flat direction; where f jumps the two rules agree to the order of the
// step. So each is used where it is the better one. The simulated values
// also become more accurate (the event is no longer smeared over one
// step); with no event in a step this is Rk4Step.
#ifndef SIM_SWITCHED_RK4_H_
#define SIM_SWITCHED_RK4_H_

#include <cmath>

#include <Eigen/Core>

#include "sim/rk4.h"
#include "sim/scalar.h"

namespace axis {

// Most events handled inside one step; beyond that the step is finished in
// the mode reached (a chattering contact would otherwise cost without bound).
inline constexpr int kMaxEventsPerStep = 4;

// The scalar of a sub-step differentiated in its own length s alone (value,
// ∂/∂s): how the state at an event moves with the event's time. A type of
// its own in the system's interface (EventDerivative below), never mixed
// with the parameters' Jets even where those have one component too.
using EventTimeJet = ceres::Jet<double, 1>;
template <int N>
using EventTimeState = Eigen::Matrix<EventTimeJet, N, 1>;

namespace internal {

// The step's own event-time rule (Rk4SwitchedStep): *y is the state at the
// event, reached by the sub-step of length s_event from `start` (values) at
// t0 in `mode`; g the guard there (T, its Jet part G_p). Adds
// ∂Φ_s/∂s·∂s/∂p to *y and ∂s/∂p = −G_p/G_s to *s_t, ∂Φ_s/∂s computed
// exactly: the sub-step's formula run with a step length that carries its
// own derivative (forward mode in s alone).
template <typename T, int N, typename System>
void StepOwnEventJump(const System& system, double t0, double s_event,
                      int mode, int next,
                      const Eigen::Matrix<double, N, 1>& start, const T& g,
                      Eigen::Matrix<T, N, 1>* y, T* s_t) {
  EventTimeState<N> at_event;
  for (int i = 0; i < N; ++i) at_event[i] = EventTimeJet(start[i]);
  const auto event_field = [&system, mode](double tt,
                                           const EventTimeState<N>& s,
                                           EventTimeState<N>* ds) {
    system.EventDerivative(tt, s, mode, ds);
  };
  Rk4StepOfLength(event_field, t0, EventTimeJet(s_event, 0), &at_event);
  Eigen::Matrix<double, N, 1> dphi;
  for (int i = 0; i < N; ++i) dphi[i] = at_event[i].v[0];
  const double g_s = system.GuardRate(dphi, mode, next);
  if (g_s == 0.0 || !std::isfinite(g_s)) return;
  AddScaledDerivative(-1.0 / g_s, g, s_t);
  for (int i = 0; i < N; ++i) {
    if (dphi[i] != 0.0) AddScaledDerivative(-dphi[i] / g_s, g, &(*y)[i]);
  }
}

// The flow's saltation at an event at time te from `mode` to `next`, *y the
// state there and g the guard: S += (f⁺ − f⁻)·(dg/dp)/(dg/dt).
template <typename T, int N, typename System>
void SaltationJump(const System& system, double te, int mode, int next,
                   const T& g, Eigen::Matrix<T, N, 1>* y) {
  Eigen::Matrix<T, N, 1> before, after;
  system.Derivative(te, *y, mode, &before);
  system.Derivative(te, *y, next, &after);
  Eigen::Matrix<double, N, 1> rate_along;
  for (int i = 0; i < N; ++i) rate_along[i] = ScalarValue(before[i]);
  const double rate = system.GuardRate(rate_along, mode, next);
  if (rate == 0.0 || !std::isfinite(rate)) return;
  for (int i = 0; i < N; ++i) {
    const double jump = ScalarValue(after[i]) - ScalarValue(before[i]);
    if (jump != 0.0) AddScaledDerivative(jump / rate, g, &(*y)[i]);
  }
}

}  // namespace internal

// Advances *y (N states of scalar T: double or ceres::Jet) from t to t + h
// in `mode` and returns the mode at t + h. A mode is one region of each of
// System::kFamilies independent switching families (e.g. gear contact ×
// preamp region), the regions of a family ordered so that only neighbours
// share a boundary. `system` must provide, for S = T and S = double:
//   void Derivative(double t, const Eigen::Matrix<S, N, 1>& y, int mode,
//                   Eigen::Matrix<S, N, 1>* dy) const;  // smooth in y
//   S Guard(const Eigen::Matrix<S, N, 1>& y, int from, int to) const;
// and
//   void EventDerivative(double t, const EventTimeState<N>& y, int mode,
//                        EventTimeState<N>* dy) const;  // Derivative at the
//       // parameters' values, its Jet part ∂/∂s carried through y
//   double GuardRate(const Eigen::Matrix<double, N, 1>& dy, int from,
//                    int to) const;  // g_y·dy: the guard's rate along dy
//   bool StepOwnEventSensitivity(int from, int to) const;  // the rule at
//       // an event from `from` to `to`: true for the step's own, false for
//       // the flow's saltation
//   static constexpr int kFamilies;  // ≥ 1
//   int Mode(const Eigen::Matrix<double, N, 1>& y) const;
//   int Toward(int from, int to, int family) const;  // `from` with the
//       // region of `family` moved one region toward that of `to`; `from`
//       // itself where the two agree in that family
// Guard(y, from, to) (`to` = Toward(from, ·, ·) ≠ from) is negative in
// region `from`, positive in `to`, zero on their boundary, and may depend on
// the parameters (its Jet part then carries ∂g/∂p). Where the step ends in
// another mode, the event of every family that changed is located on the
// double trajectory to 1e-12·h by the Illinois variant of regula falsi, and
// the earliest is taken. A family whose guard crosses and recrosses inside
// one step (a grazing contact) is not seen.
// Never throws unless the system does.
template <typename T, int N, typename System>
int Rk4SwitchedStep(const System& system, double t, double h, int mode,
                    Eigen::Matrix<T, N, 1>* y) {
  using State = Eigen::Matrix<T, N, 1>;
  using Values = Eigen::Matrix<double, N, 1>;
  const auto values_of = [](const State& s) {
    Values v;
    for (int i = 0; i < N; ++i) v[i] = ScalarValue(s[i]);
    return v;
  };
  double t0 = t;
  double remaining = h;
  // The rest of the step as a T: after an event its derivative part is
  // minus that of the event's time (below), zero before the first.
  T remaining_t = T(h);
  bool moved = false;  // an event has given remaining_t a derivative
  for (int events = 0;; ++events) {
    const auto field = [&system, &mode](double tt, const State& s, State* ds) {
      system.Derivative(tt, s, mode, ds);
    };
    State trial = *y;
    if (moved) {
      Rk4StepOfLength(field, t0, remaining_t, &trial);
    } else {
      Rk4Step(field, t0, remaining, &trial);
    }
    const int end_mode = system.Mode(values_of(trial));
    if (end_mode == mode || events == kMaxEventsPerStep) {
      *y = trial;
      return end_mode;
    }

    // Locate each changed family's event on the double trajectory:
    // G(s) = g(Φ_s(y)) changes sign on [0, remaining]; the earliest wins.
    const Values start = values_of(*y);
    const Values end = values_of(trial);
    const auto value_field = [&system, &mode](double tt, const Values& s,
                                              Values* ds) {
      system.Derivative(tt, s, mode, ds);
    };
    int next = mode;
    double s_event = remaining;
    for (int family = 0; family < System::kFamilies; ++family) {
      const int to = system.Toward(mode, end_mode, family);
      if (to == mode) continue;
      const auto guard_after = [&](double s) {
        Values v = start;
        if (s > 0.0) Rk4Step(value_field, t0, s, &v);
        return system.Guard(v, mode, to);
      };
      double a = 0.0, b = remaining;
      double ga = system.Guard(start, mode, to);
      double gb = system.Guard(end, mode, to);
      double s_to = 0.0;
      if (ga < 0.0 && gb > 0.0) {
        int side = 0;
        for (int it = 0; it < 100 && b - a > 1e-12 * h; ++it) {
          const double s = (a * gb - b * ga) / (gb - ga);
          const double gs = guard_after(s);
          if (gs == 0.0) {
            a = b = s;
            break;
          }
          if (gs > 0.0) {
            b = s;
            gb = gs;
            if (side == 1) ga *= 0.5;
            side = 1;
          } else {
            a = s;
            ga = gs;
            if (side == -1) gb *= 0.5;
            side = -1;
          }
        }
        s_to = b;  // on the `to` side (or on the boundary)
      } else if (!(ga >= 0.0)) {
        // The end is outside `mode` in this family for another reason than
        // this guard (not possible with ordered regions): no event here.
        continue;
      }
      // ga ≥ 0: already on the boundary (e.g. an event ended the last step
      // and the motion turns back at once): switch at s = 0.
      if (next == mode || s_to < s_event) {
        next = to;
        s_event = s_to;
      }
    }
    if (next == mode) {
      *y = trial;
      return end_mode;
    }

    if (s_event > 0.0) Rk4Step(field, t0, s_event, y);
    // Two rules carry the sensitivities across the event (see the file's
    // head). The step's own: the event's time s(p) solves G(s, p) =
    // g(Φ_s(y(p)), p) = 0 for this RK4 sub-step Φ_s, so ∂s/∂p = −G_p/G_s,
    // G_p being the Jet part of the guard at the event (through the state's
    // sensitivities and any parameter in the guard itself) and G_s =
    // g_y·∂Φ_s/∂s; the state at the event gains ∂Φ_s/∂s·∂s/∂p and the rest
    // of the step, h − s, carries −∂s/∂p. It is the derivative of the
    // simulated trace, and differs from the flow's saltation where the field
    // is continuous but a stiff mode makes ∂Φ_s/∂s differ from f (the full
    // current loop at 10 µs, h·λ ≈ −1.4). Stage times are not
    // differentiated: a smooth input's rate at the event is left out.
    const T g = system.Guard(*y, mode, next);
    T s_t = T(s_event);
    if (system.StepOwnEventSensitivity(mode, next)) {
      internal::StepOwnEventJump(system, t0, s_event, mode, next,
                                 start, g, y, &s_t);
      moved = true;
    } else {
      internal::SaltationJump(system, t0 + s_event, mode, next, g, y);
    }
    mode = next;
    t0 += s_event;
    remaining -= s_event;
    remaining_t = remaining_t - s_t;
    if (!(remaining > 1e-12 * h)) return mode;
  }
}

}  // namespace axis

#endif  // SIM_SWITCHED_RK4_H_
