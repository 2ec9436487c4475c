// A small Monte Carlo campaign written into a test's folder, for the
// campaign tests (tests/campaign_test.cc, tests/fleet_campaign_test.cc): a
// 0.4 s sine record of the X axis (configs/axes/x_axis.yaml, noise as in
// testdata) and a job fitting B_a alone on it.
#ifndef TESTS_CAMPAIGN_FILES_H_
#define TESTS_CAMPAIGN_FILES_H_

#include <string>

#include "run/campaign.h"
#include "tests/test_files.h"

namespace axis {
namespace campaign_files {

// Writes sine.yaml (the generating config), job.yaml and campaign.yaml into
// the test's folder; campaign.yaml is `campaign` (seeds, truth, output, …)
// with the job and generator keys prepended. Returns campaign.yaml's path.
inline std::string WriteCampaign(const std::string& campaign) {
  const std::string root = PROJECT_SOURCE_DIR;
  testing_files::WriteTemp(
      "sine.yaml", "model: " + root + "/configs/axes/x_axis.yaml\n"
                   "duration: 0.4\nstep: 1.0e-5\noutput_rate: 1000\n"
                   "channels: [u, a, tach]\nnoise: {a: 0.02, tach: 0.005}\nseed: 7\n"
                   "input: {type: sine, amplitude: 3, frequency: 2}\n");
  testing_files::WriteTemp(
      "job.yaml", "model: " + root + "/configs/axes/x_axis.yaml\n"
                  "free:\n  B_a: {initial: 150, lower: 10, upper: 2000}\n"
                  "experiments:\n  - name: sine\n    data: replaced.csv\n"
                  "    channels: {u: u, a: a, tach: tach}\n    input: {column: u}\n"
                  "    fit: {a: 0.02, tach: 0.005}\n"
                  "uncertainty: {method: gauss_newton}\n");
  return testing_files::WriteTemp("campaign.yaml",
                                  "job: job.yaml\ngenerate: {sine: sine.yaml}\n" + campaign);
}

}  // namespace campaign_files
}  // namespace axis

#endif  // TESTS_CAMPAIGN_FILES_H_
