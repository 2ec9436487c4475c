#include "io/json_log.h"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace axis {
namespace {

using Json = nlohmann::ordered_json;  // keys in file order

// What a JSON value is, for a "got …" message: "a string (\"xl330\")".
// Arrays and objects are not printed (a deeply nested one would recurse).
std::string Describe(const Json& v) {
  if (v.is_array()) return "an array of " + std::to_string(v.size()) + " element(s)";
  if (v.is_object()) return "an object";
  std::string text = v.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  if (v.is_string()) return "a string (" + text + ")";
  if (v.is_number()) return "a number (" + text + ")";
  return text;  // null, true, false
}

// v as a table value into *out: a finite number, or true/false as 1/0;
// false for anything else (the caller names the place).
bool ToValue(const Json& v, double* out) {
  if (v.is_boolean()) {
    *out = v.get<bool>() ? 1.0 : 0.0;
    return true;
  }
  if (!v.is_number()) return false;
  *out = v.get<double>();
  return std::isfinite(*out);
}

// The log's top level: constants and what is not a column.
void ReadTopLevel(const Json& root, DataTable* table) {
  for (auto it = root.begin(); it != root.end(); ++it) {
    if (it.key() == "entries") continue;
    double value = 0.0;
    if (ToValue(it.value(), &value)) table->constants.emplace_back(it.key(), value);
    table->not_columns.emplace_back(it.key(), Describe(it.value()) + " of the log itself");
  }
}

// One entry's values into the columns, every key of entries[0] and no other.
void ReadEntry(const Json& entry, size_t row, DataTable* table) {
  const std::string where = table->RowLocation(row) + ": ";
  if (!entry.is_object()) {
    throw std::invalid_argument(where + "expected an object of " +
                                std::to_string(table->names.size()) + " keys, got " +
                                Describe(entry));
  }
  for (size_t j = 0; j < table->names.size(); ++j) {
    const auto it = entry.find(table->names[j]);
    if (it == entry.end()) {
      throw std::invalid_argument(where + "expected key '" + table->names[j] +
                                  "' (every entry has the keys of entries[0]), got none");
    }
    double value = 0.0;
    if (!ToValue(*it, &value)) {
      throw std::invalid_argument(where + "key '" + table->names[j] +
                                  "': expected a finite number or true/false, got " +
                                  Describe(*it));
    }
    table->columns[j].push_back(value);
  }
  if (entry.size() != table->names.size()) {
    for (auto it = entry.begin(); it != entry.end(); ++it) {
      bool known = false;
      for (const std::string& n : table->names) known = known || n == it.key();
      if (!known) {
        throw std::invalid_argument(where + "expected only the keys of entries[0] (" +
                                    table->NameList() + "), got key '" + it.key() + "'");
      }
    }
  }
}

}  // namespace

DataTable ParseJsonLog(const std::string& text, const std::string& name) {
  DataTable table;
  table.path = name;
  table.format = DataTable::Format::kJson;
  table.column_rule = "a key of every object of entries[] (numbers or true/false)";
  Json root;
  try {
    root = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw std::invalid_argument(name + ": expected JSON text, got a parse error at byte " +
                                std::to_string(e.byte) + " (" + e.what() + ")");
  } catch (const Json::exception& e) {  // e.g. a number out of double's range
    throw std::invalid_argument(name + ": expected JSON text, got " + e.what());
  }
  if (!root.is_object()) {
    throw std::invalid_argument(name + ": expected a JSON object with an array 'entries', got " +
                                Describe(root));
  }
  const auto entries = root.find("entries");
  if (entries == root.end() || !entries->is_array()) {
    throw std::invalid_argument(
        name + ": expected an array 'entries' (one object per sample), got " +
        (entries == root.end() ? std::string("no such key") : Describe(*entries)));
  }
  if (entries->empty()) {
    throw std::invalid_argument(name + ": expected at least one object in 'entries', got none");
  }
  ReadTopLevel(root, &table);
  const Json& first = entries->front();
  if (!first.is_object() || first.empty()) {
    throw std::invalid_argument(table.RowLocation(0) +
                                ": expected an object of named values, got " + Describe(first));
  }
  for (auto it = first.begin(); it != first.end(); ++it) table.names.push_back(it.key());
  table.columns.assign(table.names.size(), {});
  for (std::vector<double>& c : table.columns) c.reserve(entries->size());
  for (size_t row = 0; row < entries->size(); ++row) ReadEntry((*entries)[row], row, &table);
  return table;
}

DataTable ReadJsonLog(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": expected a readable JSON log, got none");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw std::invalid_argument(path + ": expected a readable JSON log, got a read error");
  return ParseJsonLog(text.str(), path);
}

}  // namespace axis
