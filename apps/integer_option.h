// A CLI11 check for an integer option with the range of the config key it
// overrides, so that the flag refuses what the key refuses instead of
// letting CLI11 wrap or overflow the number.
#ifndef APPS_INTEGER_OPTION_H_
#define APPS_INTEGER_OPTION_H_

#include <cerrno>
#include <cstdlib>
#include <string>

#include <CLI/CLI.hpp>

namespace axis {

// Accepts the decimal integers in [min, max]; else CLI11 reports (exit 2)
// "<flag>: expected an integer in <min>..<max> (<as>), got '<text>'".
inline CLI::Validator IntegerIn(long long min, long long max, const std::string& as) {
  const std::string range = std::to_string(min) + ".." + std::to_string(max);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long x = std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || errno == ERANGE || x < min || x > max) {
          return "expected an integer in " + range + " (" + as + "), got '" + text + "'";
        }
        return "";
      },
      "INT in " + range);
}

// Accepts the decimal integers in [1, max]; else CLI11 reports (exit 2)
// "<flag>: expected a positive integer (1..<max>, <as>), got '<text>'"
// (CLI::PositiveNumber said "Value 0 not in range 0.000000 to 1.797…e308").
inline CLI::Validator PositiveInteger(long long max, const std::string& as) {
  const std::string range = "1.." + std::to_string(max);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long x = std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || *end != '\0' || errno == ERANGE || x < 1 || x > max) {
          return "expected a positive integer (" + range + ", " + as + "), got '" + text + "'";
        }
        return "";
      },
      "INT in " + range);
}

}  // namespace axis

#endif  // APPS_INTEGER_OPTION_H_
