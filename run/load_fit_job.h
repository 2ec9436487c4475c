// Loading a fit job (configs/jobs/*.yaml; format: configs/README.md) and
// the quick form of fit-params: one strict loader that resolves every file,
// column and name before any work, so that fitting cannot fail on input.
#ifndef RUN_LOAD_FIT_JOB_H_
#define RUN_LOAD_FIT_JOB_H_

#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "run/fit_job.h"

namespace axis {

// The longest sample period (s) of a record LoadFitJob accepts: slower than
// 50 Hz a record sees none of a servo axis's dynamics (the 5 ms controller,
// the gear resonance, T_p: milliseconds), and it is most likely one whose
// time column is in ms (1–20 kHz records then read as periods of 1–0.05).
constexpr double kMaxSamplePeriod = 0.02;

// Loads and checks a job: all files, columns and names are resolved here, so
// that fitting cannot fail on input. An experiment's `data:` is a CSV file,
// or a MAT file if its name ends in .mat (ReadDataTable, io/data_file.h:
// variables are columns). Throws std::invalid_argument naming the file, line
// and key (YAML), file and line (CSV) or file and variable (MAT): unknown
// keys, a missing column, NaN or empty cells, time not strictly increasing,
// a sample period above kMaxSamplePeriod (time not in seconds), an empty
// file, a MAT variable that is not a vector as long as the time, a free
// parameter the model does not have, reversed bounds, an initial value
// outside its bounds, a fitted channel that is not measured, two
// experiments (fitted or validated) of the same name.
FitJob LoadFitJob(const std::string& path);

// As LoadFitJob, from a parsed YAML document; `path` names it in messages
// and relative file names are resolved against `base_dir`.
FitJob ParseFitJob(const YAML::Node& root, const std::string& path,
                   const std::string& base_dir);

// The quick form of fit-params: one experiment from `data_path` (CSV, or MAT
// if named *.mat; time column "t", every other column whose name is a
// channel is measured), open loop
// with input column `input_column`, fitting `fit_channels` each with σ the
// noise estimated from its record (common/statistics.h DifferenceNoiseSd),
// at least 1e-4 of the signal's standard deviation (a noise-free record),
// 1 for a constant channel, so that s² ≈ 1 at a fit down to the noise and the
// score tests of --discover mean what they say; each σ and how it was found
// is a note of the experiment (FitExperiment::input_notes, printed and
// reported). Frees `free_names` with initial values from the model and
// bounds [value/10, value·10]. Throws std::invalid_argument.
FitJob MakeQuickJob(const std::string& model_path, const std::string& data_path,
                    const std::string& input_column,
                    const std::vector<std::string>& fit_channels,
                    const std::vector<std::string>& free_names);

}  // namespace axis

#endif  // RUN_LOAD_FIT_JOB_H_
