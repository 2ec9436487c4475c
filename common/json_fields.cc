#include "common/json_fields.h"

#include <limits>
#include <stdexcept>

namespace axis {
namespace {

std::string Shown(const nlohmann::json& v) { return v.dump().substr(0, 60); }

}  // namespace

const nlohmann::json& JsonField(const nlohmann::json& json, const std::string& key,
                                const std::string& where, nlohmann::json::value_t type,
                                const char* expected) {
  if (!json.is_object() || !json.contains(key)) {
    throw std::invalid_argument(where + ": expected a key '" + key + "', got none");
  }
  const nlohmann::json& v = json.at(key);
  const bool number = type == nlohmann::json::value_t::number_float;
  const bool integer = type == nlohmann::json::value_t::number_integer;
  const bool ok = number    ? (v.is_number() || v.is_null())
                  : integer ? v.is_number_integer()
                            : v.type() == type;
  if (!ok) {
    throw std::invalid_argument(where + "." + key + ": expected " + expected + ", got " +
                                Shown(v));
  }
  return v;
}

std::string JsonStringField(const nlohmann::json& json, const std::string& key,
                            const std::string& where) {
  return JsonField(json, key, where, nlohmann::json::value_t::string, "a string")
      .get<std::string>();
}

double JsonNumberField(const nlohmann::json& json, const std::string& key,
                       const std::string& where) {
  const nlohmann::json& v =
      JsonField(json, key, where, nlohmann::json::value_t::number_float, "a number or null");
  return v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>();
}

bool JsonBoolField(const nlohmann::json& json, const std::string& key, const std::string& where) {
  return JsonField(json, key, where, nlohmann::json::value_t::boolean, "true or false")
      .get<bool>();
}

int JsonIntField(const nlohmann::json& json, const std::string& key, const std::string& where) {
  const nlohmann::json& v =
      JsonField(json, key, where, nlohmann::json::value_t::number_integer, "an integer");
  const bool fits = v.is_number_unsigned()
                        ? v.get<unsigned long long>() <=
                              static_cast<unsigned long long>(std::numeric_limits<int>::max())
                        : v.get<long long>() >= std::numeric_limits<int>::min() &&
                              v.get<long long>() <= std::numeric_limits<int>::max();
  if (!fits) {
    throw std::invalid_argument(where + "." + key + ": expected an integer of at most " +
                                std::to_string(std::numeric_limits<int>::max()) +
                                " in magnitude, got " + Shown(v));
  }
  return v.get<int>();
}

const nlohmann::json& JsonArrayField(const nlohmann::json& json, const std::string& key,
                                     const std::string& where) {
  return JsonField(json, key, where, nlohmann::json::value_t::array, "a list");
}

std::vector<std::string> JsonStrings(const nlohmann::json& json, const std::string& key,
                                     const std::string& where) {
  std::vector<std::string> out;
  const nlohmann::json& list = JsonArrayField(json, key, where);
  for (size_t k = 0; k < list.size(); ++k) {
    if (!list[k].is_string()) {
      throw std::invalid_argument(where + "." + key + "[" + std::to_string(k) +
                                  "]: expected a string, got " + Shown(list[k]));
    }
    out.push_back(list[k].get<std::string>());
  }
  return out;
}

std::vector<double> JsonNumbers(const nlohmann::json& json, const std::string& key,
                                const std::string& where) {
  std::vector<double> out;
  const nlohmann::json& list = JsonArrayField(json, key, where);
  for (size_t k = 0; k < list.size(); ++k) {
    if (list[k].is_null()) {
      out.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    if (!list[k].is_number()) {
      throw std::invalid_argument(where + "." + key + "[" + std::to_string(k) +
                                  "]: expected a number or null, got " + Shown(list[k]));
    }
    out.push_back(list[k].get<double>());
  }
  return out;
}

}  // namespace axis
