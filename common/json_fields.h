// Checked reads of JSON documents this project writes and reads back
// (fleet rows between MPI ranks and in fleet.json, campaign seed outcomes
// between ranks): each reader takes the key and a `where` prefix naming the
// document, and throws std::invalid_argument "WHERE.KEY: expected …, got …"
// (the value shown truncated to 60 characters) or "WHERE: expected a key
// 'KEY', got none". Numbers are read as JSON writes them: a number, or null
// for NaN (JsonNumber in report/report.h writes non-finite values as null).
// Library: nlohmann::json (https://json.nlohmann.me).
#ifndef COMMON_JSON_FIELDS_H_
#define COMMON_JSON_FIELDS_H_

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace axis {

// The value at `key` of the object `json`, checked to be of `type` (for
// value_t::number_float: any number or null); `expected` names the kind in
// the message. Throws std::invalid_argument if `json` is not an object, has
// no `key`, or the value is of another kind.
const nlohmann::json& JsonField(const nlohmann::json& json, const std::string& key,
                                const std::string& where, nlohmann::json::value_t type,
                                const char* expected);

// JsonField of each kind. JsonNumberField: NaN for null.
std::string JsonStringField(const nlohmann::json& json, const std::string& key,
                            const std::string& where);
double JsonNumberField(const nlohmann::json& json, const std::string& key,
                       const std::string& where);
bool JsonBoolField(const nlohmann::json& json, const std::string& key, const std::string& where);
// Any integer (signed or unsigned JSON integer) that fits an int.
int JsonIntField(const nlohmann::json& json, const std::string& key, const std::string& where);
const nlohmann::json& JsonArrayField(const nlohmann::json& json, const std::string& key,
                                     const std::string& where);

// A list at `key` whose every element is a string / a number or null (NaN).
// The message of a bad element names it: "WHERE.KEY[K]: expected …, got …".
std::vector<std::string> JsonStrings(const nlohmann::json& json, const std::string& key,
                                     const std::string& where);
std::vector<double> JsonNumbers(const nlohmann::json& json, const std::string& key,
                                const std::string& where);

}  // namespace axis

#endif  // COMMON_JSON_FIELDS_H_
