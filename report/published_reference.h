// The job key `published:` (the EMPS benchmark, issue 5): a published
// reference model to set beside the fit, and its strict loader; the
// comparison itself is report/published.h.
#ifndef REPORT_PUBLISHED_REFERENCE_H_
#define REPORT_PUBLISHED_REFERENCE_H_

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "estimation/estimation_problem.h"
#include "sim/axis_config.h"

namespace axis {

// A relative error the source quotes for one channel of one experiment (%).
struct QuotedError {
  std::string experiment, channel;
  double percent = 0.0;
};

// The job key `published:` — {source, configuration?, effects?, set?,
// relative_error_percent?: {experiment: {channel: percent}}}; `effects` and
// `set` apply to the job's model as in a model config (sim/axis_config.h
// ParseModelOverrides).
struct PublishedReference {
  bool present = false;
  std::string source;
  AxisConfig model;                     // the job's model, published values
  std::vector<std::string> parameters;  // the names the source publishes
  std::vector<QuotedError> quoted;
};

// Reads the job key `published:` of the job `file` into `out` (present set):
// its model is `problem`'s with the key's overrides (ParseModelOverrides);
// the experiments relative_error_percent names must be `problem`'s (fitted
// or validation), its channels MODEL.md §6 names. Throws
// std::invalid_argument naming file, line and key (io/yaml_util.h).
void ReadPublishedReference(const YAML::Node& node, const std::string& file,
                            const EstimationProblem& problem, PublishedReference* out);


}  // namespace axis

#endif  // REPORT_PUBLISHED_REFERENCE_H_
