// The sampled position controller and the move of the identified axis tuned
// to a specification (issue 45; job key `tune.move:`, tune/tune_settings.h
// MoveTuneSettings). Nelson & Chang (1984) built their simulation for
// "off-line testing of system changes and new control schemes" and named
// minimum-time and minimum-jerk moves as the strategies to evaluate; with
// the current and voltage limits the usual linear design does not apply,
// so the search simulates the nonlinear model (tune/move_response.h).
//
// For each profile of the spec (trapezoid, minimum-jerk at the machine's
// limits), unshaped and with each input shaper of
// MoveTuneSettings::shapers (sim/input_shaper.h; its frequency and
// damping searched too): the controller gains of MoveTuneSettings::gains
// (MODEL.md §5)
// and, with slow_down, a time scale s in [0.25, 1] of the profile are
// searched to minimise the move time (start to settled in the band) plus
// a penalty per unit of the spec's violation — each bound tightened by the
// design margin MoveTuneSettings::margin — so that any setting that meets
// the spec beats any that does not: NLopt's DIRECT-L (global, on
// the box of the gains, log-scaled where the lower end is positive) for
// half the budget, then Subplex (local, derivative-free; the move time
// is a step function of the settings at the output period) from the
// better of DIRECT-L's best and the current setting. The checks: the
// model with each free parameter of the fit at either end of its 95 %
// interval (tune/interval_ends.h) and, where the job fits the quasi-steady
// current loop, the estimate with the full loop at its own step
// (estimation/current_loop_check.h WithFullLoop). Then, up to three
// rounds: the two checks where the best setting breaks the spec (with its
// margin) most are added to the models it must meet (the objective becomes
// the worst over the estimate and them) and Subplex runs again from it for
// half the budget. Each profile's tuned setting and the current one are
// judged at the estimate and every check — the checks then include
// TuneSettings::samples points of the fit's joint 95 % region
// (tune/joint_region.h), which judge but do not steer the robust rounds —
// all run to
// the same end (the
// longest move's end plus `settle`); the proposal is the tuned setting
// with the lowest objective among those that meet the spec at every
// check, else the one that meets it at the most checks (then the lowest
// objective).
#ifndef TUNE_MOVE_TUNING_H_
#define TUNE_MOVE_TUNING_H_

#include <string>
#include <vector>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "tune/tune_settings.h"
#include "sim/controller.h"
#include "tune/analog_loop_tuning.h"
#include "tune/interval_ends.h"
#include "tune/klipper_shaper_rule.h"
#include "tune/move_response.h"

namespace axis {

// A figure of a setting at one model it is judged on.
struct CheckFigure {
  std::string check;  // "the estimate", "V_L at low end", "joint sample 3", …
  double value = 0.0;
};

// A controller and a move, judged at the estimate (and, for the current
// and the proposed one, over the uncertainty).
struct MoveSetting {
  // The analog loop it runs on (V/V, s): the model's, or the analog
  // tuning's proposal (TuneMove).
  double K1 = 0.0, T_p = 0.0;
  std::string profile;          // "trapezoid" or "min_jerk"
  ControllerConfig controller;  // the gains (the rest as the axis's)
  // The move with the limits it uses and its input shaper
  // (Reference::shaper; none for an unshaped move).
  Reference reference;
  // m, the largest distance between the shaped and the unshaped command
  // (MoveSmoothing, tune/move_response.h); 0 unshaped.
  double smoothing = 0.0;
  // m, the residual vibration (MoveMetrics::ringing) at the estimate and at
  // every check, in that order (Judge).
  std::vector<CheckFigure> residual_vibration;
  double speed = 1.0;           // the time scale s of the profile, in (0, 1]
  MoveMetrics metrics;          // at the estimate
  std::vector<std::string> violations;  // at the estimate
  // The search's (s): the move time plus a penalty per unit of violation,
  // the worst over the estimate and `scenarios`.
  double objective = 0.0;
  // The checks ("Delta_M at high end", "the full current loop") the robust
  // search added because the setting broke the spec there.
  std::vector<std::string> scenarios;
  int evaluations = 0;          // simulations of its search
  // "move_time", "settling_time", "following_error", "overshoot",
  // "peak_current", "ringing", in this order.
  std::vector<FigureSpread> spread;
  bool robust = false;  // every bound met at the estimate and every check
  // "<check>: <violation>" ("V_L at low end: overshoot ..."); of the joint
  // region's samples only the first that breaks a bound met at the estimate.
  std::vector<std::string> robust_violations;
  // The samples of the fit's joint 95 % region judged (tune/joint_region.h,
  // TuneSettings::samples) and those where every bound is met.
  int samples = 0, samples_met = 0;
  int checks_met = 0;  // of all the checks (ends, samples, full loop), those where it holds
  MoveResponse response;             // at the estimate
  MoveResponse band_low, band_high;  // over the estimate and the checks
};

struct MoveTuning {
  bool ran = false;
  std::string note;  // why not, or what the search could not do
  MoveSpec spec;
  double margin = 0.0;  // MoveTuneSettings::margin, as searched
  // Whether the move was tuned on the analog loop's proposal (the inner
  // loop first, as the paper's order) rather than the model's K_1, T_p.
  bool on_proposed_analog_loop = false;
  std::vector<TunedGain> gains;  // searched
  bool slow_down = true;
  // The axis's controller (the model's, else MODEL.md §5's AID 600
  // defaults) on the spec's first profile at the limits.
  MoveSetting current;
  // The shapers tried (MoveTuneSettings::shapers) and, per profile, the
  // frequency range searched or why none was ("trapezoid: 5.1-20.4 Hz, from
  // the residual vibration of its unshaped move at 10.2 Hz").
  std::vector<ShaperType> shapers;
  std::vector<std::string> shaper_notes;
  // One per profile of the spec, in its order, then one per profile and
  // shaper (profile-major) where a shaper was searched; all judged.
  std::vector<MoveSetting> tuned;
  MoveSetting proposed;            // the one chosen of `tuned` (TuneMove)
  // With tune.move.klipper: Klipper's rule (tune/klipper_shaper_rule.h) on
  // the resonance test simulated on the identified model under the
  // trapezoid's unshaped tuned gains (else the first profile's), and that
  // setting with the shaper it recommends, judged as the others but never
  // proposed.
  bool klipper_ran = false;
  std::string klipper_note;  // why it did not run, with tune.move.klipper
  ResonanceSpectrum resonance;
  KlipperShaperChoice klipper_choice;
  MoveSetting klipper;
  int simulations = 0;
  double seconds = 0.0;
};

// Tunes the controller gains and the move of tune.move on the model of
// `job` at `result`'s estimate (AtEstimate) — with the K_1 and T_p that
// `analog` proposes if it is given and ran — simulating at the first
// fitted experiment's RK4 step. The model's amplifier may be any; the controller
// is the model's (AxisConfig::controller) if it has one, else the AID 600
// defaults; the joint region's samples are tune.samples. ran is false
// with a note if tune.move is not enabled. The searches of the profiles
// (then of their shapers) and the simulations of a setting on the checks'
// models run up to job.solver.threads at once; the result is the same for
// any number of threads.
// Throws std::runtime_error if the job has no experiment or the model at
// the estimate does not simulate the current setting; never for a spec
// that cannot be met (the proposal then has the least violation).
MoveTuning TuneMove(const EstimationProblem& job, const FitResult& result,
                    const TuneSettings& tune, const AnalogLoopTuning* analog = nullptr);

// The field of `c` that TunedGain::name `name` names ("G_p", "G_i", "G_v",
// "G_ff", "alpha"; MODEL.md §5), nullptr for another name. Never throws.
double* ControllerGain(ControllerConfig* c, const std::string& name);

// The setting `s` (its K_1, T_p, controller and move) on another axis
// `axis` (e.g. the model that generated the records), simulated at `step`
// (s): the spec's
// violations there (MoveViolations), empty if it holds. Throws
// std::invalid_argument as SimulateMove.
std::vector<std::string> MoveViolationsOn(const AxisConfig& axis, double step,
                                          const MoveSetting& s, const MoveSpec& spec);

}  // namespace axis

#endif  // TUNE_MOVE_TUNING_H_
