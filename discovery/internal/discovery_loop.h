// The model-discovery loop as a sequence of named steps, its state in
// members (as estimation/internal/fitter.h Fitter): per forward step the score tests
// of the candidates, the rule, the refits (screened and run against the
// level that decides the step), the choice of the step's effect; then the
// backward pass, the removal of insignificant effects, and the final
// model's diagnostics and verdict. Discover (discovery/discovery.h) is the
// public entry; this class is internal to discovery/. What each step does
// and why: discovery/discovery.h Discover, discovery/discovery_settings.h.
#ifndef DISCOVERY_INTERNAL_DISCOVERY_LOOP_H_
#define DISCOVERY_INTERNAL_DISCOVERY_LOOP_H_

#include <cstddef>
#include <functional>
#include <memory>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "common/progress.h"
#include "discovery/candidates.h"
#include "discovery/discovery_report.h"
#include "discovery/score_test.h"
#include "estimation/fit_control.h"
#include "estimation/fit_result.h"
#include "estimation/horizon_checkpoint.h"
#include "discovery/discovery_settings.h"
#include "estimation/estimation_problem.h"

namespace axis {

class DiscoveryLoop {
 public:
  // `settings`, `job`, `result` and `progress` (may be null) must outlive
  // the loop; `job` and `result` are the loop's model and fit, replaced as
  // it adds and removes effects.
  // `stage` (may be empty) is told each step's name as it begins.
  DiscoveryLoop(const DiscoverySettings& settings, EstimationProblem* job, FitResult* result,
                std::ostream* progress, std::function<void(const char*)> stage = {});
  DiscoveryLoop(const DiscoveryLoop&) = delete;
  DiscoveryLoop& operator=(const DiscoveryLoop&) = delete;

  // Runs the loop once (Discover). Throws as Discover.
  DiscoveryReport Run();

 private:
  // A refit that improved BIC, waiting for the step's choice.
  struct Trial {
    size_t step;  // index in report_.steps
    Candidate candidate;
    EstimationProblem job;
    FitResult fit;
  };
  // Refits waiting to run: in score order, one at a time by the first
  // rule (the first that improves BIC ends the step), all of the top
  // `misspecified_tries` at once, concurrently, by the second
  // (FitConcurrently).
  struct Pending {
    const Score* score;
    Candidate candidate;
    std::vector<EstimationProblem> starts;      // one job per start (StartsOf)
    std::vector<std::string> names;  // the effect's parameters, now free
    // What each start begins from where StartLabel does not say (a filter
    // beside a delay: its time constant), else empty.
    std::vector<std::string> labels;
  };
  // The level a refit must end below to matter (issue 11): a refit whose
  // BIC's lower bound passes kStopFactor times it stops on a shorter
  // horizon (FitControl::abandon_above_bic). First the BIC before the
  // step (a refit above it is rejected); once a batch's leading refit has
  // run, its BIC if it would be kept (no other refit above it can win the
  // step).
  struct Level {
    double bic;
    std::string name;  // for DiscoveryStep::stopped
  };

  // ---- a forward step; false ends the forward steps
  bool ForwardStep();
  bool RankStepCandidates();  // the score tests; false if none is significant
  void ChooseRule();          // score order, or the lowest BIC of the refits
  void RefitCandidates();     // the significant candidates, by the rule
  // The candidate the data cannot tell from `score`'s with no more
  // parameters than it, or "".
  std::string TwinOf(const Score& score) const;
  // `score` and the front-end candidates on its channel the score test
  // cannot tell from it (RefitCandidates), or nothing if it is not a
  // front-end term or has no such twin.
  std::vector<std::string> FrontEndFamily(const Score& score) const;
  int DofOf(const std::string& name) const;
  void QueueRefit(const Score& score);
  // The jobs of a candidate's refit: the effect added at `score`'s step,
  // one per start.
  std::vector<EstimationProblem> RefitJobs(const Candidate& candidate, const Score& score) const;
  // The score the refits of a delay start from: `score`, or with its step at
  // the records' alignment lag where that is more than half a sample away.
  Score DelayStart(const Candidate& candidate, const Score& score) const;
  // Queues the front-end terms of the channels that already have one, while
  // the residual is above the noise (s² past 3 standard deviations of its
  // χ²), whatever their score (a filter after a delay is second order).
  void QueueFrontEndCompanions();
  // Whether `candidate` is a low-pass on a channel whose delay is already in
  // the model, and the refits of one such: three starts (FilterAfterDelayJobs
  // in discovery_loop.cc says which).
  bool IsFilterAfterDelay(const Candidate& candidate) const;
  std::vector<EstimationProblem> FilterAfterDelayJobs(const Candidate& candidate,
                                                      const Score& score) const;
  // Among the refits that improved BIC, the one the step keeps given the
  // lowest, improved_[lowest]: a simpler front-end term of the same channel
  // (a delay before a first-order low-pass before a second-order one) whose
  // BIC is within kDecisiveBic of the lowest wins instead (issue 56: a
  // delay split into a shorter delay and a resonant filter).
  size_t SimplestFrontEnd(size_t lowest) const;
  bool KeepLowest();  // the step's effect; false if no refit improved BIC

  // ---- a batch of refits (batch_)
  void RunBatch();
  void ShowBatchStatus() const;
  void ScreenBatch();      // order_, screen_seconds_, screen_bound_, resume_
  // Which refits go on past the screen (goes_on_): all, but by the lowest
  // BIC rule only the top `tries` by score, the top `tries` by the screen's
  // bound, and those whose screen failed.
  void CutAfterScreen();
  void RunAgainstLevel();  // the leader, then the others against its level
  // Fits candidates [from, to) of order_ against the current level; the
  // starts of a candidate with more of them than solver.finalists
  // (StartsOf, the filter beside a delay) to their last shorter horizon
  // first, then the finalists lowest there to the whole record
  // (ContinueFinalists).
  void RunCandidates(std::vector<size_t>::const_iterator from,
                     std::vector<size_t>::const_iterator to);
  // The finalists of each candidate among `jobs` (run with `controls`;
  // owner[j] its candidate; `out`, `secs`: the first run's results and
  // times, updated in place; jobs[0] goes to fits_[first]): of the starts
  // that stopped before the whole record, the solver.finalists lowest by
  // their BIC's bound there resume from their checkpoints; the others are
  // marked not continued (cut_). Where every finalist of a candidate
  // fails, its other starts go on too.
  void ContinueFinalists(const std::vector<EstimationProblem>& jobs,
                         const std::vector<FitControl>& controls,
                         const std::vector<size_t>& owner, std::vector<FitResult>* out,
                         std::vector<double>* secs, size_t first);
  // Whether fitted channel `k`'s residual is above its noise in the
  // current fit: Σ(r/σ)² − n above 3·√(2n) over its samples.
  bool ChannelAboveNoise(int k) const;
  // Stops fitting the records' tail a channel read ahead cannot predict.
  void TrimAheadOfTheRecords();
  // The callback FitConcurrently calls as each refit of the batch ends,
  // `already` of the batch's refits done before that call.
  std::function<void(size_t, size_t)> RefitProgress(size_t already);
  // The job's solver.finalists, at least 1.
  size_t Finalists() const;
  void SetLevelFromLeader();
  void JudgeCandidate(size_t b);
  // Candidate b's step when it did not go on past the screen.
  void RecordCut(size_t b);
  // Candidate b's place in the step's score ranking (1-based).
  size_t ScoreRank(size_t b) const;
  // Candidate b's start to keep (its lowest BIC): retried from a tenth of
  // the step if every start failed, its search bounds widened if it ended
  // on one; fills the record's timing and notes.
  size_t ChooseStart(size_t b, std::vector<FitResult>* own, DiscoveryStep* record);
  size_t RetryFromTenth(size_t b, std::vector<FitResult>* own, DiscoveryStep* record);
  std::string StartsText(size_t b, const std::vector<FitResult>& own,
                         size_t best) const;
  void RealignDelay(size_t b, size_t best, std::vector<FitResult>* own, DiscoveryStep* record);
  void WidenIfOnBound(size_t b, size_t best, std::vector<FitResult>* own,
                      DiscoveryStep* record);
  // The step's fields that come from the candidate and its score (effect,
  // rule, chi2, dof, p_value, bic_before); RecordRefit or RecordCut add the
  // rest.
  DiscoveryStep StepOf(const Pending& q) const;
  void RecordRefit(const Pending& q, const Level& level, const FitResult& refit,
                   const EstimationProblem& refit_job, DiscoveryStep* record) const;
  void PrintRefit(const Pending& q, const DiscoveryStep& record) const;

  // ---- after the forward steps
  void BackwardPass();
  void DropInsignificantEffects();
  void DiagnoseFinalModel();  // the final diagnostics and verdict

  const DiscoverySettings& settings_;
  EstimationProblem* job_;
  FitResult* result_;
  std::ostream* progress_;
  // The job's continuation, kept by the loop's refits (AsWarmRefit
  // switches it off).
  double first_horizon_ = 0.0;
  // Progress (common/progress.h): the stage only. How many refits a step
  // takes, and how many steps the loop makes, is known only as it goes, so
  // no remaining time is estimated here.
  ProgressStream* status_ = nullptr;
  std::function<void(const char*)> stage_;
  // TrimAheadOfTheRecords: the job's records before the first trim, and
  // how much of their end is not fitted now (s).
  std::vector<FitExperiment> whole_records_;
  double trimmed_ = 0.0;
  // QueueFrontEndCompanions: the front-end terms refitted as companions
  // since the front end last changed.
  std::set<std::string> companions_tried_;
  DiscoveryReport report_;

  // ---- the forward step's state
  int step_ = 0;
  std::vector<Candidate> candidates_;
  std::string step_name_;
  Ranking ranking_;
  double threshold_ = 0.0;  // alpha / number of candidates
  bool by_refit_ = false;   // s² above kMisspecifiedS2: the lowest BIC wins
  std::string rule_;
  std::vector<Trial> improved_;
  int tries_ = 0;
  std::string rejected_;
  std::vector<Pending> batch_;
  std::set<std::string> queued_;  // the step's candidates queued so far
  Level level_;

  // ---- the batch's state
  // The order the refits run in: the screen's, by bound, lowest first;
  // after the leader, those that go on are reordered by screen time.
  std::vector<size_t> order_;
  std::vector<double> screen_seconds_;
  // Per candidate: the screen's BIC bound (lowest over its starts; +inf if
  // every start failed or nothing was screened), whether its refit goes on
  // past the screen.
  std::vector<double> screen_bound_;
  std::vector<bool> goes_on_;
  // The screen's shorter horizons, per candidate and start, which its
  // refit goes on after instead of running them again (FitControl::resume).
  std::vector<std::vector<std::shared_ptr<const HorizonCheckpoint>>> resume_;
  std::vector<size_t> pos_;     // candidate c's first start in fits_
  std::vector<Level> level_of_;  // the level candidate c ran against
  std::vector<FitResult> fits_;
  std::vector<double> seconds_;
  // Per entry of fits_: a start not continued to the whole record (not
  // among its candidate's finalists), and its BIC's bound where it stopped
  // (its fits_ entry's bic is then +inf, so that it is never kept).
  std::vector<bool> cut_;
  std::vector<double> cut_bound_;
  size_t runs_done_ = 0;  // the batch's refit runs done (progress line)
};

}  // namespace axis

#endif  // DISCOVERY_INTERNAL_DISCOVERY_LOOP_H_
