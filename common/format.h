// Number formatting and text tables: the format of every text report
// (params.md, the tables on stdout, report.html, the campaign and fleet
// tables) and JSON numbers. Never throws (except std::bad_alloc).
#ifndef COMMON_FORMAT_H_
#define COMMON_FORMAT_H_

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace axis {

// "%.*g" of `digits` significant digits (1–17); `nan_text` for NaN,
// "inf"/"-inf" for infinities. The number format of every text report
// (params.md, the tables on stdout, report.html). Never throws.
std::string FormatNumber(double value, int digits = 6, const char* nan_text = "nan");

// A JSON number, or null if not finite (JSON has no NaN or infinity).
// JsonT: nlohmann::json or nlohmann::ordered_json.
template <typename JsonT = nlohmann::json>
JsonT JsonNumber(double value) {
  return std::isfinite(value) ? JsonT(value) : JsonT(nullptr);
}

// `items` joined by `separator` ("a, b, c"); "" for none. Never throws.
std::string Join(const std::vector<std::string>& items, const std::string& separator);

// A table of text cells, rendered fixed-width (params.md, the terminal) or
// as Markdown (RenderMarkdown): the header row, per column whether it is
// right-aligned (numbers), and the rows (a short row is padded with empty
// cells).
struct TextTable {
  std::vector<std::string> headers;
  std::vector<bool> right;  // one per header
  std::vector<std::vector<std::string>> rows;
};

// `table` as fixed-width text: columns padded to their widest cell, a rule
// under the header. Never throws.
std::string RenderText(const TextTable& table);

// `table` as a Markdown table: cells on one line with '|' escaped,
// right-aligned columns marked "---:". Never throws.
std::string RenderMarkdown(const TextTable& table);

// `s` with line breaks and tabs turned into spaces (one table row or
// Markdown line per value). Never throws.
std::string OneLine(std::string s);

}  // namespace axis

#endif  // COMMON_FORMAT_H_
