// A published reference model set beside the fit (job key `published:`):
// the parameters a source reports, the relative errors it quotes, and the
// same model simulated by this tool on the job's experiments with the job's
// own controller settings. Used for the EMPS benchmark (issue 5;
// testdata/emps/README.md): Janot, Gautier & Brunot 2019 publish M, Fv, Fc
// and an offset, and closed-loop relative errors 100·‖ŷ − y‖/‖y‖.
#ifndef REPORT_PUBLISHED_H_
#define REPORT_PUBLISHED_H_

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "estimation/fit_result.h"
#include "estimation/estimation_problem.h"
#include "report/published_reference.h"
#include "sim/config.h"

namespace axis {

struct ParameterComparison {
  std::string name, unit;
  double published = 0.0;
  double fitted = 0.0;     // this fit's value (the model's value if fixed)
  double std_error = 0.0;  // NaN if fixed
  bool free = false;       // estimated by this fit (false: not in the model)
};

struct ChannelComparison {
  std::string experiment, channel;
  double fitted_percent = 0.0;      // this fit's relative error
  double published_percent = 0.0;   // the published model simulated here
  double quoted_percent = 0.0;      // the source's figure, NaN if none
  double fitted_rms = 0.0;          // this fit's RMS error (channel unit)
  double published_rms = 0.0;       // the published model's, simulated here
  double published_mae = 0.0;       // its mean absolute error (ChannelFit::mae)
};

struct PublishedComparison {
  std::string source;
  std::vector<ParameterComparison> parameters;
  std::vector<ChannelComparison> channels;
};

// Compares `result` (fitted on job's `experiments` and `validate`) with the
// published model `published`, which is simulated on every experiment
// here. A published model whose simulation fails gives NaN errors. Never
// throws on that.
PublishedComparison ComparePublished(const EstimationProblem& job, const FitResult& result,
                                     const PublishedReference& published);

// The comparison as text tables (terminal and params.md).
std::string FormatPublished(const PublishedComparison& comparison);

// report.json's "published" block: {"source", "parameters": {name:
// {"published", "fitted", "std_error", "free"}}, "channels": [{"experiment",
// "channel", "relative_error_percent", "published_simulated_percent",
// "published_quoted_percent", "rms", "published_simulated_rms"}]}.
nlohmann::json PublishedToJson(const PublishedComparison& comparison);

}  // namespace axis

#endif  // REPORT_PUBLISHED_H_
