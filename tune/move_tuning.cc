#include "tune/move_tuning.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include <nlopt.h>

#include "common/concurrency.h"
#include "common/format.h"
#include "estimation/at_estimate.h"
#include "estimation/current_loop_check.h"
#include "tune/joint_region.h"

namespace axis {
namespace {

// The slowest time scale of the profile the search may choose (a move
// four times as long as at the limits).
constexpr double kMinSpeed = 0.25;
// Subplex's first step, in the unit box of the search.
constexpr double kLocalStep = 0.1;
// Rounds of the robust search: the interval ends where the best setting
// breaks the spec join the models it must meet, and Subplex runs again.
constexpr int kRobustRounds = 3;
// The ends added per round: the worst ones (each adds a simulation to every
// evaluation of the search).
constexpr size_t kEndsPerRound = 2;
// s, the grid on which a shaped command's smoothing is read (the move
// response's output period).
constexpr double kSmoothingGrid = 1e-4;
// A residual vibration is shaped only if it swings by more than this
// fraction of the position band about its mean (ResidualVibrationFrequency).
constexpr double kVibrationFloor = 0.1;

constexpr FigureField<MoveMetrics> kMoveFigures[] = {
    {"move_time", &MoveMetrics::move_time},
    {"settling_time", &MoveMetrics::settling_time},
    {"following_error", &MoveMetrics::following_error},
    {"overshoot", &MoveMetrics::overshoot},
    {"peak_current", &MoveMetrics::peak_current},
    {"ringing", &MoveMetrics::ringing}};

// A gain from its coordinate z in [0, 1] of the search box and back: log
// between the ends where the lower one is positive, else linear.
double GainAt(const TunedGain& g, double z) {
  if (g.low > 0.0) return std::exp(std::log(g.low) + z * (std::log(g.high) - std::log(g.low)));
  return g.low + z * (g.high - g.low);
}
double CoordinateOf(const TunedGain& g, double value) {
  const double x = std::clamp(value, g.low, g.high);
  if (g.low > 0.0) return (std::log(x) - std::log(g.low)) / (std::log(g.high) - std::log(g.low));
  return (x - g.low) / (g.high - g.low);
}

// The spec whose bounds the search must meet: each upper bound lowered by
// the fraction `margin` (what the model does not capture: its integration
// step and current-loop approximation, the corners of the uncertainty).
MoveSpec WithMargin(MoveSpec s, double margin) {
  for (double MoveSpec::*b : {&MoveSpec::max_settling_time, &MoveSpec::max_following_error,
                              &MoveSpec::max_overshoot, &MoveSpec::max_current,
                              &MoveSpec::max_ringing}) {
    s.*b *= 1.0 - margin;  // NaN stays NaN: no bound
  }
  return s;
}

// The input shaper a search tunes (none: the unshaped move), and the box of
// its frequency (Hz, log scale) and damping ratio.
struct ShaperSearch {
  ShaperType type = ShaperType::kNone;
  double f_low = 0.0, f_high = 0.0;
  double zeta_low = 0.0, zeta_high = 0.0;
};

struct NloptDeleter {
  void operator()(nlopt_opt o) const { nlopt_destroy(o); }
};
using Nlopt = std::unique_ptr<std::remove_pointer_t<nlopt_opt>, NloptDeleter>;

// A model other than the estimate a setting is judged on: an interval end,
// or the estimate with the full current loop where the job fits the
// quasi-steady one.
struct Check {
  std::string name;       // "V_L at low end", "the full current loop", "joint sample 3"
  std::string parameter;  // what moves the figures ("V_L", "current loop"; "" for a sample)
  AxisConfig model;
  double step = 0.0;      // s, its RK4 step
  bool sample = false;    // a point of the joint 95 % region (tune/joint_region.h)
};

class MoveTuner {
 public:
  MoveTuner(const EstimationProblem& job, const FitResult& result, const TuneSettings& tune,
            const AnalogLoopTuning* analog)
      : job_(job),
        result_(result),
        analog_(analog),
        settings_(tune.move),
        spec_(tune.move.spec),
        samples_(tune.samples),
        threads_(std::max(1, job.solver.threads)) {}

  MoveTuning Run() {
    const auto start = std::chrono::steady_clock::now();
    if (!Prepare()) return out_;
    std::vector<SearchTask> unshaped;
    for (const std::string& profile : spec_.profiles) unshaped.push_back({profile, {}, {}});
    out_.tuned = SearchEach(unshaped);
    SearchShapers();
    if (settings_.klipper.enabled) ApplyKlippersRule();
    // Every judged run ends together (the plots and tune_move.csv put the
    // current and the proposed side by side): a shorter move settles for
    // longer.
    judge_end_ = out_.current.reference.MoveDuration();
    for (const MoveSetting& t : out_.tuned) {
      judge_end_ = std::max(judge_end_, t.reference.MoveDuration());
    }
    if (out_.klipper_ran) judge_end_ = std::max(judge_end_, out_.klipper.reference.MoveDuration());
    judge_end_ += spec_.settle;
    Judge(&out_.current);
    for (MoveSetting& t : out_.tuned) Judge(&t);
    if (out_.klipper_ran) Judge(&out_.klipper);
    out_.proposed = out_.tuned[Choose()];
    out_.ran = true;
    out_.simulations = simulations_;
    out_.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out_;
  }

 private:
  // The tuned setting proposed: the lowest objective among those that meet
  // the spec at the estimate and every check; where none does, the one
  // that meets it at the most checks (the likeliest to hold on the axis: on
  // the tune_sensor_delay campaign the fastest missed on a seed where the
  // other profile, meeting more checks, held), then the lowest objective.
  size_t Choose() const {
    size_t best = 0;
    for (size_t k = 1; k < out_.tuned.size(); ++k) {
      const MoveSetting& a = out_.tuned[k];
      const MoveSetting& b = out_.tuned[best];
      if (a.robust != b.robust) {
        if (a.robust) best = k;
      } else if (!a.robust && a.checks_met != b.checks_met) {
        if (a.checks_met > b.checks_met) best = k;
      } else if (a.objective < b.objective) {
        best = k;
      }
    }
    return best;
  }

  // Each shaper of the settings on each profile, from the profile's
  // unshaped tuned setting, in the frequency range the settings give or
  // around the residual vibration that setting leaves.
  void SearchShapers() {
    out_.shapers = settings_.shapers;
    if (settings_.shapers.empty()) return;
    std::vector<SearchTask> shaped;
    for (const MoveSetting& start : out_.tuned) {
      ShaperSearch box;
      if (!ShaperRange(start, &box)) continue;
      for (ShaperType type : settings_.shapers) {
        box.type = type;
        shaped.push_back({start.profile, box, start});
      }
    }
    for (MoveSetting& s : SearchEach(shaped)) out_.tuned.push_back(std::move(s));
  }

  // One search of the tuner: a profile, and the shaper it tunes with the
  // profile's unshaped tuned setting it starts from (none: unshaped).
  struct SearchTask {
    std::string profile;
    ShaperSearch shaping;
    std::optional<MoveSetting> shaped_start;
  };

  // Search of each task, several at once (job.solver.threads): each on a
  // copy of this tuner (its own scenarios_, shaping_ and simulation count;
  // the model, checks and spec read only), the results in the tasks'
  // order, the same whatever the number of threads. A search's own loops
  // over models (CheckEach) get the threads the searches leave.
  std::vector<MoveSetting> SearchEach(const std::vector<SearchTask>& tasks) {
    std::vector<MoveSetting> found(tasks.size());
    std::vector<int> simulations(tasks.size(), 0);
    const int at_once = static_cast<int>(std::min<size_t>(tasks.size(), threads_));
    const int inner = std::max(1, threads_ / std::max(1, at_once));
    ForEachConcurrently(tasks.size(), threads_, [&](size_t k) {
      MoveTuner worker(*this);
      worker.threads_ = inner;
      worker.simulations_ = 0;  // Search clears the scenarios itself
      worker.shaping_ = tasks[k].shaping;
      worker.shaped_start_ = tasks[k].shaped_start ? &*tasks[k].shaped_start : nullptr;
      found[k] = worker.Search(tasks[k].profile);
      simulations[k] = worker.simulations_;
    });
    for (int n : simulations) simulations_ += n;
    return found;
  }

  // The addresses of `checks`, for CheckEach.
  static std::vector<const Check*> AddressesOf(const std::vector<Check>& checks) {
    std::vector<const Check*> out;
    for (const Check& check : checks) out.push_back(&check);
    return out;
  }

  // The move of `controller` and `reference` on each of `checks` (the run
  // `settle` s past the move), up to threads_ at once; counts them.
  std::vector<MoveResponse> CheckEach(const std::vector<const Check*>& checks,
                                      const ControllerConfig& controller,
                                      const Reference& reference, double settle) {
    std::vector<MoveResponse> out(checks.size());
    ForEachConcurrently(checks.size(), threads_, [&](size_t k) {
      out[k] = SimulateMove(checks[k]->model, controller, reference, checks[k]->step, settle);
    });
    simulations_ += static_cast<int>(checks.size());
    return out;
  }

  // The frequency and damping box of the shapers on `unshaped`'s profile:
  // the settings' range, else half to twice the frequency of the residual
  // vibration `unshaped` leaves at the estimate; false, with a note, where
  // it leaves none to shape.
  bool ShaperRange(const MoveSetting& unshaped, ShaperSearch* box) {
    box->zeta_low = settings_.shaper_damping_low;
    box->zeta_high = settings_.shaper_damping_high;
    if (!std::isnan(settings_.shaper_frequency_low)) {
      box->f_low = settings_.shaper_frequency_low;
      box->f_high = settings_.shaper_frequency_high;
      out_.shaper_notes.push_back(unshaped.profile + ": " + FormatNumber(box->f_low, 4) + "-" +
                                  FormatNumber(box->f_high, 4) + " Hz, as tune.move sets");
      return true;
    }
    ++simulations_;
    const MoveResponse r =
        SimulateMove(model_, unshaped.controller, unshaped.reference, step_, spec_.settle);
    const double f = ResidualVibrationFrequency(r, kVibrationFloor * spec_.position_band);
    if (std::isnan(f)) {
      out_.shaper_notes.push_back(
          unshaped.profile + ": no shaper: its unshaped tuned move leaves no residual "
                             "vibration on the identified model (swing about its mean under " +
          FormatNumber(kVibrationFloor * spec_.position_band, 3) +
          " m, or under three crossings; tune.move.shaper_frequency sets a range)");
      return false;
    }
    box->f_low = 0.5 * f;
    box->f_high = 2.0 * f;
    out_.shaper_notes.push_back(unshaped.profile + ": " + FormatNumber(box->f_low, 4) + "-" +
                                FormatNumber(box->f_high, 4) +
                                " Hz, around the residual vibration of its unshaped tuned "
                                "move at " + FormatNumber(f, 4) + " Hz");
    return true;
  }

  // Klipper's rule on the resonance test of the identified model under the
  // trapezoid's unshaped tuned gains (else the first profile's), and that
  // setting with the shaper it recommends.
  void ApplyKlippersRule() {
    size_t base = 0;
    for (size_t k = 0; k < spec_.profiles.size(); ++k) {
      if (spec_.profiles[k] == "trapezoid") base = k;
    }
    const MoveSetting& unshaped = out_.tuned[base];
    ++simulations_;
    try {
      out_.resonance =
          SimulateResonanceTest(model_, unshaped.controller, step_, settings_.klipper);
      out_.klipper_choice =
          ChooseShaperAsKlipper(out_.resonance, unshaped.reference, settings_.klipper);
    } catch (const std::exception& e) {
      out_.klipper_note = std::string("Klipper's rule not applied: ") + e.what();
      return;
    }
    scenarios_.clear();
    out_.klipper = Evaluate(unshaped.profile, unshaped.controller, unshaped.speed,
                            out_.klipper_choice.shaper);
    out_.klipper_ran = true;
  }

  bool Prepare() {
    out_.spec = spec_;
    out_.margin = settings_.margin;
    search_spec_ = WithMargin(spec_, settings_.margin);
    out_.gains = settings_.gains;
    out_.slow_down = settings_.slow_down;
    if (!settings_.enabled) {
      out_.note = "no move tuning: the job has no tune.move block";
      return false;
    }
    if (job_.experiments.empty()) throw std::runtime_error("the job has no fitted experiment");
    model_ = AtEstimate(job_, result_).model;
    if (analog_ != nullptr && analog_->ran) {
      model_.params.K1 = analog_->proposed.K1;
      model_.params.T_p = analog_->proposed.T_p;
      out_.on_proposed_analog_loop = true;
      // K_1 and T_p are then settings, not uncertain parameters of the axis.
      fixed_ = {"T_p", "K1"};
    }
    base_ = model_.has_controller ? model_.controller : ControllerConfig{};
    if (base_.firmware.enabled) {
      out_.note = "no move tuning: the controller is a servo's firmware loop (type: "
                  "servo_firmware, MODEL.md section 5), whose gains are its registers, not the "
                  "sampled position controller's that tune.move sets";
      return false;
    }
    step_ = job_.experiments.front().options.step;
    // The longest run the search can make: the penalty per unit of
    // violation, and the time charged to a move that does not settle.
    penalty_ = 0.0;
    for (const std::string& p : spec_.profiles) {
      penalty_ = std::max(penalty_, MoveAt(p, kMinSpeed).MoveDuration() + spec_.settle);
    }
    MakeChecks();
    out_.current = Evaluate(spec_.profiles.front(), base_, 1.0);
    if (!out_.current.response.finite) {
      throw std::runtime_error("the identified model's move under the current controller is "
                               "not finite");
    }
    return true;
  }

  // The interval ends, and the full current loop at its step
  // (estimation/current_loop_check.h WithFullLoop) where the job fits the
  // quasi-steady one: the tuning is for the machine, not the fit's
  // approximation.
  void MakeChecks() {
    for (IntervalEnd& end : IntervalEnds(result_, model_, fixed_)) {
      checks_.push_back({EndName(end), end.parameter, std::move(end.model), step_});
    }
    for (RegionSample& s :
         JointRegionSamples(result_, model_, fixed_, job_.free, samples_)) {
      checks_.push_back({s.name, "", std::move(s.model), step_, true});
    }
    if (model_.structure.amplifier != Amplifier::kAnalogVelocityLoop ||
        model_.structure.current_loop != CurrentLoop::kQuasiSteady) {
      return;
    }
    double full_step = 0.0;
    EstimationProblem full = WithFullLoop(AtEstimate(job_, result_), &full_step);
    full.model.params.K1 = model_.params.K1;
    full.model.params.T_p = model_.params.T_p;
    checks_.push_back({"the full current loop", "current loop", std::move(full.model),
                       std::min(step_, full_step)});
  }

  // The spec's move with `profile` at the time scale `speed`.
  Reference MoveAt(const std::string& profile, double speed) const {
    Reference r;
    r.kind = profile == "min_jerk" ? Reference::Kind::kMinJerk : Reference::Kind::kTrapezoid;
    r.distance = spec_.distance;
    r.velocity = spec_.max_velocity * speed;
    r.acceleration = spec_.max_acceleration * speed * speed;
    r.jerk = spec_.max_jerk * speed * speed * speed;
    return r;
  }

  MoveSetting Evaluate(const std::string& profile, const ControllerConfig& c, double speed,
                       const InputShaper& shaper = InputShaper{}) {
    MoveSetting s;
    s.K1 = model_.params.K1;
    s.T_p = model_.params.T_p;
    s.profile = profile;
    s.controller = c;
    s.speed = speed;
    s.reference = MoveAt(profile, speed);
    s.reference.shaper = shaper;
    ++simulations_;
    s.response = SimulateMove(model_, c, s.reference, step_, spec_.settle);
    s.metrics = MeasureMove(s.response, spec_);
    s.violations = MoveViolations(s.metrics, spec_);
    s.objective = ObjectiveOf(s.metrics);
    // The worst over the models the robust search has added.
    for (const MoveResponse& r : CheckEach(AddressesOf(scenarios_), c, s.reference,
                                           spec_.settle)) {
      s.objective = std::max(s.objective, ObjectiveOf(MeasureMove(r, spec_)));
    }
    return s;
  }

  // A move that does not settle is charged the longest unshaped run, or
  // its own run where a shaper made that longer.
  double ObjectiveOf(const MoveMetrics& m) const {
    return (m.settled ? m.move_time : std::max(penalty_, m.move_time)) +
           penalty_ * MoveViolation(m, search_spec_);
  }

  // The checks at which `s` breaks the spec with its margin, the worst
  // kEndsPerRound of them (by MoveViolation).
  std::vector<Check> Violating(const MoveSetting& s) {
    // The joint region's samples judge the setting (Judge) but do not
    // steer the search: added as scenarios, the worst of them (out at
    // the region's edge, farther than any interval end) made the tuned
    // moves worse on the axes that made the records (tune_coulomb and
    // tune_payload: move spec met 8/10 each, against 10/10 without).
    std::vector<const Check*> ends;
    for (const Check& check : checks_) {
      if (!check.sample) ends.push_back(&check);
    }
    const std::vector<MoveResponse> runs = CheckEach(ends, s.controller, s.reference, spec_.settle);
    std::vector<std::pair<double, const Check*>> broken;
    for (size_t k = 0; k < ends.size(); ++k) {
      const double v = MoveViolation(MeasureMove(runs[k], spec_), search_spec_);
      if (v > 0.0) broken.emplace_back(v, ends[k]);
    }
    std::stable_sort(broken.begin(), broken.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    std::vector<Check> out;
    for (size_t k = 0; k < broken.size() && k < kEndsPerRound; ++k) {
      out.push_back(*broken[k].second);
    }
    return out;
  }

  // The setting at the coordinates z of the search box: the gains, the
  // speed (with slow_down), the shaper's frequency and damping (shaped).
  MoveSetting At(const std::string& profile, const double* z) {
    ControllerConfig c = base_;
    size_t i = 0;
    for (; i < settings_.gains.size(); ++i) {
      *ControllerGain(&c, settings_.gains[i].name) = GainAt(settings_.gains[i], z[i]);
    }
    const double speed = settings_.slow_down ? z[i++] : 1.0;
    InputShaper shaper;
    if (shaping_.type != ShaperType::kNone) {
      const double f = std::exp(std::log(shaping_.f_low) +
                                z[i] * (std::log(shaping_.f_high) - std::log(shaping_.f_low)));
      const double zeta = shaping_.zeta_low + z[i + 1] * (shaping_.zeta_high - shaping_.zeta_low);
      shaper = MakeInputShaper(shaping_.type, f, zeta);
    }
    return Evaluate(profile, c, speed, shaper);
  }

  struct SearchState {
    MoveTuner* tuner;
    const std::string* profile;
    MoveSetting best;
    int evaluations = 0;
  };

  static double Objective(unsigned, const double* z, double*, void* data) {
    SearchState* st = static_cast<SearchState*>(data);
    MoveSetting s = st->tuner->At(*st->profile, z);
    ++st->evaluations;
    const double j = std::isfinite(s.objective) ? s.objective : HUGE_VAL;
    if (st->best.profile.empty() || j < st->best.objective) {
      s.response = MoveResponse{};  // the best keeps its figures; Judge simulates again
      st->best = std::move(s);
    }
    return j;
  }

  // DIRECT-L on the box for half the budget, then Subplex from the better
  // of its best and the current setting (with a shaper: the profile's
  // unshaped tuned setting, the shaper in the middle of its box); then the
  // robust rounds.
  MoveSetting Search(const std::string& profile) {
    scenarios_.clear();
    const size_t gains = settings_.gains.size();
    const unsigned n = static_cast<unsigned>(gains + (settings_.slow_down ? 1 : 0) +
                                             (shaping_.type != ShaperType::kNone ? 2 : 0));
    std::vector<double> lower(n, 0.0), upper(n, 1.0), z(n, 0.5);
    if (settings_.slow_down) lower[gains] = kMinSpeed;
    SearchState st{this, &profile, MoveSetting{}, 0};
    const int global_budget = settings_.evaluations / 2;
    Run(NLOPT_GN_DIRECT_L, lower, upper, global_budget, &st, &z);
    std::vector<double> start =
        Coordinates(st.best.controller, st.best.speed, st.best.reference.shaper);
    std::vector<double> current =
        shaped_start_ != nullptr
            ? Coordinates(shaped_start_->controller, shaped_start_->speed, InputShaper{})
            : Coordinates(base_, 1.0, InputShaper{});
    const double best_of_direct = st.best.objective;
    Objective(n, current.data(), nullptr, &st);  // the current gains, in the box
    if (st.best.objective < best_of_direct) start = current;
    Run(NLOPT_LN_SBPLX, lower, upper, settings_.evaluations - st.evaluations, &st, &start);
    MoveSetting best = std::move(st.best);
    best.evaluations = st.evaluations;
    Robustify(profile, lower, upper, &best);
    return best;
  }

  // Up to kRobustRounds times: the interval ends at which `best` breaks the
  // spec join scenarios_ (the objective is then the worst over the estimate
  // and them), and Subplex runs again from `best` for half the budget.
  void Robustify(const std::string& profile, const std::vector<double>& lower,
                 const std::vector<double>& upper, MoveSetting* best) {
    for (int round = 0; round < kRobustRounds; ++round) {
      std::vector<Check> violating = Violating(*best);
      if (violating.empty()) break;
      for (Check& check : violating) {
        if (std::find(best->scenarios.begin(), best->scenarios.end(), check.name) !=
            best->scenarios.end()) {
          continue;
        }
        best->scenarios.push_back(check.name);
        scenarios_.push_back(std::move(check));
      }
      SearchState st{this, &profile, MoveSetting{}, 0};
      std::vector<double> start =
          Coordinates(best->controller, best->speed, best->reference.shaper);
      Run(NLOPT_LN_SBPLX, lower, upper, settings_.evaluations / 2, &st, &start);
      const std::vector<std::string> names = best->scenarios;
      const int evaluations = best->evaluations + st.evaluations;
      *best = std::move(st.best);
      best->scenarios = names;
      best->evaluations = evaluations;
    }
  }

  // The coordinates of a setting in the search box; a shaped search puts
  // an unshaped setting's shaper in the middle of its box.
  std::vector<double> Coordinates(ControllerConfig c, double speed,
                                  const InputShaper& shaper) const {
    std::vector<double> z;
    for (const TunedGain& g : settings_.gains) z.push_back(CoordinateOf(g, *ControllerGain(&c, g.name)));
    if (settings_.slow_down) z.push_back(std::clamp(speed, kMinSpeed, 1.0));
    if (shaping_.type != ShaperType::kNone) {
      if (shaper.type == ShaperType::kNone) {
        z.insert(z.end(), {0.5, 0.5});
      } else {
        z.push_back(CoordinateOf({"", shaping_.f_low, shaping_.f_high}, shaper.frequency));
        z.push_back(std::clamp((shaper.damping - shaping_.zeta_low) /
                                   (shaping_.zeta_high - shaping_.zeta_low),
                               0.0, 1.0));
      }
    }
    return z;
  }

  static void Run(nlopt_algorithm algorithm, const std::vector<double>& lower,
                  const std::vector<double>& upper, int budget, SearchState* st,
                  std::vector<double>* z) {
    if (budget <= 0) return;
    const unsigned n = static_cast<unsigned>(z->size());
    Nlopt opt(nlopt_create(algorithm, n));
    if (!opt) throw std::runtime_error("NLopt could not create its optimiser");
    nlopt_set_lower_bounds(opt.get(), lower.data());
    nlopt_set_upper_bounds(opt.get(), upper.data());
    nlopt_set_min_objective(opt.get(), &MoveTuner::Objective, st);
    nlopt_set_maxeval(opt.get(), budget);
    std::vector<double> step(n, kLocalStep);
    nlopt_set_initial_step(opt.get(), step.data());
    double value = 0.0;
    // Its outcome is the best point the objective saw (SearchState::best),
    // whatever NLopt's return code.
    nlopt_optimize(opt.get(), z->data(), &value);
  }

  // The setting at the estimate and at each end of each free parameter's
  // interval.
  void Judge(MoveSetting* s) {
    ++simulations_;
    const double settle = judge_end_ - s->reference.MoveDuration();
    s->response = SimulateMove(model_, s->controller, s->reference, step_, settle);
    s->metrics = MeasureMove(s->response, spec_);
    s->violations = MoveViolations(s->metrics, spec_);
    s->smoothing = MoveSmoothing(s->reference, kSmoothingGrid);
    s->residual_vibration = {{"the estimate", s->metrics.ringing}};
    WidenMoveBand(s->response, &s->band_low, &s->band_high);
    const std::vector<std::string> broken = MoveViolatedFigures(s->metrics, spec_);
    s->robust = s->violations.empty();
    s->spread = StartSpread(FigureNames(kMoveFigures), FigureValues(s->metrics, kMoveFigures));
    std::vector<double> moved(std::size(kMoveFigures), 0.0);
    const std::vector<MoveResponse> runs =
        CheckEach(AddressesOf(checks_), s->controller, s->reference, settle);
    for (size_t k = 0; k < checks_.size(); ++k) {
      const Check& check = checks_[k];
      const MoveResponse& r = runs[k];
      WidenMoveBand(r, &s->band_low, &s->band_high);
      const MoveMetrics m = MeasureMove(r, spec_);
      s->residual_vibration.push_back({check.name, m.ringing});
      const std::vector<std::string> violations = MoveViolations(m, spec_);
      s->checks_met += violations.empty();
      if (check.sample) {
        ++s->samples;
        s->samples_met += violations.empty();
      }
      if (check.sample && s->samples - s->samples_met > 1) {
        s->robust = false;  // an earlier sample broke it and was noted
      } else {
        NoteEndViolations(check.name, violations, MoveViolatedFigures(m, spec_), broken,
                          &s->robust, &s->robust_violations);
      }
      WidenSpread(check.parameter, FigureValues(m, kMoveFigures), &moved, &s->spread);
    }
  }

  const EstimationProblem& job_;
  const FitResult& result_;
  const AnalogLoopTuning* analog_;
  const MoveTuneSettings& settings_;
  const MoveSpec& spec_;
  const int samples_;  // TuneSettings::samples: points of the joint region
  int threads_;        // simulations at once (job.solver.threads; a search's: SearchEach)
  MoveSpec search_spec_;  // spec_ with the design margin (the search's)
  AxisConfig model_;
  ControllerConfig base_;
  std::vector<std::string> fixed_;        // parameters that are settings
  std::vector<Check> checks_;     // the models a setting is judged on
  std::vector<Check> scenarios_;  // those the robust search has added
  ShaperSearch shaping_;                       // the shaper the search tunes
  const MoveSetting* shaped_start_ = nullptr;  // its profile's unshaped setting
  double step_ = 0.0;
  double penalty_ = 0.0;
  double judge_end_ = 0.0;  // s, the judged runs' length
  int simulations_ = 0;
  MoveTuning out_;
};

}  // namespace

double* ControllerGain(ControllerConfig* c, const std::string& name) {
  if (name == "G_p") return &c->G_p;
  if (name == "G_i") return &c->G_i;
  if (name == "G_v") return &c->G_v;
  if (name == "G_ff") return &c->G_ff;
  if (name == "alpha") return &c->alpha;
  return nullptr;
}

MoveTuning TuneMove(const EstimationProblem& job, const FitResult& result,
                    const TuneSettings& tune, const AnalogLoopTuning* analog) {
  return MoveTuner(job, result, tune, analog).Run();
}

std::vector<std::string> MoveViolationsOn(const AxisConfig& axis, double step,
                                          const MoveSetting& s, const MoveSpec& spec) {
  AxisConfig model = axis;
  model.params.K1 = s.K1;
  model.params.T_p = s.T_p;
  return MoveViolations(
      MeasureMove(SimulateMove(model, s.controller, s.reference, step, spec.settle), spec), spec);
}

}  // namespace axis
