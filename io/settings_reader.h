// One generic loader for settings structs, in the manner of Drake's
// yaml_read_archive (common/yaml/yaml_read_archive.h): a settings struct
// names its keys once, in a member
//
//   template <typename Archive> void Serialize(Archive* a) {
//     a->Visit("max_iterations", &max_iterations, 1, 100000);
//     a->Visit("first_horizon", &first_horizon, YamlMap::Range::kNonNegative);
//   }
//
// and ReadSettings reads each key that is present into its field, leaving
// the others at their values (the struct's defaults, or what the caller set
// before). The rules and messages are those of YamlMap (io/yaml_util.h):
// "<file>:<line>: key '<prefix><key>': expected <what>, got <value>", thrown
// as std::invalid_argument. ReadSettings does not call YamlMap::Finish: a
// loader may read further keys by hand (a list, a nested mapping) and then
// finish the map itself.
#ifndef IO_SETTINGS_READER_H_
#define IO_SETTINGS_READER_H_

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io/yaml_util.h"

namespace axis {

// The archive ReadSettings hands to a struct's Serialize: one Visit per key.
class SettingsReader {
 public:
  explicit SettingsReader(YamlMap* map) : map_(map) {}

  // An integer in [min, max] (YamlMap::Integer).
  void Visit(const char* key, int* value, long min, long max) {
    *value = static_cast<int>(map_->Integer(key, *value, min, max));
  }
  // A seed in [min, max] (YamlMap::Integer).
  void Visit(const char* key, std::uint64_t* value, long min, long max) {
    *value = static_cast<std::uint64_t>(map_->Integer(key, static_cast<long>(*value), min, max));
  }
  // A number in `range` (YamlMap::Number: finite unless the range opts in
  // to infinity).
  void Visit(const char* key, double* value, YamlMap::Range range) {
    *value = map_->Number(key, *value, range);
  }
  // `false` or `true` (YamlMap::Choice).
  void Visit(const char* key, bool* value) {
    *value = map_->Choice(key, {"false", "true"}, *value ? "true" : "false") == "true";
  }
  // One of the names of an enumeration, in the order the message lists
  // them (YamlMap::Choice).
  template <typename Enum>
  void Visit(const char* key, Enum* value,
             const std::vector<std::pair<std::string, Enum>>& names) {
    std::vector<std::string> choices;
    std::string current;
    for (const auto& [name, e] : names) {
      choices.push_back(name);
      if (e == *value) current = name;
    }
    const std::string chosen = map_->Choice(key, choices, current);
    for (const auto& [name, e] : names) {
      if (name == chosen) *value = e;
    }
  }

  YamlMap& map() { return *map_; }

 private:
  YamlMap* map_;
};

// Reads the keys `settings->Serialize` names from `map` into `settings`.
// Throws std::invalid_argument as YamlMap does (file, line and key).
template <typename Settings>
void ReadSettings(YamlMap* map, Settings* settings) {
  SettingsReader reader(map);
  settings->Serialize(&reader);
}

}  // namespace axis

#endif  // IO_SETTINGS_READER_H_
