// The widths of ceres::Jet (numbers of derivative parts) for which the fit's
// simulations are instantiated: ExperimentCost::Create's derivative strides
// (experiment_cost.cc) and the narrower Jets in which SimulateAt integrates
// the plant alone (experiment_cost.h).
//
// A Jet<double, N> keeps its derivative parts in an Eigen fixed-size vector,
// and Eigen vectorises it with whole registers only where N is a multiple of
// the register's width in doubles (Eigen's packet size: 8 with AVX-512, 4
// with AVX, 2 with SSE2); otherwise the parts go through narrower registers
// or one at a time. On a processor with AVX-512 a whole 3 s PRBS record took
// 14.3 ms in Jet<8> against 20.6 ms in Jet<6> and 21.2 ms in Jet<5> (the
// fastest of twelve interleaved runs each; medians 17.5, 28.0, 41.5 ms;
// bench_rk4_step `SimulatePrbs<Jet<N>, true>`). The widths are whole numbers
// of registers: kJetLane, 2·kJetLane, … up to kMaxJetWidth, and a θ wider
// than kMaxJetWidth is differentiated in chunks of kMaxJetWidth (Ceres's
// DynamicAutoDiffCostFunction). The derivative parts beyond θ's entries are
// zero; values and derivatives do not depend on the width chosen up to the
// last bits (a scalar tail and a vector lane round alike unless the
// processor fuses a multiply-add in one and not the other).
#ifndef ESTIMATION_JET_WIDTHS_H_
#define ESTIMATION_JET_WIDTHS_H_

#include <algorithm>

#include <Eigen/Core>

namespace axis {

// One register of doubles on the processor the build targets, at least 4
// (a Jet<2> or Jet<3> costs about what a Jet<4> does).
inline constexpr int kJetLane =
    std::max(4, static_cast<int>(Eigen::internal::packet_traits<double>::size));

// The widest instantiated Jet: 16 derivative parts.
inline constexpr int kMaxJetWidth = 16;
static_assert(kMaxJetWidth % kJetLane == 0, "the widest Jet is a whole number of registers");

}  // namespace axis

#endif  // ESTIMATION_JET_WIDTHS_H_
