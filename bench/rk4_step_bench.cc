// Nanoseconds per RK4 step of the X axis (MODEL.md §3, analog velocity loop
// with gear coupling, 10 V step input, h = 10 µs), in double and in
// ceres::Jet<double, 5>, next to a plain hand-written loop of the same
// equations as the reference cost of the arithmetic itself.
#include <benchmark/benchmark.h>

#include <algorithm>

#include <ceres/jet.h>

#include "sim/axis_model.h"
#include "sim/rk4.h"

namespace {

constexpr double kStep = 1e-5;
constexpr double kInput = 10.0;
constexpr long kRestartEvery = 150000;  // 1.5 s: transient and steady state

template <typename T>
void BM_Rk4Step(benchmark::State& state) {
  const axis::AxisStructure structure;
  axis::AxisParams<T> params = axis::AxisParams<double>().cast<T>();
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
struct Plain {
  double y[7] = {0, 0, 0, 0, 0, 0, 0};
};

inline void PlainDerivative(const double* y, double u, double* dy) {
  const double R = 0.56, L = 0.00235, K_e = 0.289, K_tau = 0.289,
               J_m = 0.000847, B_m = 0.000733, K_t = 0.0668, r_g = 0.00573,
               H = 0.00001, M = 146, T_z = 0.00705, T_p = 0.04, T_r = 0.000159,
               K1 = 1014, K2 = 870, K_i = 3, V_M = 95, V_L = 2.7, B_a = 200,
               b_g = 1500, k_g = 5e6, K_a = 1000;
  const double vc = std::clamp(y[4] + T_z * y[5], -V_L, V_L);
  const double vm = std::clamp(K_a * (vc - y[6] / K_i), -V_M, V_M);
  const double X = r_g * y[2] - y[0];
  double fg = 0.0;
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

void BM_HandWrittenStep(benchmark::State& state) {
  Plain s;
  long n = 0;
  double k1[7], k2[7], k3[7], k4[7], tmp[7];
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
      s = Plain();
    }
  }
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK(BM_HandWrittenStep);
BENCHMARK_TEMPLATE(BM_Rk4Step, double);
BENCHMARK_TEMPLATE(BM_Rk4Step, ceres::Jet<double, 5>);

}  // namespace

BENCHMARK_MAIN();
