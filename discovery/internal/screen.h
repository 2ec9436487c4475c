// Competing refits under a level (issue 11): the rule that stops a refit
// once it can no longer end below the lowest BIC a competing refit has
// reached, the screen that runs every refit over the first horizons of its
// continuation only (the discovery loop's candidates,
// discovery/internal/discovery_loop.cc), and the level one fit publishes for others
// running beside it (the force map's forms, discovery/internal/force_map_step.cc).
// Both are several refits of which only the lowest BIC matters.
#ifndef DISCOVERY_INTERNAL_SCREEN_H_
#define DISCOVERY_INTERNAL_SCREEN_H_

#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "estimation/fit_result.h"
#include "estimation/horizon_checkpoint.h"
#include "estimation/estimation_problem.h"

namespace axis {

// A refit stops once the lower bound of its BIC on a shorter horizon
// (estimation/fit.h FitParameters) exceeds this many times the level that decides
// (the BIC before the step, or the lowest a competing refit has reached;
// BICs here are positive). Not 1: the bound takes the shorter horizon's
// minimum as the one its stage found, and a stage can end in a local
// minimum above the whole record's (motor-side Coulomb friction on the
// coulomb case: 3.90e5 at the 0.2 s horizon, 2.93e5 at the end, 1.33
// times less), so the stop needs a margin.
constexpr double kStopFactor = 2.0;

// How many horizons of the continuation (first_horizon, 2·, 4·, 8·) the
// screen runs (ScreenFits): on the load_offset case the true offset,
// seventh by score, comes first after the screen, and seven of the eight
// others stop at the first horizon.
constexpr int kScreenStages = 4;

// The screen's last horizon for a continuation from `first_horizon` (s):
// first_horizon·2^(kScreenStages−1). Never throws.
double ScreenHorizon(double first_horizon);

// Each entry's 1-based place when `bound` is sorted lowest first, a
// non-finite bound taken as +inf and ties kept in index order. Never throws.
std::vector<size_t> RanksByBound(const std::vector<double>& bound);

// Which of a batch's competing refits go on past the screen when the lowest
// BIC among them decides (the discovery loop far from a model that explains
// the data, s² > 2). Neither judge ranks reliably alone there: the score
// test is a linearisation at a model far from the data (the payload ninth
// by score on its own data, power_payload), and the screen sees the first
// horizons only (EMPS: the bounds of all nine candidates within 5 % at
// 0.4 s, Coulomb friction sixth of them, then the step's winner by a
// factor 5 in BIC). So the union goes on: candidate b goes on if
// score_rank[b] <= top (1-based place in the step's score ranking), if its
// screen bound is among the `top` lowest (RanksByBound), or if
// its bound is not finite (the screen failed: its refit goes on to its
// retry). One rung of successive halving (Jamieson & Talwalkar 2016,
// "Non-stochastic best arm identification and hyperparameter
// optimization", AISTATS) with two judges. All go on when there are at most
// 2·top. Shapes: score_rank and bound of the same length n; returns n
// flags. Throws std::invalid_argument if the lengths differ or top is 0.
std::vector<bool> GoOnPastScreen(const std::vector<size_t>& score_rank,
                                 const std::vector<double>& bound, size_t top);

// What the screen left of one refit.
struct ScreenedFit {
  // The lower bound of the BIC the refit can end with, from its last
  // screened horizon (FitResult::bic of the stopped fit); +inf if it failed.
  double bound = 0.0;
  double seconds = 0.0;  // wall time of the screen's fit (s)
  // Its shorter horizons, to resume from (FitControl::resume); null if
  // the fit ended before them.
  std::shared_ptr<const HorizonCheckpoint> checkpoint;
};

// Runs every job's first kScreenStages horizons only
// (FitControl::stop_after_horizon = first_horizon·2^(kScreenStages−1)),
// up to `threads` fits at once (FitConcurrently, estimation/fit.h), and returns
// per job (same order) the bound, time and checkpoint. Ordering competing
// refits by the bound, lowest first, lets the leading one set a low level
// early; it changes which refits stop, not which wins. Throws
// std::invalid_argument if a job's solver.first_horizon is not > 0 (no
// continuation: nothing to screen) and as FitParameters does.
std::vector<ScreenedFit> ScreenFits(std::vector<EstimationProblem> jobs, int threads);

// Why a refit stopped early (FitResult::abandoned_horizon) against `level`
// (a BIC) named `level_name` (e.g. "coulomb's BIC"): its horizon, the bound
// and the level it passed; "" for a refit that ran to the end. Never throws.
std::string StoppedText(const FitResult& fit, double level, const std::string& level_name);

}  // namespace axis

#endif  // DISCOVERY_INTERNAL_SCREEN_H_
