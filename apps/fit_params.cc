// fit-params JOB.yaml [--out DIR] [--discover]
// fit-params --model M.yaml --data D.csv --input u --fit a,tach
//            --free V_L,B_a,b_g,k_g,T_p [--out DIR]
//
// Estimates the free parameters of a model from recorded traces (estimation/fit.h).
// Exit codes: 0 success, 2 bad input (command line, job, data), 1 other,
// 130/143 interrupted by SIGINT/SIGTERM (nothing written; io/interrupt.h).
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <iostream>
#include <stdexcept>

#include <CLI/CLI.hpp>
#include <glog/logging.h>

#include "common/allocator.h"
#include "common/progress.h"
#include "run/fit_params.h"
#include "io/interrupt.h"

int main(int argc, char** argv) {
  axis::KeepFreedMemory();  // common/allocator.h: a fit reuses its buffers
  // Ceres logs through glog; fit-params reports solver trouble itself
  // (termination message, undetermined parameters), so only fatal messages.
  axis::InstallInterruptHandlers("fit-params");
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;
  CLI::App app{"Estimate servo-axis parameters from recorded traces"};
  axis::FitParamsOptions options;
  app.add_option("job", options.job_path, "fit job YAML file");
  app.add_option("--model", options.model_path, "model config (quick form)");
  app.add_option("--data", options.data_path, "data CSV, or MAT file *.mat (quick form)");
  app.add_option("--input", options.input_column, "input column (quick form)");
  app.add_option("--fit", options.fit_channels, "fitted channels (quick form)")
      ->delimiter(',');
  app.add_option("--free", options.free_names, "free parameters (quick form)")
      ->delimiter(',');
  app.add_option("--out", options.out_dir, "output directory");
  app.add_flag("--discover", options.discover,
               "after the fit, find and add the effects the residual asks for");
  try {
    app.parse(argc, argv);
    const bool quick = !options.model_path.empty() || !options.data_path.empty();
    if (options.job_path.empty() == !quick) {
      throw CLI::ValidationError(
          "expected either JOB.yaml or --model/--data/--input/--fit/--free");
    }
    if (quick && (options.model_path.empty() || options.data_path.empty() ||
                  options.input_column.empty() || options.fit_channels.empty() ||
                  options.free_names.empty())) {
      throw CLI::ValidationError(
          "the quick form needs --model, --data, --input, --fit and --free");
    }
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  // On a terminal the progress is one updating line; in a pipe or a file,
  // plain lines (common/progress.h).
  options.progress_columns = axis::TerminalColumns(STDOUT_FILENO);
  try {
    axis::RunFitParams(options, std::cout, std::cerr);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "fit-params: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fit-params: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
