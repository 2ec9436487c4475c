// The job key `published:` (the EMPS benchmark, issue 5): a published
// reference model to set beside the fit; the comparison itself is
// report/published.h.
#ifndef JOB_PUBLISHED_REFERENCE_H_
#define JOB_PUBLISHED_REFERENCE_H_

#include <string>
#include <vector>

#include "sim/config.h"

namespace axis {

// A relative error the source quotes for one channel of one experiment (%).
struct QuotedError {
  std::string experiment, channel;
  double percent = 0.0;
};

// The job key `published:` — {source, configuration?, effects?, set?,
// relative_error_percent?: {experiment: {channel: percent}}}; `effects` and
// `set` apply to the job's model as in a model config (sim/config.h
// ParseModelOverrides).
struct PublishedReference {
  bool present = false;
  std::string source;
  AxisConfig model;                     // the job's model, published values
  std::vector<std::string> parameters;  // the names the source publishes
  std::vector<QuotedError> quoted;
};


}  // namespace axis

#endif  // JOB_PUBLISHED_REFERENCE_H_
