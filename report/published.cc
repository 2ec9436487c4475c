#include "report/published.h"

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

#include "common/format.h"
#include "estimation/evaluate_experiment.h"
#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "report/published_reference.h"

namespace axis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

PublishedComparison ComparePublished(const EstimationProblem& job, const FitResult& result,
                                     const PublishedReference& reference) {
  PublishedComparison out;
  out.source = reference.source;
  AxisParams<double> published = reference.model.params;
  for (const std::string& name : reference.parameters) {
    ParameterComparison p;
    p.name = name;
    p.unit = ParamUnit(name, job.model.structure.motion);
    p.published = *FindParam(&published, name);
    p.fitted = kNaN;
    p.std_error = kNaN;
    for (const ParameterEstimate& e : result.parameters) {
      if (e.name != name) continue;
      p.fitted = e.value;
      // A parameter tied to a fitted one (ParameterEstimate::tied_to) is
      // estimated with it.
      p.free = e.free || !e.tied_to.empty();
      if (p.free) p.std_error = e.std_error;
    }
    out.parameters.push_back(p);
  }
  const auto compare = [&](const std::vector<FitExperiment>& experiments) {
    for (const FitExperiment& e : experiments) {
      const ExperimentFit simulated =
          EvaluateExperiment(reference.model.structure, published, e);
      const ExperimentFit* fitted = nullptr;
      for (const ExperimentFit& f : result.experiments) {
        if (f.name == e.name) fitted = &f;
      }
      for (const ChannelFit& c : simulated.channels) {
        ChannelComparison row;
        row.experiment = e.name;
        row.channel = c.channel;
        row.published_percent = c.relative_error_percent;
        row.published_rms = c.rms;
        row.published_mae = c.mae;
        row.fitted_percent = row.fitted_rms = kNaN;
        if (fitted) {
          for (const ChannelFit& f : fitted->channels) {
            if (f.channel != c.channel) continue;
            row.fitted_percent = f.relative_error_percent;
            row.fitted_rms = f.rms;
          }
        }
        row.quoted_percent = kNaN;
        for (const QuotedError& q : reference.quoted) {
          if (q.experiment == e.name && q.channel == c.channel) row.quoted_percent = q.percent;
        }
        out.channels.push_back(row);
      }
    }
  };
  compare(job.experiments);
  compare(job.validate);
  return out;
}

std::string FormatPublished(const PublishedComparison& c) {
  std::ostringstream out;
  out << "Published reference: " << c.source << "\n";
  out << "  parameter  unit         this fit     std error    published   difference %\n";
  for (const ParameterComparison& p : c.parameters) {
    out << "  " << std::left << std::setw(10) << p.name << " " << std::setw(8)
        << p.unit << std::right << std::setprecision(6) << std::setw(13)
        << p.fitted << std::setw(14) << p.std_error << std::setw(13) << p.published
        << std::setw(15) << std::setprecision(3)
        << 100.0 * (p.fitted - p.published) / std::abs(p.published)
        << (p.free ? "" : "   (not estimated: effect not in the model)") << "\n";
  }
  out << "  relative error % (100·‖ŷ − y‖/‖y‖) and RMS error (channel unit)\n";
  out << "  experiment              channel   this fit   published model here   published (quoted)"
         "   RMS this fit   RMS published here\n";
  for (const ChannelComparison& r : c.channels) {
    out << "  " << std::left << std::setw(24) << r.experiment << std::setw(8)
        << r.channel << std::right << std::setprecision(4) << std::setw(10)
        << r.fitted_percent << std::setw(23) << r.published_percent << std::setw(21);
    if (std::isnan(r.quoted_percent)) {
      out << "-";
    } else {
      out << r.quoted_percent;
    }
    out << std::setw(15) << r.fitted_rms << std::setw(21) << r.published_rms << "\n";
  }
  return out.str();
}

nlohmann::json PublishedToJson(const PublishedComparison& c) {
  nlohmann::json out;
  out["source"] = c.source;
  out["parameters"] = nlohmann::json::object();
  for (const ParameterComparison& p : c.parameters) {
    out["parameters"][p.name] = {{"published", JsonNumber(p.published)},
                                 {"fitted", JsonNumber(p.fitted)},
                                 {"std_error", JsonNumber(p.std_error)},
                                 {"free", p.free}};
  }
  out["channels"] = nlohmann::json::array();
  for (const ChannelComparison& r : c.channels) {
    out["channels"].push_back({{"experiment", r.experiment},
                               {"channel", r.channel},
                               {"relative_error_percent", JsonNumber(r.fitted_percent)},
                               {"published_simulated_percent", JsonNumber(r.published_percent)},
                               {"published_quoted_percent", JsonNumber(r.quoted_percent)},
                               {"rms", JsonNumber(r.fitted_rms)},
                               {"published_simulated_rms", JsonNumber(r.published_rms)}});
  }
  return out;
}

}  // namespace axis
