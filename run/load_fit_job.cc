#include "run/load_fit_job.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <Eigen/Dense>

#include "common/format.h"
#include "common/statistics.h"
#include "design/design_settings.h"
#include "discovery/discovery_settings.h"
#include "discovery/frequency_response_settings.h"
#include "estimation/full_loop_refit.h"
#include "estimation/parameter_tie.h"
#include "estimation/solver_settings.h"
#include "io/csv.h"
#include "io/data_file.h"
#include "io/data_table.h"
#include "io/output_staging.h"
#include "io/settings_reader.h"
#include "report/published_reference.h"
#include "run/benchmark_settings.h"
#include "run/fit_job.h"
#include "sim/dense_decompositions.h"
#include "sim/drive_config.h"
#include "sim/auto_step.h"
#include "sim/preflight.h"
#include "tune/klipper_shaper_rule.h"

namespace axis {
namespace {

using Range = YamlMap::Range;

std::string Num(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

// The median of the steps time[k] - time[k - 1] over the `count` samples
// from `first` (count >= 2; of an even number of steps, the upper middle).
double MedianStep(const std::vector<double>& time, size_t first, size_t count) {
  std::vector<double> steps;
  steps.reserve(count - 1);
  for (size_t k = first + 1; k < first + count; ++k) steps.push_back(time[k] - time[k - 1]);
  const auto middle = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), middle, steps.end());
  return *middle;
}

// Rows of `table` with time in [start, end], as (first row, row count).
std::pair<size_t, size_t> WindowRows(const std::vector<double>& time,
                                     double start, double end) {
  size_t first = 0;
  while (first < time.size() && time[first] < start) ++first;
  size_t last = first;
  while (last < time.size() && time[last] <= end) ++last;
  return {first, last - first};
}

// A table signal from `column` of the data, restricted to the window and
// shifted so that the window starts at t = 0.
// Its times are those of the simulation, k·period: the recorded clock's
// jitter (EMPS: 3e-8 s) must not move a held sample to the next grid point.
InputSignal ColumnSignal(const DataTable& data, const std::string& column,
                         double scale, double offset, bool hold, size_t first,
                         size_t count, double period) {
  InputSignal s;
  s.kind = InputSignal::Kind::kTable;
  s.hold = hold;  // (cubic: MakeCubic on the result)
  const std::vector<double>& values = data.Column(column);
  for (size_t k = first; k < first + count; ++k) {
    s.times.push_back(static_cast<double>(k - first) * period);
    s.values.push_back(scale * values[k] + offset);
  }
  return s;
}

// The share of consecutive samples of values[first, first + count) that are
// exactly equal, and the number of changes between them.
struct Levels {
  double equal_share = 0.0;
  size_t changes = 0;
};

Levels CountLevels(const std::vector<double>& values, size_t first, size_t count) {
  Levels out;
  if (count < 2) return out;
  size_t equal = 0;
  for (size_t k = first + 1; k < first + count; ++k) {
    (values[k] == values[k - 1] ? equal : out.changes) += 1;
  }
  out.equal_share = static_cast<double>(equal) / static_cast<double>(count - 1);
  return out;
}

// A drive signal of an experiment: either a profile (`type:` key, see
// ParseInputSignal) or a column of the experiment's data file. Without an
// `interpolation` key a column that is piecewise constant (at least half of
// its consecutive samples equal, and at least one change) is held, as a DAC
// or a sampled controller holds it, and *note says so; otherwise linear.
// A sampled smooth signal changes at every sample; reading a held one
// linearly puts a ramp one sample early at every switch, which the
// discovery loop then explains with friction or sensor delays (issue 10).
InputSignal ParseDriveSignal(YamlMap& map, const DataTable& data,
                             double period, size_t first,
                             size_t count, const std::string& base_dir,
                             double duration, std::string* note) {
  if (map.Has("type")) return ParseInputSignal(map, base_dir, duration);
  const std::string column = map.String("column");
  RequireColumn(map, map.Optional("column"), map.KeyPath("column"), data, column);
  const double scale = map.Number("scale", 1.0);
  const double offset = map.Number("offset", 0.0);
  bool hold = false;
  bool cubic = false;
  if (map.Has("interpolation")) {
    const std::string mode = map.Choice("interpolation", {"linear", "hold", "cubic"}, "linear");
    hold = mode == "hold";
    cubic = mode == "cubic";
  } else {
    const Levels levels = CountLevels(data.Column(column), first, count);
    hold = levels.changes > 0 && levels.equal_share >= 0.5;
    if (hold) {
      std::ostringstream why;
      why << map.KeyPath("column") << " '" << column
          << "' read as held (piecewise constant: " << std::setprecision(3)
          << 100.0 * levels.equal_share << " % of consecutive samples equal, "
          << levels.changes << " changes); set " << map.KeyPath("interpolation")
          << ": linear to interpolate instead";
      *note = why.str();
    }
  }
  InputSignal s = ColumnSignal(data, column, scale, offset, hold, first, count, period);
  if (cubic) MakeCubicOrThrow(map, &s);
  map.Finish();
  return s;
}

// A measured channel's column: `channel: column` or `channel: {column,
// scale, offset}` (values = scale·column + offset).
struct ChannelSpec {
  std::string column;
  double scale = 1.0, offset = 0.0;
};

ChannelSpec ParseChannelSpec(YamlMap& channels, const std::string& name,
                             const DataTable& data) {
  ChannelSpec spec;
  const YAML::Node value = channels.Optional(name);
  if (value.IsScalar()) {
    spec.column = value.Scalar();
  } else {
    YamlMap m(value, channels.file(), channels.KeyPath(name) + ".");
    spec.column = m.String("column");
    spec.scale = m.Number("scale", 1.0);
    spec.offset = m.Number("offset", 0.0);
    m.Finish();
  }
  RequireColumn(channels, value, channels.KeyPath(name), data, spec.column);
  return spec;
}

// The `published:` key (report/published.h).
}  // namespace

namespace {

// The job's integration step: `fixed` (s, > 0) where simulation.step gives
// one, else each record's own from the model (sim/auto_step.h) under
// `limit`.
struct StepRule {
  double fixed = 0.0;
  double limit = 0.0;
};

// One experiment of a job (an entry of `experiments:` or `validate:`) as a
// sequence of named steps over its keys, in the order its checks run: the
// name, the data file and its window, the initial state, the sampling and
// the simulation grid, the measured and fitted channels, the drive.
class ExperimentParser {
 public:
  // `map` (the entry), `model` and `base_dir` must outlive the parser.
  ExperimentParser(YamlMap& map, const std::string& role, const AxisConfig& model,
                   const StepRule& step, const std::string& base_dir)
      : map_(map), model_(model), rule_(step), base_dir_(base_dir) {
    e_.role = role;
  }
  ExperimentParser(const ExperimentParser&) = delete;
  ExperimentParser& operator=(const ExperimentParser&) = delete;

  FitExperiment Parse();

 private:
  void ParseName();
  void ReadData();     // data:, time: (data_, time_)
  void ParseWindow();  // window: (first_, count_)
  void ParseInitialState();
  void ParseDeclaredState(const YAML::Node& init_node);
  void EstimateStateFromSamples(const YAML::Node& init_node);
  void CheckSampling();    // at least 3 samples, period, uniform steps
  void SetTimeGrid();      // e.t and the simulation options
  void ParseChannels();    // channels:
  void ParseFitted();      // fit:
  void ParseStateChoice(); // initial_state: rest or estimate
  void ParseDrive();       // input: or reference: (with controller:, injection:)
  void ParseClosedLoop();
  // A drive signal of `map` (ParseDriveSignal), its note kept.
  InputSignal DriveSignal(YamlMap& map);
  void Finish();           // unknown keys, recorded channels, the grid

  YamlMap& map_;
  const AxisConfig& model_;
  const StepRule rule_;
  double step_ = 0.0;  // s, the record's RK4 step (SetTimeGrid)
  const std::string& base_dir_;

  FitExperiment e_;
  DataTable data_;
  const std::vector<double>* time_ = nullptr;  // the time column of data_
  size_t first_ = 0;  // the window's rows
  size_t count_ = 0;
  double period_ = 0.0;  // s, the data's mean step over the window
  // initial_state: rest (default), estimate (y0, y1 fitted), or
  // {from_samples: N, degree: D}: position and velocity from the
  // least-squares polynomial of degree D (1 or 2, default 2) through the
  // first N samples of the measured x channel, extrapolated to the next
  // sample, where the experiment then starts (the EMPS benchmark's protocol:
  // "the first 20 samples may be used to initialise the state"). Degree 2
  // because a line's slope is the velocity at the window's middle, sample
  // (N−1)/2: an axis accelerating at a starts ((N+1)/2)·h·a slower than it
  // is (EMPS: 0.95 m/s², 10.5 ms, 10 mm/s, held for the ≈0.5 s time
  // constant M/B_a ≈5 mm of open-loop drift).
  std::string init_ = "rest";
  long init_samples_ = 0;
  int init_degree_ = 2;
};

FitExperiment ExperimentParser::Parse() {
  ParseName();
  ReadData();
  ParseWindow();
  ParseInitialState();
  CheckSampling();
  SetTimeGrid();
  ParseChannels();
  if (e_.role == "fit") ParseFitted();
  ParseStateChoice();
  ParseDrive();
  Finish();
  return std::move(e_);
}

void ExperimentParser::ParseName() {
  e_.name = map_.String("name");
  if (!IsOutputName(e_.name)) {
    ThrowConfigError(map_.file(), map_.Optional("name"), map_.KeyPath("name"),
                     "a name of letters, digits, '_', '-', '.' (it names "
                     "output files)",
                     "'" + e_.name + "'");
  }
}

void ExperimentParser::ReadData() {
  e_.data_path = ResolvePath(base_dir_, map_.String("data"));
  const std::string time_column = map_.String("time", "t");
  data_ = ReadDataTable(e_.data_path, time_column);
  if (!data_.HasColumn(time_column)) {
    ThrowConfigError(map_.file(), map_.node(), map_.KeyPath("time"),
                     "a time " + data_.ColumnWord() + " of " + e_.data_path,
                     data_.DescribeName(time_column));
  }
  CheckStrictlyIncreasing(data_, time_column);
  time_ = &data_.Column(time_column);
}

void ExperimentParser::ParseWindow() {
  const std::vector<double>& time = *time_;
  double start = time.front(), end = time.back();
  if (const YAML::Node w = map_.Optional("window")) {
    if (!w.IsSequence() || w.size() != 2) {
      ThrowConfigError(map_.file(), w, map_.KeyPath("window"),
                       "[start, end] in seconds", Describe(w));
    }
    start = map_.NumberFrom(w[0], map_.KeyPath("window"), Range::kAny);
    end = map_.NumberFrom(w[1], map_.KeyPath("window"), Range::kAny);
    if (!(end > start)) {
      ThrowConfigError(map_.file(), w, map_.KeyPath("window"),
                       "start < end", Num(start) + " and " + Num(end));
    }
  }
  std::tie(first_, count_) = WindowRows(time, start, end);
}

void ExperimentParser::ParseInitialState() {
  const YAML::Node init_node = map_.Optional("initial_state");
  bool declared_state = false;
  if (init_node && init_node.IsMap()) {
    for (const auto& entry : init_node) {
      const std::string key = entry.first.as<std::string>();
      declared_state = declared_state || (key.size() == 2 && key[0] == 'y');
    }
  }
  if (declared_state) {
    ParseDeclaredState(init_node);
  } else if (init_node && init_node.IsMap()) {
    EstimateStateFromSamples(init_node);
  }
}

void ExperimentParser::ParseDeclaredState(const YAML::Node& init_node) {
  // A declared state y0..y6 (MODEL.md §1), as in an experiment file: the
  // record starts from it (a record taken in motion, its state known).
  YamlMap spec(init_node, map_.file(), map_.KeyPath("initial_state."));
  for (int k = 0; k < kNumStates; ++k) {
    e_.initial_state[k] = spec.Number("y" + std::to_string(k), 0.0);
  }
  spec.Finish();
  e_.initial_state = ConsistentInitialState(model_, e_.initial_state);
  init_ = "declared";
}

void ExperimentParser::EstimateStateFromSamples(const YAML::Node& init_node) {
  YamlMap spec(init_node, map_.file(), map_.KeyPath("initial_state."));
  init_samples_ = spec.Integer("from_samples", 0, 2, 1000000);
  if (!spec.Has("from_samples")) {
    ThrowConfigError(map_.file(), init_node, map_.KeyPath("initial_state.from_samples"),
                     "a number of samples (more than the polynomial's degree, 2 by "
                     "default), or the states y0..y6",
                     "none");
  }
  init_degree_ = static_cast<int>(spec.Integer("degree", 2, 1, 2));
  if (init_samples_ <= init_degree_) {
    ThrowConfigError(map_.file(), init_node, map_.KeyPath("initial_state.from_samples"),
                     "more samples than the degree " + std::to_string(init_degree_) +
                         " (a polynomial through them)",
                     std::to_string(init_samples_));
  }
  spec.Finish();
  init_ = "from_samples";
  YAML::Node channels_node = map_.Required("channels");
  YamlMap channels(channels_node, map_.file(), map_.KeyPath("channels."));
  if (!channels.Has("x")) {
    ThrowConfigError(map_.file(), init_node, map_.KeyPath("initial_state"),
                     "a measured position channel 'x' under 'channels'",
                     "none");
  }
  if (count_ < static_cast<size_t>(init_samples_) + 3) {
    ThrowConfigError(map_.file(), init_node, map_.KeyPath("initial_state.from_samples"),
                     "at most the window's " + std::to_string(count_) +
                         " samples minus 3",
                     std::to_string(init_samples_));
  }
  const ChannelSpec x = ParseChannelSpec(channels, "x", data_);
  const std::vector<double>& raw = data_.Column(x.column);
  const std::vector<double>& time = *time_;
  // Least squares x(t) = c0 + c1·t (+ c2·t²), t from the next sample:
  // c0 is the position and c1 the velocity there (Eigen's QR).
  const double t0 = time[first_ + init_samples_];
  Eigen::MatrixXd basis(init_samples_, init_degree_ + 1);
  Eigen::VectorXd xs(init_samples_);
  for (long k = 0; k < init_samples_; ++k) {
    const double tk = time[first_ + k] - t0;
    for (int d = 0; d <= init_degree_; ++d) basis(k, d) = std::pow(tk, d);
    xs(k) = x.scale * raw[first_ + k] + x.offset;
  }
  const Eigen::VectorXd c = QrLeastSquares(basis, xs);
  const double intercept = c(0);
  const double slope = c(1);
  e_.initial_state[0] = intercept;
  e_.initial_state[1] = slope;
  // The motor with the load, in either coupling (in rigid coupling
  // ConsistentInitialState's y2, y3; a motor encoder reads y2).
  e_.initial_state[2] = intercept / model_.params.r_g;
  e_.initial_state[3] = slope / model_.params.r_g;
  first_ += init_samples_;
  count_ -= init_samples_;
}

void ExperimentParser::CheckSampling() {
  const std::vector<double>& time = *time_;
  if (count_ < 3) {
    ThrowConfigError(map_.file(), map_.node(), map_.KeyPath("window"),
                     "at least 3 samples of " + e_.data_path + " in the window",
                     std::to_string(count_));
  }
  e_.t_offset = time[first_];
  period_ = (time[first_ + count_ - 1] - time[first_]) / (count_ - 1);
  // A servo axis's dynamics (the 5 ms controller, the gear resonance, the
  // preamp's T_p) are milliseconds: a record sampled slower than 50 Hz sees
  // none of them, and is most likely one whose time column is not in
  // seconds (a 1 kHz record in ms reads as 1 s per sample, and its fit as
  // a horizon of minutes).
  if (period_ > kMaxSamplePeriod) {
    throw std::invalid_argument(
        data_.RowLocation(first_ + 1) + ": expected time in seconds sampled at 50 Hz or faster " +
        "(a sample period of at most " + Num(kMaxSamplePeriod) + " s), got a period of " +
        Num(period_) + " (is the time column in ms? convert it to s)");
  }
  // Each step against the median step, not the mean: one dropped sample
  // skews the mean, and every step then looked wrong but the gap's.
  const double median_step = MedianStep(time, first_, count_);
  for (size_t k = first_ + 1; k < first_ + count_; ++k) {
    const double dt = time[k] - time[k - 1];
    if (std::abs(dt - median_step) > 1e-3 * median_step) {
      throw std::invalid_argument(
          data_.RowLocation(k) + ": expected uniform sampling (the median step " +
          Num(median_step) + " s within 0.1 %), got a step of " + Num(dt) + " s from " +
          Num(time[k - 1]) + " to " + Num(time[k]) + " s" +
          (dt > 1.5 * median_step ? " (a gap: a dropped sample?)" : ""));
    }
  }
}

void ExperimentParser::SetTimeGrid() {
  const std::vector<double>& time = *time_;
  for (size_t k = first_; k < first_ + count_; ++k) e_.t.push_back(time[k] - e_.t_offset);
  // The simulation samples on the data grid: the period rounded to whole
  // integration steps (the EMPS clock jitters by 3e-8 s).
  if (rule_.fixed > 0.0) {
    step_ = rule_.fixed;
  } else {
    try {
      step_ = AutoStep(rule_.limit, period_,
                       model_.has_controller ? model_.controller.T_s : 0.0);
    } catch (const std::invalid_argument& err) {
      throw std::invalid_argument(std::string("key 'simulation.step' (none set): ") + err.what());
    }
  }
  e_.options.step = step_;
  e_.options.output_period = std::max(1L, std::lround(period_ / step_)) * step_;
  if (std::abs(e_.options.output_period - period_) > 1e-3 * period_) {
    ThrowConfigError(map_.file(), map_.node(), "simulation.step",
                     "a step that divides the data period " + Num(period_) + " s",
                     Num(step_) + " s");
  }
  e_.options.duration = e_.options.output_period * (count_ - 1);
  for (size_t k = 0; k < e_.t.size(); ++k) e_.t[k] = k * e_.options.output_period;
}

void ExperimentParser::ParseChannels() {
  // Measured channels: channel: column, or channel: {column, scale, offset}.
  YamlMap channels(map_.Required("channels"), map_.file(), map_.KeyPath("channels."));
  for (const auto& entry : channels.node()) {
    const std::string name = entry.first.Scalar();
    const Channel c = ChannelOrThrow(name, channels, entry.first,
                                     channels.KeyPath(name));
    const ChannelSpec spec = ParseChannelSpec(channels, name, data_);
    const std::vector<double>& raw = data_.Column(spec.column);
    std::vector<double> values;
    for (size_t k = first_; k < first_ + count_; ++k) {
      values.push_back(spec.scale * raw[k] + spec.offset);
    }
    e_.measured_channels.push_back(c);
    e_.measured.push_back(std::move(values));
  }
  channels.Finish();
}

void ExperimentParser::ParseFitted() {
  YamlMap fit(map_.Required("fit"), map_.file(), map_.KeyPath("fit."));
  for (const auto& entry : fit.node()) {
    const std::string name = entry.first.Scalar();
    const Channel c = ChannelOrThrow(name, fit, entry.first, fit.KeyPath(name));
    if (std::find(e_.measured_channels.begin(), e_.measured_channels.end(), c) ==
        e_.measured_channels.end()) {
      ThrowConfigError(map_.file(), entry.first, fit.KeyPath(name),
                       "a channel listed under 'channels' (measured)",
                       "'" + name + "'");
    }
    e_.fitted.push_back({c, fit.Number(name, Range::kFinitePositive)});
  }
  fit.Finish();
  if (e_.fitted.empty()) {
    ThrowConfigError(map_.file(), map_.Optional("fit"), map_.KeyPath("fit"),
                     "at least one channel: sigma", "none");
  }
}

void ExperimentParser::ParseStateChoice() {
  if (init_ != "from_samples" && init_ != "declared") {
    init_ = map_.Choice("initial_state", {"rest", "estimate"}, "rest");
  }
  e_.estimate_initial_state = init_ == "estimate";
  // A record taken in motion: an inductive drive's current was running
  // before it began (sim/simulate.h SimulationOptions::settled_current).
  e_.options.settled_current = init_ == "from_samples" || init_ == "estimate";
  if (e_.estimate_initial_state && e_.role != "fit") {
    ThrowConfigError(map_.file(), map_.Optional("initial_state"), map_.KeyPath("initial_state"),
                     "rest or {from_samples: N} in a validation experiment (only "
                     "fitted experiments estimate their state)",
                     "estimate");
  }
}

InputSignal ExperimentParser::DriveSignal(YamlMap& map) {
  std::string note;
  InputSignal s = ParseDriveSignal(map, data_, e_.options.output_period, first_, count_,
                                   base_dir_, e_.options.duration, &note);
  if (!note.empty()) e_.input_notes.push_back(note);
  return s;
}

void ExperimentParser::ParseDrive() {
  // What drives the axis: an input (open loop) or a reference (closed loop).
  const bool has_input = map_.Has("input");
  const bool has_reference = map_.Has("reference");
  if (has_input == has_reference) {
    ThrowConfigError(map_.file(), map_.node(), map_.KeyPath("input"),
                     "exactly one of 'input' (open loop) or 'reference' "
                     "(closed loop)",
                     has_input ? "both" : "neither");
  }
  if (has_input) {
    YamlMap input(map_.Required("input"), map_.file(), map_.KeyPath("input."));
    e_.drive.input = DriveSignal(input);
  } else {
    ParseClosedLoop();
  }
  for (const char* key : {"controller", "supply"}) {
    if (has_input && map_.Has(key)) {
      ThrowConfigError(map_.file(), map_.Optional(key), map_.KeyPath(key),
                       std::string("a ") + key + " only with 'reference' (closed loop)",
                       std::string("a ") + key + " in an open-loop experiment ('input')");
    }
  }
  // MODEL.md §4 drive enable: on where the signal is ≥ 0.5.
  if (const YAML::Node node = map_.Optional("enable")) {
    CheckDriveEnable(model_.structure, map_, node, "enable");
    YamlMap enable(node, map_.file(), map_.KeyPath("enable."));
    e_.drive.enable = DriveSignal(enable);
    e_.drive.has_enable = true;
  }
}

void ExperimentParser::ParseClosedLoop() {
  e_.drive.closed_loop = true;
  e_.drive.controller = model_.controller;
  if (const YAML::Node node = map_.Optional("controller")) {
    YamlMap c(node, map_.file(), map_.KeyPath("controller."));
    e_.drive.controller = ParseController(c, model_.controller);
  } else if (!model_.has_controller) {
    ThrowConfigError(map_.file(), map_.node(), map_.KeyPath("controller"),
                     "a controller here or in the model config", "none");
  }
  YamlMap ref(map_.Required("reference"), map_.file(), map_.KeyPath("reference."));
  if (ref.Has("type")) {
    e_.drive.reference = ParseReference(ref, base_dir_, 0.0);
  } else {
    e_.drive.reference.kind = Reference::Kind::kTable;
    e_.drive.reference.table = DriveSignal(ref);
  }
  if (const YAML::Node node = map_.Optional("injection")) {
    YamlMap inj(node, map_.file(), map_.KeyPath("injection."));
    e_.drive.injection = DriveSignal(inj);
    e_.drive.has_injection = true;
  }
  if (map_.Has("supply")) {
    e_.drive.supply = ParseSupply(map_, [this](YamlMap& m) { return DriveSignal(m); });
    e_.drive.has_supply = true;
  }
  CheckFirmwareDrive(model_.structure, e_.drive.controller, e_.drive.has_supply, map_);
}

void ExperimentParser::Finish() {
  map_.Finish();
  // Record every measured channel and the input.
  e_.options.channels = e_.measured_channels;
  if (std::find(e_.options.channels.begin(), e_.options.channels.end(),
                Channel::kU) == e_.options.channels.end()) {
    e_.options.channels.push_back(Channel::kU);
  }
  try {
    MakeGrid(e_.options, e_.drive);
  } catch (const std::invalid_argument& err) {
    throw std::invalid_argument(map_.file() + ": experiment '" + e_.name +
                                "': " + err.what());
  }
}

std::vector<FitExperiment> ParseExperimentList(YamlMap& root,
                                               const std::string& key,
                                               const std::string& role,
                                               const AxisConfig& model,
                                               const StepRule& step,
                                               const std::string& base_dir,
                                               bool required,
                                               std::map<std::string, std::string>* names) {
  std::vector<FitExperiment> out;
  const YAML::Node list = required ? root.Required(key) : root.Optional(key);
  if (!list) return out;
  if (!list.IsSequence() || (required && list.size() == 0)) {
    ThrowConfigError(root.file(), list, key,
                     required ? "a non-empty list of experiments" : "a list of experiments",
                     list.IsSequence() ? "an empty list" : Describe(list));
  }
  for (size_t k = 0; k < list.size(); ++k) {
    YamlMap map(list[k], root.file(), key + "[" + std::to_string(k) + "].");
    out.push_back(ExperimentParser(map, role, model, step, base_dir).Parse());
    // Names are unique over experiments: and validate: together: they name
    // the output files, and reports find a run by its name.
    const auto [first, inserted] = names->emplace(out.back().name, map.KeyPath("name"));
    if (!inserted) {
      ThrowConfigError(root.file(), list[k]["name"], map.KeyPath("name"),
                       "a name no other experiment of the job has", "'" + out.back().name +
                       "', the name of " + first->second);
    }
  }
  return out;
}

void CheckFreeParameter(const FreeParameter& f, const std::string& where) {
  if (!(f.lower < f.upper)) {
    throw std::invalid_argument(where + ": expected lower < upper, got lower " +
                                Num(f.lower) + " and upper " + Num(f.upper));
  }
  if (!(f.initial >= f.lower && f.initial <= f.upper)) {
    throw std::invalid_argument(where + ": expected the initial value within [" +
                                Num(f.lower) + ", " + Num(f.upper) + "], got " +
                                Num(f.initial));
  }
}

// A job's keys as a sequence of named steps, one per key group, in the order
// their checks run: the model, the simulation settings, the free parameters
// and their ties (before the experiments, so that a bad name is reported
// without reading data), the step, the solver, uncertainty, discovery, design and output settings, the
// experiments, the fit's memory, the published reference and the benchmark.
class FitJobParser {
 public:
  // `path` and `dir` must outlive the parser.
  FitJobParser(const YAML::Node& node, const std::string& path, const std::string& dir)
      : path_(path), dir_(dir), root_(node, path, "") {
    job_.problem.path = path;
  }
  FitJobParser(const FitJobParser&) = delete;
  FitJobParser& operator=(const FitJobParser&) = delete;

  FitJob Parse();

 private:
  void ParseModel();       // title, description, model, overrides, controller
  void ParseSimulation();  // simulation: (step_)
  // After the ties: simulation.step's RK4 check, or without it the limit
  // of sim/auto_step.h.
  void ChooseStep();
  void ParseFree();
  void ParseTies();  // tie: after free:, before the step and the experiments
  FreeParameter ParseFreeParameter(YamlMap& free, const YAML::Node& key,
                                   const std::string& name);
  void ParseSolver();  // solver:, uncertainty:
  void CheckKlipperSampleRate(const YAML::Node& tune);  // tune.move.klipper vs T_s
  void ParseOutput();
  void ParseExperiments();  // experiments:, validate:
  void CheckFitMemory();

  const std::string& path_;
  const std::string& dir_;
  FitJob job_;
  YamlMap root_;
  StepRule step_;  // simulation.step, or the model's own (ChooseStep)
};

FitJob FitJobParser::Parse() {
  ParseModel();
  ParseSimulation();
  ParseFree();
  ParseTies();
  ChooseStep();
  ParseSolver();
  if (const YAML::Node node = root_.Optional("discover")) {
    ReadDiscoverySettings(node, path_, &job_.discover);
    // The declared model of a discovery job is expected to miss an effect
    // (estimation/estimation_problem.h exploratory).
    job_.problem.exploratory = true;
  }
  if (const YAML::Node node = root_.Optional("design")) {
    ReadDesignSettings(node, path_, &job_.design);
  }
  if (const YAML::Node node = root_.Optional("tune")) {
    ParseTuneSettings(node, path_, &job_.tune);
    CheckKlipperSampleRate(node);
  }
  if (const YAML::Node node = root_.Optional("frequency_response")) {
    ReadFrequencyResponseSettings(node, path_, &job_.frequency_response);
  }
  ParseOutput();
  ParseExperiments();
  CheckFitMemory();
  if (const YAML::Node node = root_.Optional("published")) {
    ReadPublishedReference(node, path_, job_.problem, &job_.published);
  }
  if (const YAML::Node node = root_.Optional("benchmark")) {
    ParseBenchmark(node, path_, job_.problem.experiments, job_.problem.validate, &job_.benchmark,
                   job_.problem.model.structure.motion == Motion::kRotary);
  }
  root_.Finish();
  return std::move(job_);
}

// Klipper's resonance test is read by the position controller every T_s:
// its max_freq above KlipperHighestFrequency (tune/klipper_shaper_rule.h)
// is refused here rather than after the fit.
void FitJobParser::CheckKlipperSampleRate(const YAML::Node& tune) {
  const KlipperRuleSettings& k = job_.tune.move.klipper;
  const AxisConfig& m = job_.problem.model;
  const double limit =
      KlipperHighestFrequency(m.has_controller ? m.controller : ControllerConfig{});
  if (!k.enabled || k.max_freq <= limit) return;
  const YAML::Node move = tune.IsMap() ? tune["move"] : YAML::Node();
  const YAML::Node at = move && move.IsMap() && move["klipper"] ? move["klipper"] : tune;
  ThrowConfigError(path_, at, "tune.move.klipper.max_freq",
                   "at most a quarter of the controller's sample rate (" + FormatNumber(limit) +
                       " Hz: the sweep is read every T_s)",
                   FormatNumber(k.max_freq) + " Hz");
}

void FitJobParser::ParseModel() {
  job_.title = root_.String("title", path_);
  root_.String("description", "");
  job_.problem.model = LoadAxisConfig(ResolvePath(dir_, root_.String("model")));
  ParseModelOverrides(root_, &job_.problem.model);
  if (const YAML::Node node = root_.Optional("controller")) {
    YamlMap map(node, path_, "controller.");
    job_.problem.model.controller = ParseController(map, job_.problem.model.controller);
    job_.problem.model.has_controller = true;
  }
}

void FitJobParser::ParseSimulation() {
  if (const YAML::Node node = root_.Optional("simulation")) {
    YamlMap map(node, path_, "simulation.");
    if (map.Has("step")) step_.fixed = map.Number("step", Range::kFinitePositive);
    ReadSettings(&map, &job_.full_loop);
    map.Finish();
  }
}

void FitJobParser::ChooseStep() {
  if (step_.fixed > 0.0) {
    const YAML::Node sim = root_.node()["simulation"];
    const YAML::Node node = sim && sim.IsMap() ? sim["step"] : YAML::Node();
    CheckRk4Step(job_.problem.model.structure, job_.problem.model.params, step_.fixed,
                 node ? path_ + ":" + std::to_string(node.Mark().line + 1) : path_,
                 "simulation.step");
    return;
  }
  const std::vector<ParameterRange> ranges = FreeParameterRanges(job_.problem);
  try {
    step_.limit = AutoStepLimit(job_.problem.model.structure, job_.problem.model.params, ranges);
  } catch (const std::invalid_argument& err) {
    throw std::invalid_argument(path_ + ": key 'simulation.step' (none set): " + err.what());
  }
  job_.step_note = AutoStepNote(step_.limit);
}

void FitJobParser::ParseFree() {
  YamlMap free(root_.Required("free"), path_, "free.");
  for (const auto& entry : free.node()) {
    const std::string name = entry.first.Scalar();
    job_.problem.free.push_back(ParseFreeParameter(free, entry.first, name));
  }
  free.Finish();
  if (job_.problem.free.empty()) {
    ThrowConfigError(path_, free.node(), "free", "at least one free parameter",
                     "none");
  }
}

// `tie: {K_e: K_tau}`: each key a model parameter that is not free, taking
// the value of the parameter it names (estimation/parameter_tie.h); no
// chains (a source that is itself tied) and no parameter tied twice. The
// job's model takes the tied values now, so that the step (ChooseStep) and
// the experiments see them.
void FitJobParser::ParseTies() {
  const YAML::Node node = root_.Optional("tie");
  if (!node) return;
  YamlMap ties(node, path_, "tie.");
  AxisParams<double>& params = job_.problem.model.params;
  const auto is_free = [&](const std::string& name) {
    for (const FreeParameter& f : job_.problem.free) {
      if (f.name == name) return true;
    }
    return false;
  };
  for (const auto& entry : ties.node()) {
    const std::string name = entry.first.Scalar();
    const std::string key = "tie." + name;
    const std::string source = ties.String(name);
    if (FindParam(&params, name) == nullptr || name.find('.') != std::string::npos) {
      ThrowConfigError(path_, entry.first, key, "a parameter name of the model (MODEL.md)",
                       "'" + name + "'");
    }
    if (FindParam(&params, source) == nullptr || source.find('.') != std::string::npos) {
      ThrowConfigError(path_, entry.second, key,
                       "the name of the model parameter " + name + " takes its value from",
                       "'" + source + "'");
    }
    if (source == name) {
      ThrowConfigError(path_, entry.second, key, "another parameter than " + name,
                       "'" + source + "'");
    }
    if (is_free(name)) {
      ThrowConfigError(path_, entry.first, key,
                       "a parameter that is not free (a tied one follows " + source + ")",
                       name + " under 'free'");
    }
    for (const ParameterTie& tie : job_.problem.ties) {
      if (tie.parameter == source || tie.source == name) {
        ThrowConfigError(path_, entry.first, key,
                         "no chain of ties (tie each parameter to an untied one)",
                         tie.parameter + " tied to " + tie.source);
      }
    }
    job_.problem.ties.push_back({name, source});
  }
  ties.Finish();
  ApplyTies(TieIndices(job_.problem.ties), &params);
}

// The entry `name` (its key `key`) of `free`.
FreeParameter FitJobParser::ParseFreeParameter(YamlMap& free, const YAML::Node& key,
                                               const std::string& name) {
  double* field = FindParam(&job_.problem.model.params, name);
  if (field == nullptr) {
    ThrowConfigError(path_, key, "free." + name,
                     "a parameter name of the model (MODEL.md sections 2 "
                     "and 7, e.g. V_L, B_a, b_g, k_g, T_p)",
                     "'" + name + "'");
  }
  YamlMap spec(free.Optional(name), path_, "free." + name + ".");
  // The values a free parameter takes lie in its range, as a value of
  // set: must (M > 0, B_a >= 0, ...), and are finite, V_L's too: the
  // solver needs finite bounds.
  const Range range = ParamRange(name) == Range::kPositiveOrInfinite ? Range::kPositive
                                                                      : ParamRange(name);
  const auto in_range = [&](const std::string& key, double x) {
    if (!InRange(x, range)) {
      ThrowConfigError(path_, spec.Optional(key), spec.KeyPath(key),
                       std::string(RangeText(range)) + " (the range of " + name + ")",
                       Describe(spec.Optional(key)));
    }
    return x;
  };
  FreeParameter f;
  f.name = name;
  f.unit = ParamUnit(name, job_.problem.model.structure.motion);
  f.initial = spec.Has("initial") ? in_range("initial", spec.Number("initial")) : *field;
  f.lower = in_range("lower", spec.Number("lower"));
  f.upper = in_range("upper", spec.Number("upper"));
  f.scale = spec.Number("scale", 1.0, Range::kFinitePositive);
  f.log = f.lower > 0.0;
  spec.Finish();
  const int line = key.Mark().line + 1;
  CheckFreeParameter(f, path_ + (line > 0 ? ":" + std::to_string(line) : "") +
                            ": key 'free." + name + "'");
  return f;
}

void FitJobParser::ParseSolver() {
  if (const YAML::Node node = root_.Optional("solver")) {
    YamlMap map(node, path_, "solver.");
    ReadSolverSettings(&map, &job_.problem.solver);
  }
  if (const YAML::Node node = root_.Optional("uncertainty")) {
    YamlMap map(node, path_, "uncertainty.");
    ReadUncertaintySettings(&map, &job_.problem.uncertainty);
  }
}

void FitJobParser::ParseOutput() {
  if (const YAML::Node node = root_.Optional("output")) {
    YamlMap map(node, path_, "output.");
    job_.out_dir = OutputDirectory(&map, dir_);
    map.Finish();
  }
}

void FitJobParser::ParseExperiments() {
  std::map<std::string, std::string> names;  // experiment name -> its key
  job_.problem.experiments = ParseExperimentList(root_, "experiments", "fit", job_.problem.model,
                                         step_, dir_, true, &names);
  job_.problem.validate = ParseExperimentList(root_, "validate", "validate", job_.problem.model,
                                      step_, dir_, false, &names);
}

void FitJobParser::CheckFitMemory() {
  // Per fitted experiment, a Jacobian evaluation holds the simulated
  // channels and the residuals as Jets of 1 + |θ| doubles, and Ceres the
  // dense Jacobian (residuals × |θ|, twice for the QR factorisation).
  const double theta = static_cast<double>(job_.problem.free.size() + EstimatedStateCount(job_.problem));
  double bytes = 0.0;
  for (const FitExperiment& e : job_.problem.experiments) {
    const double samples = static_cast<double>(e.t.size());
    bytes += 8.0 * samples *
             ((e.measured_channels.size() + e.fitted.size()) * (1.0 + theta) +
              2.0 * e.fitted.size() * theta);
  }
  CheckMemory(bytes, path_, "the fit",
              "fit a shorter 'window' of the experiments or resample the data");
}

}  // namespace

FitJob ParseFitJob(const YAML::Node& node, const std::string& path,
                   const std::string& dir) {
  return FitJobParser(node, path, dir).Parse();
}

// The quick form's σ at least this fraction of the signal's standard
// deviation (MakeQuickJob).
constexpr double kQuickSigmaFloor = 1e-4;

FitJob MakeQuickJob(const std::string& model_path, const std::string& data_path,
                    const std::string& input_column,
                    const std::vector<std::string>& fit_channels,
                    const std::vector<std::string>& free_names) {
  // Build the equivalent job YAML and load it through the strict loader, so
  // the quick form has exactly the checks of a job file.
  YAML::Node job;
  job["title"] = "fit-params quick form: " + data_path;
  job["model"] = model_path;
  const DataTable data = ReadDataTable(data_path, "t");
  YAML::Node experiment;
  experiment["name"] = "data";
  experiment["data"] = data_path;
  YAML::Node channels(YAML::NodeType::Map);
  for (const std::string& name : data.names) {
    const auto c = ParseChannel(name);
    if (c && *c != Channel::kT) channels[name] = name;
  }
  experiment["channels"] = channels;
  experiment["input"]["column"] = input_column;
  std::vector<std::string> sigma_notes;
  for (const std::string& name : fit_channels) {
    if (!data.HasColumn(name)) {
      throw std::invalid_argument("--fit: expected " + data.ColumnExpectation() +
                                  ", got " + data.DescribeName(name));
    }
    // σ: the noise on the channel, from its second differences; where they
    // are all 0 (a noise-free or linear record), the signal's spread (1 if
    // it is constant), so that the channels are weighted alike.
    // A noise-free record (synthetic) has second differences at rounding
    // or curvature level: σ is floored at kQuickSigmaFloor of the signal's
    // spread (80 dB), so that the channels' weights stay comparable.
    const std::vector<double>& y = data.Column(name);
    double mean = 0.0, var = 0.0;
    for (double v : y) mean += v / y.size();
    for (double v : y) var += (v - mean) * (v - mean) / y.size();
    const double spread = std::sqrt(var);
    double sigma = DifferenceNoiseSd(y);
    std::string how = "estimated from the record's second differences";
    if (!(sigma > 0.0) && !(spread > 0.0)) {
      sigma = 1.0;
      how = "1 (the channel is constant)";
    } else if (!(sigma >= kQuickSigmaFloor * spread)) {
      sigma = kQuickSigmaFloor * spread;
      how = "1e-4 of the signal's standard deviation (the record is nearly noise-free)";
    }
    experiment["fit"][name] = sigma;
    sigma_notes.push_back("fitted channel " + name + ": sigma " + Num(sigma) + ", " + how +
                          " (no job to declare it)");
  }
  job["experiments"].push_back(experiment);
  AxisConfig model = LoadAxisConfig(model_path);
  for (const std::string& name : free_names) {
    double* field = FindParam(&model.params, name);
    if (field == nullptr) {
      throw std::invalid_argument("--free: expected a parameter name of the "
                                  "model, got '" + name + "'");
    }
    const double v = *field;
    if (!std::isfinite(v)) {
      throw std::invalid_argument("--free " + name + ": expected a parameter with a finite "
                                  "value in " + model_path + " (the bounds are value/10 and "
                                  "value*10), got " + Num(v));
    }
    YAML::Node spec;
    spec["initial"] = v;
    // A zero's bounds [-1, 1] are clipped to the parameter's range (F_s >= 0: [0, 1]).
    const double lower = v > 0 ? v / 10 : (v < 0 ? v * 10 : -1.0);
    spec["lower"] = ParamRange(name) == YamlMap::Range::kNonNegative ? std::max(lower, 0.0) : lower;
    spec["upper"] = v > 0 ? v * 10 : (v < 0 ? v / 10 : 1.0);
    job["free"][name] = spec;
  }
  FitJob parsed = ParseFitJob(job, "(command line)", ".");
  for (std::string& note : sigma_notes) {
    parsed.problem.experiments[0].input_notes.push_back(std::move(note));
  }
  return parsed;
}

FitJob LoadFitJob(const std::string& path) {
  return ParseFitJob(LoadYamlFile(path), path, DirectoryOf(path));
}

}  // namespace axis
