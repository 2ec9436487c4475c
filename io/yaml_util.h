// Strict reading of YAML mappings for the config loaders: every key must be
// known, required keys must be present, values must have the expected type
// and range. Errors are std::invalid_argument with the message
//   "<file>:<line>: key '<path>': expected <what>, got <value>"
// so that a user can find the offending line.
#ifndef IO_YAML_UTIL_H_
#define IO_YAML_UTIL_H_

#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace axis {

// Loads a YAML file. Throws std::invalid_argument "<file>: cannot read",
// "<file>:<line>: invalid YAML: <reason>", CheckUtf8Text's error for a file
// that is not UTF-8 text (io/internal/utf8_text.h), "<file>:<line>: expected one
// YAML document, got a second one ('---') …" (the loaders read the first
// and ignored the rest), or, for a key repeated in any mapping of the
// document (yaml-cpp keeps both; the loaders would read one and ignore the
// other) or a merge key '<<' (yaml-cpp merges nothing), CheckUniqueKeys'
// error.
YAML::Node LoadYamlFile(const std::string& file);

// As LoadYamlFile, from YAML text held in memory; `name` stands for the file
// in messages.
YAML::Node ParseYamlText(const std::string& text, const std::string& name);

// Throws std::invalid_argument "<file>:<line>: key '<path>': expected each
// key once in a mapping, got '<key>' again (first on line N)" for the first
// key repeated in `node` or any mapping below it, and "<file>:<line>: key
// '<path><<': expected no YAML merge key (not supported: write the keys
// out), got '<<' (a merge key)" for an unquoted '<<' key. `prefix` is the
// key path of `node` ("" at top level).
void CheckUniqueKeys(const YAML::Node& node, const std::string& file,
                     const std::string& prefix);

// Throws std::invalid_argument "<file>:<line>: key '<key>': expected
// <expected>, got <got>" with the line of `node` (1-based).
[[noreturn]] void ThrowConfigError(const std::string& file,
                                   const YAML::Node& node,
                                   const std::string& key,
                                   const std::string& expected,
                                   const std::string& got);

// The text of a scalar node, or a short description of a non-scalar one.
std::string Describe(const YAML::Node& node);

// A mapping that must be read completely: call Finish() after reading the
// keys; it throws on any key nobody asked for ("unknown key").
class YamlMap {
 public:
  // `node` must be a mapping, else throws. `prefix` is the key path of the
  // mapping ("" at top level, "controller." inside controller).
  YamlMap(const YAML::Node& node, std::string file, std::string prefix);

  bool Has(const std::string& key) const;
  // The child node; throws if missing ("expected a value, got nothing").
  YAML::Node Required(const std::string& key);
  // The child node or an undefined node if absent.
  YAML::Node Optional(const std::string& key);

  // Numbers. A number is finite (NaN, .inf and -.inf are refused) unless
  // its range opts in to infinity, and `range` is checked: kAny, kPositive
  // (> 0), kNonNegative (≥ 0), kPositiveOrInfinite (> 0 or .inf: a limit
  // whose documentation says .inf means none, V_L). kFinitePositive is
  // kPositive (from before numbers were finite by default).
  enum class Range {
    kAny,
    kPositive,
    kNonNegative,
    kPositiveOrInfinite,
    kFinitePositive = kPositive,
  };
  double Number(const std::string& key, Range range = Range::kAny);
  double Number(const std::string& key, double fallback,
                Range range = Range::kAny);
  long Integer(const std::string& key, long fallback, long min, long max);
  std::string String(const std::string& key);
  std::string String(const std::string& key, const std::string& fallback);
  // One of `choices`; error lists them.
  std::string Choice(const std::string& key,
                     const std::vector<std::string>& choices);
  std::string Choice(const std::string& key,
                     const std::vector<std::string>& choices,
                     const std::string& fallback);

  // Throws on the first key that was never asked for, listing the known ones.
  void Finish() const;

  const std::string& file() const { return file_; }
  const std::string& prefix() const { return prefix_; }
  const YAML::Node& node() const { return node_; }
  // Key path for messages: prefix + key.
  std::string KeyPath(const std::string& key) const { return prefix_ + key; }
  // Reads a number from any node (used for sequences); same range rules.
  double NumberFrom(const YAML::Node& value, const std::string& key_path,
                    Range range) const;

 private:
  YAML::Node node_;
  std::string file_;
  std::string prefix_;
  std::set<std::string> used_;
};

// Whether `x` is in `range` (NaN never is), and what the range expects, as
// messages say it ("a finite number >= 0"): the rule of YamlMap::Number, for
// checks made after parsing (ValidateAxisConfig).
bool InRange(double x, YamlMap::Range range);
const char* RangeText(YamlMap::Range range);

// `x` as a std::ostream prints it by default (6 significant digits), for
// the "got …" of messages.
std::string NumberText(double x);

// Directory part of a path ("." if none), and `relative` resolved against it
// (absolute paths are kept).
std::string DirectoryOf(const std::string& path);
std::string ResolvePath(const std::string& base_dir,
                        const std::string& relative);

// The key `dir` of the output block `output` (output.dir of a job, a
// campaign or a fleet manifest), resolved against `base_dir` (ResolvePath).
// Throws std::invalid_argument as YamlMap::String, and "<file>:<line>: key
// 'output.dir': expected a folder path (relative to the file's folder, or
// absolute), got '' …" for an empty or blank path (it resolved to the
// file's own folder, while --out "" is refused).
std::string OutputDirectory(YamlMap* output, const std::string& base_dir);

}  // namespace axis

#endif  // IO_YAML_UTIL_H_
