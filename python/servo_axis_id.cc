// The Python module servo_axis_id (issue 13): simulate(), load_job(),
// fit() and to_yaml() over the sim and fit libraries. Every result is
// copied into Python objects (NumPy arrays for traces); experiments and
// jobs come from files or from dicts that go through the same strict
// loaders (python/yaml_from_python.h). std::invalid_argument becomes
// ValueError with the loaders' "<file>:<line>: key '<path>': expected …,
// got …" message, std::runtime_error becomes RuntimeError (pybind11's
// standard translation).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glog/logging.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "common/allocator.h"
#include "io/output_staging.h"
#include "common/progress.h"
#include "discovery/discovery.h"
#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "python/progress_stream.h"
#include "python/yaml_from_python.h"
#include "report/published.h"
#include "report/report.h"
#include "run/job_run.h"
#include "run/write_job_run.h"
#include "sim/channels.h"
#include "sim/config.h"
#include "sim/experiment.h"
#include "io/yaml_util.h"

namespace py = pybind11;

namespace axis::python {
namespace {

// What a dict document is called in messages (the "file" of file:line:key;
// the line is that of to_yaml(dict)).
constexpr const char* kExperimentDict = "<experiment dict>";
constexpr const char* kJobDict = "<job dict>";

py::array_t<double> ToArray(const std::vector<double>& values) {
  py::array_t<double> array(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), array.mutable_data());
  return array;
}

bool IsMapping(py::handle value) {
  return py::isinstance<py::dict>(value) ||
         py::isinstance(value, py::module_::import("collections.abc").attr("Mapping"));
}

// The type name and a short repr of `value`, as messages quote it: "str 'heavy'".
std::string Quoted(py::handle value) {
  std::string text = py::repr(value).cast<std::string>();
  if (text.size() > 60) text = text.substr(0, 60) + "...";
  return std::string(py::str(py::type::of(value).attr("__name__"))) + " " + text;
}

// os.fspath(value) for a str or os.PathLike, else TypeError naming `what`
// (the expectation "a path (str or os.PathLike)" + `or_else`).
std::string PathOf(py::handle value, const std::string& what,
                   const std::string& or_else = " or a dict") {
  if (py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__")) {
    return py::module_::import("os").attr("fspath")(value).cast<std::string>();
  }
  throw py::type_error(what + ": expected a path (str or os.PathLike)" + or_else + ", got " +
                       std::string(py::str(py::type::of(value).attr("__name__"))));
}

// An argument that must be True or False (or a NumPy bool), else TypeError
// "<name>: expected True or False, got <type> <repr>" (pybind11's own
// error listed the signature and took None for False).
bool BoolArgument(py::handle value, const char* name) {
  if (py::isinstance<py::bool_>(value) ||
      py::isinstance(value, py::module_::import("numpy").attr("bool_"))) {
    return py::cast<bool>(py::bool_(py::reinterpret_borrow<py::object>(value)));
  }
  throw py::type_error(std::string(name) + ": expected True or False, got " + Quoted(value));
}

// simulate(seed=...): None (the experiment's seed) or an integer in
// 0..kMaxExperimentSeed, the range of simulate-axis --seed. TypeError for a
// non-integer (a bool or a float too), ValueError out of range.
std::optional<std::uint64_t> SeedArgument(py::handle value) {
  if (value.is_none()) return std::nullopt;
  const std::string rule = "an integer in 0.." + std::to_string(kMaxExperimentSeed) +
                           " (the range of the experiment's seed key)";
  if (py::isinstance<py::bool_>(value) || !PyIndex_Check(value.ptr())) {
    throw py::type_error("seed: expected None or " + rule + ", got " + Quoted(value));
  }
  const py::int_ seed = py::module_::import("operator").attr("index")(value);
  if (seed < py::int_(0) || seed > py::int_(kMaxExperimentSeed)) {
    throw py::value_error("seed: expected " + rule + ", got " + py::repr(seed).cast<std::string>());
  }
  return seed.cast<std::uint64_t>();
}

// simulate(set=...): applies a dict MODEL.md parameter name -> number to
// `model` as simulate-axis --set does (SetParam, then ValidateAxisConfig),
// the messages naming "set['<name>']". TypeError if `set` is not a
// mapping; ValueError for a key that is not a str or not a parameter, or a
// value that is not a real number (a bool or a str neither) or is out of
// the parameter's range.
void ApplySetDict(py::handle set, AxisConfig* model) {
  if (set.is_none()) return;
  if (!IsMapping(set)) {
    throw py::type_error("set: expected None or a dict parameter name -> number, got " +
                         Quoted(set));
  }
  for (const py::handle item : set.attr("items")()) {
    const py::tuple pair = py::reinterpret_borrow<py::tuple>(item);
    if (!py::isinstance<py::str>(pair[0])) {
      throw py::value_error("set: expected str keys (MODEL.md parameter names), got " +
                            Quoted(pair[0]));
    }
    const std::string where = "set['" + pair[0].cast<std::string>() + "']";
    const py::handle value = pair[1];
    const bool number = !py::isinstance<py::bool_>(value) && !py::isinstance<py::str>(value) &&
                        !py::isinstance<py::bytes>(value) &&
                        (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value) ||
                         py::hasattr(value, "__float__"));
    double x = 0.0;
    if (number) x = py::float_(py::reinterpret_borrow<py::object>(value)).cast<double>();
    if (!number || std::isnan(x)) {
      throw py::value_error(where + ": expected a number (the parameter's value in SI units), got " +
                            Quoted(value));
    }
    SetParam(model, pair[0].cast<std::string>(), x, where);
    ValidateAxisConfig(*model, where);
  }
}

// The folder relative paths of a dict document resolve against: base_dir,
// default the current directory. A file's relative paths resolve against
// its own folder, so base_dir with a path is refused.
std::string BaseDir(py::handle base_dir, bool is_dict) {
  if (base_dir.is_none()) return ".";
  if (!is_dict) {
    throw std::invalid_argument(
        "base_dir: expected no base_dir with a file path (its relative paths "
        "resolve against the file's folder), got '" +
        PathOf(base_dir, "base_dir", " or None") + "'");
  }
  return PathOf(base_dir, "base_dir", " or None");
}

// A parsed dict document (ParseYamlText: the same duplicate-key and syntax
// checks as a file).
YAML::Node ParseDict(py::handle dict, const char* name) {
  return ParseYamlText(ToYamlText(dict, name), name);
}

ExperimentConfig ExperimentFrom(py::handle experiment, py::handle base_dir) {
  const bool is_dict = IsMapping(experiment);
  const std::string dir = BaseDir(base_dir, is_dict);
  if (is_dict) return ParseExperiment(ParseDict(experiment, kExperimentDict), kExperimentDict, dir);
  return LoadExperiment(PathOf(experiment, "experiment"));
}

FitJob JobFrom(py::handle job, py::handle base_dir) {
  if (py::isinstance<FitJob>(job)) {
    if (!base_dir.is_none()) {
      throw std::invalid_argument(
          "base_dir: expected no base_dir with a loaded Job (its paths are "
          "resolved), got '" + PathOf(base_dir, "base_dir", " or None") + "'");
    }
    return job.cast<FitJob>();
  }
  const bool is_dict = IsMapping(job);
  const std::string dir = BaseDir(base_dir, is_dict);
  if (is_dict) return ParseFitJob(ParseDict(job, kJobDict), kJobDict, dir);
  return LoadFitJob(PathOf(job, "job", ", a dict or a Job"));
}

// The channels a simulate(channels=...) asks for: None keeps the
// experiment's, "all" is every channel but t, else a list of names.
void ChooseChannels(py::handle channels, ExperimentConfig* e) {
  if (channels.is_none()) return;
  std::vector<Channel> chosen;
  if (py::isinstance<py::str>(channels) && channels.cast<std::string>() == "all") {
    for (int c = 1; c < kNumChannels; ++c) chosen.push_back(static_cast<Channel>(c));
  } else {
    // (cast<std::vector<std::string>> raised RuntimeError "Unable to cast")
    const bool list = py::isinstance<py::list>(channels) || py::isinstance<py::tuple>(channels);
    if (py::isinstance<py::str>(channels) || !list) {
      throw py::type_error("channels: expected None, \"all\" or a list of channel names (" +
                           ChannelNameList() + "), got " + Quoted(channels));
    }
    for (const py::handle item : channels) {
      if (!py::isinstance<py::str>(item)) {
        throw py::type_error("channels: expected channel names (str), got " + Quoted(item));
      }
    }
    for (const std::string& name : channels.cast<std::vector<std::string>>()) {
      const std::optional<Channel> c = ParseChannel(name);
      if (!c) {
        throw std::invalid_argument("channels: expected \"all\" or channel names (" +
                                    ChannelNameList() + "), got '" + name + "'");
      }
      if (*c != Channel::kT && std::find(chosen.begin(), chosen.end(), *c) == chosen.end()) {
        chosen.push_back(*c);
      }
    }
  }
  if (chosen.empty()) {
    throw std::invalid_argument("channels: expected at least one channel besides t, got none");
  }
  e->options.channels = std::move(chosen);
}

py::dict Simulate(py::object experiment, py::object base_dir, py::object noise,
                  py::object seed_arg, py::object set, py::object channels) {
  // The arguments first, each named with its rule, then the experiment.
  const bool with_noise = BoolArgument(noise, "noise");
  const std::optional<std::uint64_t> seed = SeedArgument(seed_arg);
  ExperimentConfig e = ExperimentFrom(experiment, base_dir);
  ChooseChannels(channels, &e);
  ApplySetDict(set, &e.model);  // as SimulateExperiment applies --set: before the initial state
  SimulateAxisOptions options;
  options.no_noise = !with_noise;
  options.has_seed = seed.has_value();
  options.seed = seed.value_or(0);
  const std::vector<Channel> recorded = e.options.channels;
  Trace<double> trace;
  {
    py::gil_scoped_release release;
    trace = SimulateExperiment(std::move(e), options);
  }
  py::dict out;
  out["t"] = ToArray(trace.t);
  for (Channel c : recorded) out[ChannelName(c)] = ToArray(trace[c]);
  return out;
}

// A NumPy-friendly copy of the measured channels of a job experiment.
py::dict MeasuredOf(const FitExperiment& e) {
  py::dict out;
  for (size_t k = 0; k < e.measured_channels.size(); ++k) {
    out[ChannelName(e.measured_channels[k])] = ToArray(e.measured[k]);
  }
  return out;
}

py::object JsonToPython(const nlohmann::ordered_json& j) {
  return py::module_::import("json").attr("loads")(
      j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace));
}

py::object FiniteOrNone(double value, bool present) {
  return present && std::isfinite(value) ? py::object(py::float_(value)) : py::none();
}

JobRun Fit(py::object job_arg, py::object discover_arg, py::object progress, py::object out,
           py::object base_dir) {
  const bool discover = BoolArgument(discover_arg, "discover");
  if (!progress.is_none() && !PyCallable_Check(progress.ptr())) {
    throw py::type_error("progress: expected a callable taking one str, or None");
  }
  FitJob job = JobFrom(job_arg, base_dir);
  std::string out_dir;
  if (py::isinstance<py::bool_>(out)) {
    if (out.cast<bool>()) {
      if (job.out_dir.empty()) {
        throw std::invalid_argument(job.problem.path +
                                    ": expected output.dir in the job for out=True, got none");
      }
      out_dir = job.out_dir;
    }
  } else if (!out.is_none()) {
    out_dir = PathOf(out, "out", ", True, False or None");
    if (out_dir.empty()) {
      throw std::invalid_argument(
          "out: expected a folder path (or True, False or None), got '' (it wrote nothing)");
    }
  }
  // Before the fit, not after it (fit-params does the same): a file in the
  // way or a folder that cannot be written into.
  if (!out_dir.empty()) CheckOutputDirectory(out_dir);
  ProgressStream stream(progress);
  JobRun run;
  std::vector<std::string> warnings;
  {
    py::gil_scoped_release release;
    run = RunJob(std::move(job), discover, stream);
  }
  stream.Finish();
  if (!out_dir.empty()) {
    {
      py::gil_scoped_release release;
      warnings = WriteJobRun(run, out_dir);
    }
    for (const std::string& w : warnings) {
      py::module_::import("warnings").attr("warn")(w, py::module_::import("builtins").attr("RuntimeWarning"));
    }
  }
  return run;
}

template <typename T>
const T& Named(const std::vector<T>& items, const std::string& name, const char* what) {
  for (const T& item : items) {
    if (item.name == name) return item;
  }
  throw py::key_error(std::string(what) + " '" + name + "' not found");
}

// fit_result.parameter(name) and .experiment(name): a copy of the item of
// FitResult::*items called `name`.
template <typename T>
auto Lookup(std::vector<T> FitResult::*items, const char* what) {
  return [items, what](const JobRun& r, const std::string& name) {
    return Named(r.result.*items, name, what);
  };
}

// The names of `items` in order.
template <typename T>
std::vector<std::string> NamesOf(const std::vector<T>& items) {
  std::vector<std::string> names;
  for (const T& item : items) names.push_back(item.name);
  return names;
}

const ChannelFit& ChannelNamed(const ExperimentFit& e, const std::string& name) {
  for (const ChannelFit& c : e.channels) {
    if (c.channel == name) return c;
  }
  throw py::key_error("channel '" + name + "' not in experiment '" + e.name + "'");
}

void DefineJob(py::module_& m) {
  py::class_<FreeParameter>(m, "FreeParameter", "A free parameter of a job (estimation/estimation_problem.h).")
      .def_readonly("name", &FreeParameter::name)
      .def_readonly("unit", &FreeParameter::unit)
      .def_readonly("initial", &FreeParameter::initial)
      .def_readonly("lower", &FreeParameter::lower)
      .def_readonly("upper", &FreeParameter::upper)
      .def_readonly("scale", &FreeParameter::scale)
      .def_readonly("log", &FreeParameter::log, "optimised as log(value) (lower > 0)")
      .def("__repr__", [](const FreeParameter& p) {
        return "FreeParameter(" + p.name + " [" + p.unit + "], initial " +
               std::to_string(p.initial) + ", bounds [" + std::to_string(p.lower) + ", " +
               std::to_string(p.upper) + "])";
      });

  py::class_<FitExperiment>(m, "JobExperiment",
                            "A recorded experiment of a job, cut to its window.")
      .def_readonly("name", &FitExperiment::name)
      .def_readonly("role", &FitExperiment::role, "'fit' or 'validate'")
      .def_readonly("data_path", &FitExperiment::data_path)
      .def_readonly("t_offset", &FitExperiment::t_offset,
                    "s, the file's time of the first sample in the window")
      .def_property_readonly("t", [](const FitExperiment& e) { return ToArray(e.t); },
                             "s, sample times relative to the window's start (float64 array)")
      .def_property_readonly("measured", &MeasuredOf,
                             "dict channel -> measured samples (float64 arrays, channel unit)")
      .def_property_readonly(
          "fitted",
          [](const FitExperiment& e) {
            py::dict out;
            for (const FittedChannel& f : e.fitted) out[ChannelName(f.channel)] = f.sigma;
            return out;
          },
          "dict fitted channel -> sigma (channel unit)")
      .def("__repr__", [](const FitExperiment& e) {
        return "JobExperiment('" + e.name + "', " + e.role + ", " + std::to_string(e.t.size()) +
               " samples)";
      });

  py::class_<FitJob>(m, "Job",
                     "A loaded fit job (load_job): inspectable, and accepted by fit().")
      .def_property_readonly("path", [](const FitJob& j) { return j.problem.path; },
                             "the job file, or '<job dict>'")
      .def_readonly("title", &FitJob::title)
      .def_readonly("out_dir", &FitJob::out_dir, "output.dir resolved, or '' if none")
      .def_property_readonly("model", [](const FitJob& j) { return j.problem.model.name; },
                             "the model config's name")
      .def_property_readonly("model_yaml",
                             [](const FitJob& j) { return AxisConfigToYaml(j.problem.model); },
                             "the model with the job's overrides, as a model config (YAML)")
      .def_property_readonly("free", [](const FitJob& j) { return j.problem.free; },
                             "list of FreeParameter, in job order")
      .def_property_readonly("free_names", [](const FitJob& j) { return NamesOf(j.problem.free); })
      .def_property_readonly("experiments", [](const FitJob& j) { return j.problem.experiments; },
                             "fitted experiments (JobExperiment)")
      .def_property_readonly("validate", [](const FitJob& j) { return j.problem.validate; },
                             "validation experiments (JobExperiment)")
      .def_property_readonly("experiment_names",
                             [](const FitJob& j) { return NamesOf(j.problem.experiments); })
      .def_property_readonly("validate_names",
                             [](const FitJob& j) { return NamesOf(j.problem.validate); })
      .def_property_readonly("discover", [](const FitJob& j) { return j.discover.enabled; },
                             "the job has a discover: key")
      .def("__repr__", [](const FitJob& j) {
        return "Job('" + j.title + "', " + std::to_string(j.problem.free.size()) + " free, " +
               std::to_string(j.problem.experiments.size()) + " fitted and " +
               std::to_string(j.problem.validate.size()) + " validation experiment(s))";
      });
}

// Parameter: one ParameterEstimate of a fit result.
void DefineParameter(py::module_& m) {
  py::class_<ParameterEstimate>(m, "Parameter", "One model parameter of a fit result.")
      .def_readonly("name", &ParameterEstimate::name, "MODEL.md name, e.g. 'B_a'")
      .def_readonly("unit", &ParameterEstimate::unit, "SI unit, e.g. 'N*s/m'")
      .def_readonly("value", &ParameterEstimate::value)
      .def_readonly("initial", &ParameterEstimate::initial)
      .def_readonly("free", &ParameterEstimate::free)
      .def_readonly("tied_to", &ParameterEstimate::tied_to,
                    "the parameter whose value this one takes (job key tie:), or ''")
      .def_readonly("determined", &ParameterEstimate::determined,
                    "False if the data cannot determine it")
      .def_property_readonly(
          "std_error",
          [](const ParameterEstimate& p) {
            return FiniteOrNone(p.std_error, p.free || !p.tied_to.empty());
          },
          "standard error (result.uncertainty_method; a tied parameter its source's); None if "
          "fixed or not finite")
      .def_property_readonly("std_error_gauss_newton",
                             [](const ParameterEstimate& p) {
                               return FiniteOrNone(p.std_error_gauss_newton, p.free);
                             })
      .def_property_readonly(
          "ci95",
          [](const ParameterEstimate& p) -> py::object {
            const bool tied = !p.tied_to.empty() && std::isfinite(p.ci95_low);
            if (!p.free && !tied) return py::none();
            return py::make_tuple(p.ci95_low, p.ci95_high);
          },
          "95 % interval (low, high); a tied parameter its source's; None if fixed")
      .def("__repr__", [](const ParameterEstimate& p) {
        return "Parameter(" + p.name + " = " + std::to_string(p.value) + " " + p.unit +
               (p.free ? ", free)" : ", fixed)");
      });
}

// ChannelFit: the goodness of fit of one channel.
void DefineChannelFit(py::module_& m) {
  py::class_<ChannelFit>(m, "ChannelFit", "Goodness of fit of one channel of one experiment.")
      .def_readonly("channel", &ChannelFit::channel)
      .def_readonly("unit", &ChannelFit::unit)
      .def_readonly("fitted", &ChannelFit::fitted, "its residual entered the cost")
      .def_readonly("sigma", &ChannelFit::sigma, "weight of a fitted channel, else 0")
      .def_readonly("rms", &ChannelFit::rms, "RMS of simulated - measured (channel unit)")
      .def_readonly("fit_percent", &ChannelFit::fit_percent, "NRMSE fit, %")
      .def_readonly("max_error", &ChannelFit::max_error)
      .def_readonly("mae", &ChannelFit::mae)
      .def_readonly("relative_error_percent", &ChannelFit::relative_error_percent,
                    "100*|sim - meas|/|meas| (the EMPS measure)")
      .def_readonly("ljung_box_q", &ChannelFit::ljung_box_q)
      .def_readonly("ljung_box_lags", &ChannelFit::ljung_box_lags)
      .def_readonly("ljung_box_p", &ChannelFit::ljung_box_p)
      .def_readonly("input_xcorr_peak", &ChannelFit::input_xcorr_peak)
      .def_readonly("input_xcorr_lag", &ChannelFit::input_xcorr_lag)
      .def_property_readonly("measured", [](const ChannelFit& c) { return ToArray(c.measured); },
                             "float64 array per sample")
      .def_property_readonly("simulated",
                             [](const ChannelFit& c) { return ToArray(c.simulated); },
                             "float64 array per sample, with the fitted parameters")
      .def("__repr__", [](const ChannelFit& c) {
        return "ChannelFit(" + c.channel + ", rms " + std::to_string(c.rms) + " " + c.unit +
               ", fit " + std::to_string(c.fit_percent) + " %)";
      });
}

// ExperimentFit: one experiment's traces and its ChannelFits.
void DefineExperimentFit(py::module_& m) {
  py::class_<ExperimentFit>(m, "ExperimentFit",
                            "The traces and statistics of one experiment of a fit.")
      .def_readonly("name", &ExperimentFit::name)
      .def_readonly("role", &ExperimentFit::role, "'fit' or 'validate'")
      .def_property_readonly("t", [](const ExperimentFit& e) { return ToArray(e.t); },
                             "s, sample times (float64 array)")
      .def_readonly("channels", &ExperimentFit::channels, "list of ChannelFit")
      .def("channel", &ChannelNamed, py::arg("name"),
           "The ChannelFit of channel `name`; KeyError if absent.")
      .def("__repr__", [](const ExperimentFit& e) {
        return "ExperimentFit('" + e.name + "', " + e.role + ", " +
               std::to_string(e.channels.size()) + " channels)";
      });
}

// FitResult (a JobRun), in three groups of properties, defined in this order:
// the estimates, the fit's figures and notes, the reports and the rest.
void DefineFitResultEstimates(py::class_<JobRun>& c) {
  c.def_property_readonly("title", [](const JobRun& r) { return r.job.title; })
      .def_property_readonly("parameters", [](const JobRun& r) { return r.result.parameters; },
                             "list of Parameter: the free ones first (job order), then fixed")
      .def("parameter", Lookup(&FitResult::parameters, "parameter"), py::arg("name"),
           "The Parameter called `name`; KeyError if absent.")
      .def_property_readonly("values",
                             [](const JobRun& r) {
                               py::dict out;
                               for (const ParameterEstimate& p : r.result.parameters) {
                                 if (p.free) out[py::str(p.name)] = p.value;
                               }
                               return out;
                             },
                             "dict free parameter name -> fitted value")
      .def_property_readonly("experiments", [](const JobRun& r) { return r.result.experiments; },
                             "list of ExperimentFit: fitted, then validation experiments")
      .def("experiment", Lookup(&FitResult::experiments, "experiment"), py::arg("name"),
           "The ExperimentFit called `name`; KeyError if absent.")
      .def_property_readonly("free_names", [](const JobRun& r) { return r.result.free_names; })
      .def_property_readonly("correlation", [](const JobRun& r) {
        const Eigen::MatrixXd& c = r.result.correlation;
        py::array_t<double> out({c.rows(), c.cols()});
        for (Eigen::Index i = 0; i < c.rows(); ++i) {
          for (Eigen::Index k = 0; k < c.cols(); ++k) out.mutable_at(i, k) = c(i, k);
        }
        return out;
      }, "n x n correlation of the free parameters (free_names order)")
      .def_property_readonly("undetermined", [](const JobRun& r) { return r.result.undetermined; });
}

void DefineFitResultFigures(py::class_<JobRun>& c) {
  c.def_property_readonly("initial_cost", [](const JobRun& r) { return r.result.initial_cost; },
                          "Ceres cost 1/2 sum(r^2) at the initial point")
      .def_property_readonly("final_cost", [](const JobRun& r) { return r.result.final_cost; })
      .def_property_readonly("converged", [](const JobRun& r) { return r.result.converged; })
      .def_property_readonly("aic", [](const JobRun& r) { return r.result.aic; })
      .def_property_readonly("bic", [](const JobRun& r) { return r.result.bic; })
      .def_property_readonly("num_residuals", [](const JobRun& r) { return r.result.num_residuals; })
      .def_property_readonly("residual_variance",
                             [](const JobRun& r) { return r.result.residual_variance; })
      .def_property_readonly("optimum_verified",
                             [](const JobRun& r) { return r.result.optimum_verified; })
      .def_property_readonly("optimum_check", [](const JobRun& r) { return r.result.optimum_check; })
      .def_property_readonly("uncertainty_method",
                             [](const JobRun& r) { return r.result.uncertainty_method; })
      .def_property_readonly("uncertainty_note",
                             [](const JobRun& r) { return r.result.uncertainty_note; })
      .def_property_readonly("termination", [](const JobRun& r) { return r.result.termination; })
      .def_property_readonly("model_note", [](const JobRun& r) { return r.result.model_note; },
                             "where the fitting model's approximation may bias the estimate "
                             "(e.g. the quasi-steady current loop's shift), '' if nowhere")
      .def_property_readonly(
          "auto_starts_note", [](const JobRun& r) { return r.result.auto_starts_note; },
          "set when the job's start ended above s^2 = 4 and solver.auto_starts were added")
      .def_property_readonly(
          "sample_sigma_note", [](const JobRun& r) { return r.result.sample_sigma_note; },
          "set when samples of an instant accelerometer at a backlash contact were weighted "
          "by sigma_k (MODEL.md section 6), else ''")
      .def_property_readonly(
          "residual_note", [](const JobRun& r) { return r.result.residual_note; },
          "a warning when the fit ends above s^2 = 4 (residual RMS over twice sigma), else ''");
}

void DefineFitResultReports(py::class_<JobRun>& c) {
  c.def_property_readonly(
       "discovery",
       [](const JobRun& r) -> py::object {
         if (!r.discovered) return py::none();
         return JsonToPython(nlohmann::ordered_json(DiscoveryToJson(r.discovery)));
       },
       "None without discovery, else report.json's 'discovery' block as a dict: "
       "'selected', 'steps', 'verdict', 'verdict_detail', 'ranking', 'stop_reason', ...")
      .def_property_readonly(
          "discovery_table",
          [](const JobRun& r) { return r.discovered ? FormatDiscovery(r.discovery) : ""; },
          "the discovery table as fit-params prints it ('' without discovery)")
      .def_property_readonly(
          "published",
          [](const JobRun& r) -> py::object {
            if (!r.has_published) return py::none();
            return JsonToPython(nlohmann::ordered_json(PublishedToJson(r.published)));
          },
          "None, or report.json's 'published' block as a dict")
      .def_property_readonly(
          "report", [](const JobRun& r) { return JsonToPython(ReportJson(r.result, r.sections)); },
          "the whole of what fit-params writes to report.json, as a dict")
      .def_property_readonly("model_yaml",
                             [](const JobRun& r) {
                               AxisConfig fitted = r.job.problem.model;
                               for (const ParameterEstimate& p : r.result.parameters) {
                                 if (p.free || !p.tied_to.empty()) {
                                   *FindParam(&fitted.params, p.name) = p.value;
                                 }
                               }
                               return AxisConfigToYaml(fitted);
                             },
                             "the fitted model (with the discovered effects) as a model config")
      .def("table",
           [](const JobRun& r) {
             return FormatParameterTable(r.result) + "\n" + FormatFitTable(r.result);
           },
           "The parameter and fit tables as fit-params prints them.")
      .def("__repr__", [](const JobRun& r) {
        return "FitResult('" + r.job.title + "', cost " + std::to_string(r.result.final_cost) +
               (r.result.converged ? ", converged)" : ", not converged)");
      });
}

void DefineFitResult(py::module_& m) {
  py::class_<JobRun> c(m, "FitResult", "What fit() returns.");
  DefineFitResultEstimates(c);
  DefineFitResultFigures(c);
  DefineFitResultReports(c);
}

// The result classes: Parameter, ChannelFit, ExperimentFit, FitResult.
void DefineResult(py::module_& m) {
  DefineParameter(m);
  DefineChannelFit(m);
  DefineExperimentFit(m);
  DefineFitResult(m);
}

}  // namespace
}  // namespace axis::python

PYBIND11_MODULE(servo_axis_id, m) {
  axis::KeepFreedMemory();  // common/allocator.h: a fit reuses its buffers
  namespace ap = axis::python;
  // Ceres logs through glog; the results carry its messages (termination,
  // undetermined parameters), so only fatal ones, as in fit-params.
  FLAGS_minloglevel = google::GLOG_FATAL;
  m.doc() =
      "Grey-box identification of servo axes of Cartesian robots (Nelson & Chang 1984 model): "
      "simulate experiments, load and fit jobs. Formats: configs/README.md; channels and "
      "parameters: MODEL.md.";
  m.attr("__version__") = SERVO_AXIS_ID_VERSION;
  {
    std::vector<std::string> names;
    for (int c = 0; c < axis::kNumChannels; ++c) {
      names.push_back(axis::ChannelName(static_cast<axis::Channel>(c)));
    }
    m.attr("CHANNELS") = names;
  }
  ap::DefineJob(m);
  ap::DefineResult(m);

  m.def("simulate", &ap::Simulate, py::arg("experiment"), py::kw_only(),
        py::arg("base_dir") = py::none(), py::arg("noise") = true, py::arg("seed") = py::none(),
        py::arg("set") = py::none(), py::arg("channels") = py::none(),
        R"doc(Simulates one experiment as simulate-axis does and returns its trace.

experiment: path of an experiment YAML file (configs/README.md, section 2), or a dict
    with the same content (read by the same strict loader; relative paths in it resolve
    against base_dir, default the current directory).
noise: add the experiment's measurement noise (simulate-axis without --no-noise).
seed: noise seed overriding the experiment's (--seed).
set: dict parameter name -> value applied after the file (--set NAME=VALUE).
channels: None for the experiment's channels, "all", or a list of channel names
    (CHANNELS). Other channels change the noise drawn (it is drawn per channel).

Returns a dict {"t": times in s, channel: values in the channel's SI unit, ...}, float64
arrays of one length, the channels in the experiment's order.
Raises ValueError (bad experiment, with the loader's "<file>:<line>: key '<path>': expected
..., got ..." message; seed outside 0..2**62; a set name that is not a parameter or a value
that is not a number in its range, "set['M']: ..."), TypeError (experiment neither a path
nor a dict; noise not a bool; seed not an integer; set not a dict; channels not "all" or a
list of str), RuntimeError (the simulation left the finite numbers); the arguments are
checked before simulating. Releases the GIL while simulating.)doc");

  m.def(
      "load_job",
      [](py::object job, py::object base_dir) { return ap::JobFrom(job, base_dir); },
      py::arg("job"), py::kw_only(), py::arg("base_dir") = py::none(),
      R"doc(Loads and checks a fit job (configs/README.md, section 3) without fitting.

job: path of a job YAML file, or a dict with the same content (relative paths in it
    resolve against base_dir, default the current directory).
Returns a Job (title, free, free_names, experiment_names, experiments with their data...),
which fit() accepts. Raises ValueError with the loader's message, TypeError.)doc");

  m.def("fit", &ap::Fit, py::arg("job"), py::kw_only(), py::arg("discover") = false,
        py::arg("progress") = py::none(), py::arg("out") = py::none(),
        py::arg("base_dir") = py::none(),
        R"doc(Fits a job as fit-params does and returns a FitResult.

job: a job file path, a dict (as load_job), or a Job from load_job.
discover: run the discovery loop (fit-params --discover; also if the job has discover:).
progress: None, or a callable taking one str: called with each line fit-params would
    print (solver iterations, discovery steps, the final tables), from the calling thread,
    while the fit runs. If it raises, later lines are dropped and the exception is raised
    when the fit returns (the fit itself is not stopped).
out: None or False writes nothing (the job's output.dir is ignored); a folder path writes
    fit-params' files there (params.md, params.csv, report.json, fit_*.csv/.png ...);
    True writes them to the job's output.dir.
The GIL is released while fitting: other Python threads run meanwhile.
Raises ValueError (bad job, with the loader's message; out a file, or in a folder that cannot
be written into, or ''), TypeError (discover not a bool, progress not callable, out not a
path or a bool), all before fitting; RuntimeError (outputs that cannot be written after
all). Plot warnings (gnuplot missing) are RuntimeWarnings.)doc");

  m.def(
      "to_yaml", [](py::object document) { return ap::ToYamlText(document, "<dict>"); },
      py::arg("document"),
      R"doc(The YAML text a dict experiment or job is read from: the line numbers in
ValueError messages about a dict ("<job dict>:7: key ...") are lines of this text.)doc");
}
