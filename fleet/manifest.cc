#include "fleet/manifest.h"

#include <glob.h>

#include <filesystem>
#include <map>
#include <stdexcept>
#include <utility>

#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "io/yaml_util.h"

namespace axis {
namespace {

namespace fs = std::filesystem;
using Range = YamlMap::Range;

bool NameChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
         c == '_' || c == '-' || c == '.';
}

// One path segment: NameChar only, not "." or "..", not empty.
bool IsSegment(const std::string& s) {
  if (s.empty() || s == "." || s == "..") return false;
  for (char c : s) {
    if (!NameChar(c)) return false;
  }
  return true;
}

// Segments separated by single '/'.
bool IsAxisName(const std::string& s) {
  size_t start = 0;
  while (true) {
    const size_t slash = s.find('/', start);
    if (!IsSegment(s.substr(start, slash == std::string::npos ? std::string::npos
                                                              : slash - start))) {
      return false;
    }
    if (slash == std::string::npos) return true;
    start = slash + 1;
  }
}

const char* kAxisExpected =
    "an axis name: parts of letters, digits, '_', '-', '.' separated by '/' (e.g. r01/x)";
const char* kLogExpected = "a log name of letters, digits, '_', '-', '.' (e.g. now)";

std::string Stem(const std::string& path) { return fs::path(path).stem().string(); }

bool HasGlobCharacters(const std::string& s) {
  return s.find_first_of("*?[") != std::string::npos;
}

// The files a `data:` item names: the path itself, or the files its glob
// pattern matches (sorted); a pattern matching none is an error.
std::vector<std::string> ExpandData(const std::string& file, const YAML::Node& node,
                                    const std::string& key, const std::string& base_dir) {
  if (!node.IsScalar() || node.Scalar().empty()) {
    ThrowConfigError(file, node, key, "a data file path or glob pattern", Describe(node));
  }
  const std::string path = ResolvePath(base_dir, node.Scalar());
  if (!HasGlobCharacters(node.Scalar())) return {path};
  glob_t matches{};
  const int status = glob(path.c_str(), 0, nullptr, &matches);
  std::vector<std::string> out;
  if (status == 0) {
    for (size_t k = 0; k < matches.gl_pathc; ++k) out.emplace_back(matches.gl_pathv[k]);
  }
  globfree(&matches);
  if (out.empty()) {
    ThrowConfigError(file, node, key, "a glob pattern matching at least one file",
                     "'" + node.Scalar() + "' (" + path + ": no match)");
  }
  return out;
}

// Bytes of `path`, 0 if it cannot be read.
double FileBytes(const std::string& path) {
  std::error_code error;
  const auto size = fs::file_size(path, error);
  return error ? 0.0 : static_cast<double>(size);
}

// solver.starts + 1 of a job document, read leniently (the strict reading
// is ParseFitJob's, when the job runs); 1 if absent or not an integer.
double StartCount(const YAML::Node& job) {
  try {
    if (job.IsMap() && job["solver"].IsMap() && job["solver"]["starts"].IsScalar()) {
      return 1.0 + std::max(0, job["solver"]["starts"].as<int>());
    }
  } catch (const YAML::Exception&) {
  }
  return 1.0;
}

// The cost factor of a job document: starts, × 4 with discovery (the
// manifest's `discover: true` or the job's `discover:`, even empty).
double CostFactor(const YAML::Node& job, bool discover) {
  const bool discovers = discover || (job.IsMap() && job["discover"].IsDefined());
  return StartCount(job) * (discovers ? 4.0 : 1.0);
}

// The expected cost of an explicit job file: its data files' bytes ×
// starts, read leniently; 0 if the file cannot be read.
double JobFileCost(const std::string& job_path, bool discover) {
  YAML::Node job;
  try {
    job = YAML::LoadFile(job_path);
  } catch (const YAML::Exception&) {
    return 0.0;
  }
  if (!job.IsMap()) return 0.0;
  double bytes = 0.0;
  for (const char* list : {"experiments", "validate"}) {
    if (!job[list].IsSequence()) continue;
    for (const YAML::Node& e : job[list]) {
      if (e.IsMap() && e["data"].IsScalar()) {
        bytes += FileBytes(ResolvePath(DirectoryOf(job_path), e["data"].Scalar()));
      }
    }
  }
  return bytes * CostFactor(job, discover);
}

// Checks the template: a fit job without `model:`, `output:`, `validate:`,
// with exactly one `experiments:` entry and no `data:` in it.
void CheckTemplate(const YAML::Node& root, const std::string& file) {
  if (!root.IsMap()) {
    ThrowConfigError(file, root, "(top level)", "a fit job template (a mapping)", Describe(root));
  }
  for (const char* key : {"model", "output", "validate"}) {
    if (root[key].IsDefined()) {
      ThrowConfigError(file, root[key], key,
                       std::string("no '") + key +
                           "' in a job template (the manifest gives the model of each axis, "
                           "its logs and the output folder)",
                       "'" + std::string(key) + "'");
    }
  }
  const YAML::Node experiments = root["experiments"];
  if (!experiments.IsSequence() || experiments.size() != 1 || !experiments[0].IsMap()) {
    ThrowConfigError(file, experiments.IsDefined() ? experiments : root, "experiments",
                     "exactly one experiment entry (applied to each log of each axis)",
                     experiments.IsDefined() ? Describe(experiments) : "nothing");
  }
  if (experiments[0]["data"].IsDefined()) {
    ThrowConfigError(file, experiments[0]["data"], "experiments[0].data",
                     "no 'data' in a job template (each log of the manifest's axes is one)",
                     Describe(experiments[0]["data"]));
  }
}

// An entry of `axes:`; its logs appended to *entries.
void ParseAxis(const YAML::Node& node, const std::string& file, const std::string& prefix,
               const std::string& base_dir, double cost_factor,
               std::vector<std::pair<FleetEntry, YAML::Node>>* entries) {
  YamlMap map(node, file, prefix);
  const YAML::Node axis_node = map.Required("axis");
  const std::string axis = map.String("axis");
  if (!IsAxisName(axis)) ThrowConfigError(file, axis_node, prefix + "axis", kAxisExpected, Describe(axis_node));
  const std::string model = ResolvePath(base_dir, map.String("model"));
  const YAML::Node data = map.Required("data");
  std::vector<std::string> files;
  if (data.IsSequence()) {
    if (data.size() == 0) {
      ThrowConfigError(file, data, prefix + "data", "at least one data file", "an empty list");
    }
    for (size_t k = 0; k < data.size(); ++k) {
      for (std::string& f : ExpandData(file, data[k], prefix + "data[" + std::to_string(k) + "]",
                                       base_dir)) {
        files.push_back(std::move(f));
      }
    }
  } else {
    files = ExpandData(file, data, prefix + "data", base_dir);
  }
  map.Finish();
  for (const std::string& f : files) {
    FleetEntry e;
    e.axis = axis;
    e.log = Stem(f);
    if (!IsSegment(e.log)) {
      ThrowConfigError(file, data, prefix + "data",
                       std::string("data files whose names make ") + kLogExpected,
                       "'" + f + "'");
    }
    e.model_path = model;
    e.data_path = f;
    e.expected_cost = FileBytes(f) * cost_factor;
    entries->emplace_back(std::move(e), data);
  }
}

}  // namespace

FleetManifest LoadFleetManifest(const std::string& path) {
  return ParseFleetManifest(LoadYamlFile(path), path, DirectoryOf(path));
}

FleetManifest ParseFleetManifest(const YAML::Node& root, const std::string& path,
                                 const std::string& base_dir) {
  FleetManifest m;
  m.path = path;
  YamlMap map(root, path, "");
  map.Optional("description");
  m.title = map.String("title", path);
  m.threads = static_cast<int>(map.Integer("threads", 1, 1, 256));
  if (const YAML::Node d = map.Optional("discover")) {
    if (!d.IsScalar() || (d.Scalar() != "true" && d.Scalar() != "false")) {
      ThrowConfigError(path, d, "discover", "true or false", Describe(d));
    }
    m.discover = d.Scalar() == "true";
  }
  m.alpha = map.Number("alpha", 0.05, Range::kFinitePositive);
  if (m.alpha >= 1.0) {
    ThrowConfigError(path, map.Optional("alpha"), "alpha", "a level in (0, 1)",
                     Describe(map.Optional("alpha")));
  }
  if (map.Has("template")) {
    m.template_path = ResolvePath(base_dir, map.String("template"));
    m.template_root = LoadYamlFile(m.template_path);
    CheckTemplate(m.template_root, m.template_path);
  }

  std::vector<std::pair<FleetEntry, YAML::Node>> entries;  // with the node that made each
  if (const YAML::Node axes = map.Optional("axes")) {
    if (!axes.IsSequence() || axes.size() == 0) {
      ThrowConfigError(path, axes, "axes",
                       "a non-empty list of {axis, model, data} entries", Describe(axes));
    }
    if (m.template_path.empty()) {
      ThrowConfigError(path, axes, "axes",
                       "a 'template' key beside 'axes' (the job applied to their logs)",
                       "no template");
    }
    const double factor = CostFactor(m.template_root, m.discover);
    for (size_t k = 0; k < axes.size(); ++k) {
      ParseAxis(axes[k], path, "axes[" + std::to_string(k) + "].", base_dir, factor, &entries);
    }
  } else if (!m.template_path.empty()) {
    ThrowConfigError(path, map.Optional("template"), "template",
                     "an 'axes' list beside 'template' (the axes it applies to)", "no axes");
  }
  if (const YAML::Node jobs = map.Optional("jobs")) {
    if (!jobs.IsSequence() || jobs.size() == 0) {
      ThrowConfigError(path, jobs, "jobs", "a non-empty list of {axis, job, log} entries",
                       Describe(jobs));
    }
    for (size_t k = 0; k < jobs.size(); ++k) {
      const std::string prefix = "jobs[" + std::to_string(k) + "].";
      YamlMap job(jobs[k], path, prefix);
      FleetEntry e;
      const YAML::Node axis_node = job.Required("axis");
      e.axis = job.String("axis");
      if (!IsAxisName(e.axis)) ThrowConfigError(path, axis_node, prefix + "axis", kAxisExpected, Describe(axis_node));
      e.job_path = ResolvePath(base_dir, job.String("job"));
      const YAML::Node log_node = job.Optional("log");
      e.log = job.String("log", Stem(e.job_path));
      if (!IsSegment(e.log)) {
        ThrowConfigError(path, log_node ? log_node : job.Required("job"), prefix + "log",
                         kLogExpected, "'" + e.log + "'");
      }
      job.Finish();
      e.expected_cost = JobFileCost(e.job_path, m.discover);
      entries.emplace_back(std::move(e), jobs[k]);
    }
  }
  if (entries.empty()) {
    ThrowConfigError(path, root, "axes",
                     "at least one job: an 'axes' list with a 'template', or a 'jobs' list",
                     "none");
  }
  std::map<std::pair<std::string, std::string>, int> seen;  // (axis, log) -> line
  for (auto& [entry, node] : entries) {
    const auto key = std::make_pair(entry.axis, entry.log);
    const int line = node.Mark().line + 1;
    const auto [it, inserted] = seen.emplace(key, line);
    if (!inserted) {
      ThrowConfigError(path, node, "axes/jobs",
                       "each axis and log once (one output folder each)",
                       "axis '" + entry.axis + "' log '" + entry.log + "' again (first on line " +
                           std::to_string(it->second) + ")");
    }
    m.entries.push_back(std::move(entry));
  }
  if (const YAML::Node output = map.Optional("output")) {
    YamlMap out(output, path, "output.");
    m.out_dir = OutputDirectory(&out, base_dir);
    out.Finish();
  }
  map.Finish();
  return m;
}

FitJob MakeFleetJob(const FleetManifest& manifest, const FleetEntry& entry,
                    const std::string& out_dir) {
  FitJob job;
  if (!entry.job_path.empty()) {
    job = LoadFitJob(entry.job_path);
  } else {
    // Read afresh, not YAML::Clone'd: a clone loses the line marks that the
    // job's error messages name ("template.yaml:11: key …").
    YAML::Node root = LoadYamlFile(manifest.template_path);
    // Absolute: ParseFitJob resolves relative paths against the template's folder.
    root["model"] = fs::absolute(entry.model_path).string();
    root["experiments"][0]["data"] = fs::absolute(entry.data_path).string();
    const std::string title =
        root["title"].IsScalar() ? root["title"].Scalar() : std::string("fleet job");
    root["title"] = entry.axis + " " + entry.log + ": " + title;
    job = ParseFitJob(root, manifest.template_path, DirectoryOf(manifest.template_path));
  }
  job.problem.solver.threads = manifest.threads;
  job.problem.solver.progress = false;
  job.out_dir = out_dir + "/" + entry.Folder();
  return job;
}

}  // namespace axis
