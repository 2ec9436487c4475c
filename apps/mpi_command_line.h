// The command line of an MPI app (fit-fleet, fit-campaign): every rank
// parses it, only rank 0 prints help or errors (CLI11's App::exit).
#ifndef APPS_MPI_COMMAND_LINE_H_
#define APPS_MPI_COMMAND_LINE_H_

#include <optional>

#include <CLI/CLI.hpp>

namespace axis {

// Parses argc/argv with `app`. Returns no value when the app should go on,
// else its exit code: 0 after --help, 2 for a bad command line (rank 0 has
// printed the message).
inline std::optional<int> ParseOnEveryRank(CLI::App& app, int argc, char** argv, int rank) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (rank != 0) return e.get_exit_code() == 0 ? 0 : 2;
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  return std::nullopt;
}

}  // namespace axis

#endif  // APPS_MPI_COMMAND_LINE_H_
