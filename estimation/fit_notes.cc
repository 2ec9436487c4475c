#include "estimation/fit_notes.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>
#include <vector>

#include "common/format.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "estimation/solver_settings.h"
#include "sim/controller.h"

namespace axis {

std::string IntegrationNote(const EstimationProblem& job) {
  std::set<double> steps;
  for (const std::vector<FitExperiment>* list : {&job.experiments, &job.validate}) {
    for (const FitExperiment& e : *list) steps.insert(e.options.step);
  }
  std::ostringstream out;
  out << "RK4, step";
  if (steps.size() > 1) out << "s";
  const char* sep = " ";
  for (double h : steps) {
    out << sep << h;
    sep = ", ";
  }
  out << " s";
  if (job.model.structure.amplifier == Amplifier::kAnalogVelocityLoop) {
    out << "; current loop "
        << (job.model.structure.current_loop == CurrentLoop::kQuasiSteady
                ? "quasi_steady (its fast limit, the voltage limit kept: "
                  "sim/axis_params.h CurrentLoop)"
                : "full (eq. 3)");
  } else if (job.model.structure.amplifier == Amplifier::kVoltageDrive) {
    out << (job.model.structure.inductance
                ? "; armature inductance L kept (the winding current a state, MODEL.md "
                  "section 4)"
                : "; armature inductance neglected (MODEL.md section 4)");
  }
  return out.str();
}

std::string QuantisedFeedbackStopNote(const EstimationProblem& job,
                                      const ceres::Solver::Summary& summary) {
  const AxisConfig& model = job.model;
  const ControllerConfig& c = model.controller;
  // Only a fitted record in closed loop feeds the quantised position back
  // (an open-loop record driven by its u column has no controller in it).
  bool closed_loop = false;
  for (const FitExperiment& e : job.experiments) closed_loop = closed_loop || e.drive.closed_loop;
  if (!model.has_controller || !closed_loop || summary.termination_type != ceres::CONVERGENCE ||
      summary.message.rfind("Parameter tolerance", 0) != 0) {
    return "";
  }
  const double quantum = PositionQuantum(c, model.params.r_g);  // m
  if (quantum == 0.0) return "";
  const std::string key = c.load_quantum > 0.0 ? "load_quantum" : "counts_per_rev";
  std::ostringstream note;
  note << std::setprecision(3) << "stopped on the step size, not on the gradient or the cost "
       << "change, with the position feedback quantised (controller." << key << ": quantum "
       << quantum << " m, G_p·quantum = " << c.G_p * quantum
       << " V at the controller output): the cost is piecewise constant at that scale, so "
          "the end point can depend on the path by more than the standard errors; where "
          "G_p·quantum is far below the σ of u, a model "
          "without the quantiser (controller: {"
       << key << ": 0} in the job) has a smooth cost (README, Real data: EMPS)";
  return note.str();
}

std::string QuasiSteadyDelayNote(const EstimationProblem& job, const FitResult& result) {
  const AxisStructure& s = job.model.structure;
  if (s.amplifier != Amplifier::kAnalogVelocityLoop ||
      s.current_loop != CurrentLoop::kQuasiSteady) {
    return "";
  }
  const auto value = [&](const char* name) {
    for (const ParameterEstimate& e : result.parameters) {
      if (e.name == name) return e.value;
    }
    return std::numeric_limits<double>::quiet_NaN();
  };
  const double tau_i = value("L") / (value("K_a") / value("K_i") + value("R"));
  std::ostringstream note;
  note << std::setprecision(3);
  for (const ParameterEstimate& e : result.parameters) {
    if (!e.free || e.name.rfind("tau_d.", 0) != 0 || !(tau_i >= 0.5 * e.std_error)) continue;
    note << (note.tellp() > 0 ? "; " : "") << e.name << " (standard error " << e.std_error
         << " s)";
  }
  if (note.tellp() == 0) return "";
  std::ostringstream out;
  out << std::setprecision(3) << "fitted with the quasi-steady current loop, which neglects "
      << "the current loop's time constant L/(K_a/K_i + R) = " << tau_i
      << " s (eq. 3), at least half the standard error of " << note.str()
      << ": a delay absorbs part of that lag (about half of it on the sensor_delay "
         "case, one standard error there); for the delay, fit the full loop "
         "(configuration: {current_loop: full}, simulation: {quasi_steady_screen: off})";
  return out.str();
}

std::string ResidualNote(double s2) {
  if (!(s2 > kAutoStartsAbove)) return "";
  std::ostringstream note;
  note << "s^2 = " << FormatNumber(s2, 4) << ": the residual RMS is "
       << FormatNumber(std::sqrt(s2), 3)
       << " times the declared sigma; a local minimum the starts did not leave (solver.starts), "
          "an effect the model lacks (fit-params --discover), or sigma set below the noise";
  return note.str();
}

std::vector<std::string> StructuredChannels(const FitResult& result) {
  std::vector<std::string> out;
  for (const ExperimentFit& e : result.experiments) {
    if (e.role != "fit") continue;
    for (const ChannelFit& c : e.channels) {
      if (c.fitted && c.ljung_box_p < kStructuredResidualP) out.push_back(e.name + "/" + c.channel);
    }
  }
  return out;
}

std::string MisspecificationNote(const FitResult& result, double s2,
                                 const std::vector<std::string>& structured, int lags) {
  std::ostringstream note;
  note << "s^2 = " << FormatNumber(s2, 4) << " (above " << kMisspecifiedS2
       << ") with structured residuals (Ljung-Box p < " << kStructuredResidualP << ":";
  for (size_t i = 0; i < structured.size(); ++i) note << (i == 0 ? " " : ", ") << structured[i];
  note << "): the intervals are conditional on the model (they take its misfit for noise); "
          "sandwich standard errors (Newey-West, "
       << lags << " lags), which allow for the misfit:";
  bool first = true;
  for (const ParameterEstimate& p : result.parameters) {
    if (!p.free) continue;
    note << (first ? " " : ", ") << p.name << " " << FormatNumber(p.std_error_sandwich, 3)
         << (p.unit.empty() ? "" : " " + p.unit);
    first = false;
  }
  return note.str();
}

}  // namespace axis
