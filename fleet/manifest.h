// A fleet manifest (configs/fleet/*.yaml; format in configs/README.md,
// section 5): the jobs of one fleet run of fit-fleet (issue 12). Jobs are
// explicit fit-job files, and/or one job template applied to every log (data
// file) of every axis, an axis being one model config and its logs. One
// strict loader in the style of the other formats (io/yaml_util.h).
//
// The manifest is checked when loaded; the jobs themselves (the job files,
// the template filled in, the data) are loaded only when they run
// (MakeFleetJob), so that a broken job fails alone and the others complete.
#ifndef FLEET_MANIFEST_H_
#define FLEET_MANIFEST_H_

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "run/fit_job.h"

namespace axis {

// One job of the fleet: one log of one axis.
struct FleetEntry {
  std::string axis;        // e.g. "r01/x": letters, digits, '_', '-', '.', '/' between parts
  std::string log;         // e.g. "now": the data file's stem (template) or `log:` / the job file's stem
  std::string job_path;    // an explicit job file; empty for a template entry
  std::string model_path;  // template entry: the axis's model config
  std::string data_path;   // template entry: the log's data file (may be missing or broken)
  // The expected relative cost, to run the longest first: bytes of data
  // (CSV or MAT) × (solver.starts + 1) × 4 with discovery; 0 if unknown.
  double expected_cost = 0.0;
  // The job's output folder below the fleet's: "<axis>/<log>".
  std::string Folder() const { return axis + "/" + log; }
};

struct FleetManifest {
  std::string path;            // the manifest file (for messages)
  std::string title;           // `title:`, default the path
  std::string template_path;   // `template:`, empty if none
  YAML::Node template_root;    // the template, loaded and checked (if any)
  std::vector<FleetEntry> entries;  // `axes:` (each log in glob order), then `jobs:`
  int threads = 1;             // Ceres threads per job (solver.threads overridden)
  bool discover = false;       // run the discovery loop on every job (as --discover)
  // Family-wise level of the --baseline change tests (fleet/fleet_table.h).
  double alpha = 0.05;
  std::string out_dir;         // `output.dir`, relative to the manifest; --out overrides
};

// Loads and checks a manifest. Throws std::invalid_argument
// "<file>:<line>: key '<path>': expected <what>, got <value>" (unknown,
// duplicate or missing keys, a bad axis or log name, a glob matching no
// file, an (axis, log) pair twice, a template with `model:`, `output:`,
// `validate:`, or other than one `experiments:` entry without `data:`),
// and "<file>: cannot read" for a manifest or template that cannot be read.
// Relative paths resolve against the manifest's folder (the template's own
// relative paths against the template's).
FleetManifest LoadFleetManifest(const std::string& path);

// As LoadFleetManifest, from a parsed document; `path` names it in
// messages, relative paths resolve against `base_dir`.
FleetManifest ParseFleetManifest(const YAML::Node& root, const std::string& path,
                                 const std::string& base_dir);

// The fit job of `entry`: its job file (LoadFitJob), or the template with
// `model:` set to the axis's model config, the experiment's `data:` to the
// log and the title prefixed with "<axis> <log>: " (ParseFitJob); then
// solver.threads = manifest.threads, no solver progress lines, out_dir =
// `out_dir`/<axis>/<log>. Throws std::invalid_argument as LoadFitJob (a
// missing or malformed data file, a bad job).
FitJob MakeFleetJob(const FleetManifest& manifest, const FleetEntry& entry,
                    const std::string& out_dir);

}  // namespace axis

#endif  // FLEET_MANIFEST_H_
