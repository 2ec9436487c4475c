// Nanoseconds per RK4 step of the X axis (MODEL.md §3, analog velocity loop
// with gear coupling, 10 V step input, h = 10 µs), in double and in
// ceres::Jet<double, 5>, next to a plain hand-written loop of the same
// equations as the reference cost of the arithmetic itself.
#include <algorithm>
#include <string>
#include <type_traits>

#include <benchmark/benchmark.h>
#include <ceres/jet.h>

#include "sim/axis_model.h"
#include "sim/config.h"
#include "sim/rk4.h"
#include "sim/simulate.h"

namespace {

constexpr double kStep = 1e-5;
constexpr double kInput = 10.0;
constexpr long kRestartEvery = 150000;  // 1.5 s: transient and steady state

template <typename T>
void BM_Rk4Step(benchmark::State& state) {
  const axis::AxisStructure structure;
  axis::AxisParams<T> params = axis::AxisParams<double>().cast<T>();
  // As in the paper job: the five unknowns carry derivative parts.
  if constexpr (!std::is_same<T, double>::value) {
    T* unknowns[] = {&params.V_L, &params.B_a, &params.b_g, &params.k_g,
                     &params.T_p};
    for (int k = 0; k < 5; ++k) unknowns[k]->v[k % T::DIMENSION] = 1.0;
  }
  const axis::AxisCoefficients<T> coeffs =
      axis::MakeAxisCoefficients(structure, params);
  const T input(kInput);
  const auto rhs = [&](double, const axis::AxisState<T>& y,
                       axis::AxisState<T>* dy) {
    axis::AxisDerivative(structure, params, coeffs, y, input, dy);
  };
  axis::AxisState<T> y = axis::AxisState<T>::Zero();
  long n = 0;
  for (auto _ : state) {
    axis::Rk4Step(rhs, n * kStep, kStep, &y);
    benchmark::DoNotOptimize(y);
    if (++n == kRestartEvery) {
      n = 0;
      y.setZero();
    }
  }
  state.SetItemsProcessed(state.iterations());
}

// The same equations written out on plain doubles, no Eigen, no switches.
template <typename T>
struct Plain {
  T y[7] = {T(0), T(0), T(0), T(0), T(0), T(0), T(0)};
};

template <typename T>
inline void PlainDerivative(const T* y, double u, T* dy) {
  const double R = 0.56, L = 0.00235, K_e = 0.289, K_tau = 0.289,
               J_m = 0.000847, B_m = 0.000733, K_t = 0.0668, r_g = 0.00573,
               H = 0.00001, M = 146, T_z = 0.00705, T_p = 0.04, T_r = 0.000159,
               K1 = 1014, K2 = 870, K_i = 3, V_M = 95, V_L = 2.7, B_a = 200,
               b_g = 1500, k_g = 5e6, K_a = 1000;
  using std::clamp;
  const T vc = clamp<T>(y[4] + T_z * y[5], T(-V_L), T(V_L));
  const T vm = clamp<T>(K_a * (vc - y[6] / K_i), T(-V_M), T(V_M));
  const T X = r_g * y[2] - y[0];
  T fg(0.0);
  if (X > H) fg = (X - H) * k_g + (r_g * y[3] - y[1]) * b_g;
  if (X < -H) fg = (X + H) * k_g + (r_g * y[3] - y[1]) * b_g;
  dy[0] = y[1];
  dy[1] = (fg - B_a * y[1]) / M;
  dy[2] = y[3];
  dy[3] = (K_tau * y[6] - B_m * y[3] - r_g * fg) / J_m;
  dy[4] = y[5];
  dy[5] = (K1 * u - K2 * K_t * y[3] - y[4] - (T_p + T_r) * y[5]) / (T_p * T_r);
  dy[6] = (vm - R * y[6] - K_e * y[3]) / L;
}

// T = double, or ceres::Jet<double, 5> with every parameter a plain double
// (no derivative parts, unlike BM_Rk4Step's five unknowns): a lower bound on
// the cost of the Jet arithmetic of the equations.
template <typename T>
void BM_HandWrittenStep(benchmark::State& state) {
  Plain<T> s;
  long n = 0;
  T k1[7], k2[7], k3[7], k4[7], tmp[7];
  for (auto _ : state) {
    const double h = kStep;
    PlainDerivative(s.y, kInput, k1);
    for (int i = 0; i < 7; ++i) tmp[i] = s.y[i] + 0.5 * h * k1[i];
    PlainDerivative(tmp, kInput, k2);
    for (int i = 0; i < 7; ++i) tmp[i] = s.y[i] + 0.5 * h * k2[i];
    PlainDerivative(tmp, kInput, k3);
    for (int i = 0; i < 7; ++i) tmp[i] = s.y[i] + h * k3[i];
    PlainDerivative(tmp, kInput, k4);
    for (int i = 0; i < 7; ++i) {
      s.y[i] += h / 6.0 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
    }
    benchmark::DoNotOptimize(s);
    if (++n == kRestartEvery) {
      n = 0;
      s = Plain<T>();
    }
  }
  state.SetItemsProcessed(state.iterations());
}

// One simulation as a fit evaluates it: configs/experiments/x_prbs.yaml (3 s,
// PRBS ±5 V, the backlash crossed at every reversal, so the switched RK4 of
// sim/switched_rk4.h locates events), in double, in Jet<1> (a residual-only
// evaluation's guard) and in Jet<5> (the paper's five unknowns carrying
// derivative parts; a fit's Jacobian carries them in a Jet of whole vector
// registers, estimation/jet_widths.h).
// QuasiSteady: the same record with `current_loop: quasi_steady` at a 50 µs
// step (sim/axis_params.h CurrentLoop), as the discovery jobs fit it; there
// also in Jet<6> and Jet<8>, the widths a fit of six unknowns would use
// with and without whole vector registers (estimation/jet_widths.h).
template <typename T, bool QuasiSteady = false>
void BM_SimulatePrbs(benchmark::State& state) {
  axis::ExperimentConfig e =
      axis::LoadExperiment(std::string(PROJECT_SOURCE_DIR) +
                           "/configs/experiments/x_prbs.yaml");
  if (QuasiSteady) {
    e.model.structure.current_loop = axis::CurrentLoop::kQuasiSteady;
    e.options.step = 5e-5;
  }
  axis::AxisParams<T> params = e.model.params.cast<T>();
  if constexpr (!std::is_same<T, double>::value) {
    T* unknowns[] = {&params.V_L, &params.B_a, &params.b_g, &params.k_g,
                     &params.T_p};
    for (int k = 0; k < 5; ++k) unknowns[k]->v[k % T::DIMENSION] = 1.0;
  }
  const axis::SimulationGrid grid = axis::MakeGrid(e.options, e.drive);
  const axis::AxisState<T> y0 = e.initial_state.cast<T>();
  for (auto _ : state) {
    axis::Trace<T> trace = axis::Simulate(e.model.structure, params, y0,
                                          e.drive, e.options, grid);
    benchmark::DoNotOptimize(trace);
  }
  state.SetItemsProcessed(state.iterations() * grid.num_steps);
}
BENCHMARK_TEMPLATE(BM_SimulatePrbs, double)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SimulatePrbs, ceres::Jet<double, 1>)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SimulatePrbs, ceres::Jet<double, 5>)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SimulatePrbs, double, true)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SimulatePrbs, ceres::Jet<double, 5>, true)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SimulatePrbs, ceres::Jet<double, 6>, true)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_SimulatePrbs, ceres::Jet<double, 8>, true)->Unit(benchmark::kMillisecond);

BENCHMARK_TEMPLATE(BM_HandWrittenStep, double);
BENCHMARK_TEMPLATE(BM_HandWrittenStep, ceres::Jet<double, 5>);
BENCHMARK_TEMPLATE(BM_Rk4Step, double);
BENCHMARK_TEMPLATE(BM_Rk4Step, ceres::Jet<double, 1>);
BENCHMARK_TEMPLATE(BM_Rk4Step, ceres::Jet<double, 5>);

}  // namespace
