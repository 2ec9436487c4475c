#include "common/format.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace axis {

std::string FormatNumber(double value, int digits, const char* nan_text) {
  if (std::isnan(value)) return nan_text;
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.*g", digits, value);
  return buf;
}

std::string OneLine(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
  }
  return s;
}

namespace {

// Length of `s` in UTF-8 code points (for column widths with "±", "σ").
size_t DisplayWidth(const std::string& s) {
  size_t n = 0;
  for (unsigned char c : s) {
    if ((c & 0xC0) != 0x80) ++n;
  }
  return n;
}

std::string Pad(const std::string& s, size_t width, bool right) {
  const size_t w = DisplayWidth(s);
  if (w >= width) return s;
  const std::string fill(width - w, ' ');
  return right ? fill + s : s + fill;
}

std::string MarkdownCell(const std::string& s) {
  std::string out;
  for (char c : OneLine(s)) {
    if (c == '|') out += '\\';
    out += c;
  }
  return out;
}
}  // namespace

std::string RenderText(const TextTable& table) {
  const size_t n = table.headers.size();
  std::vector<size_t> width(n, 0);
  for (size_t j = 0; j < n; ++j) width[j] = DisplayWidth(table.headers[j]);
  for (const auto& row : table.rows) {
    for (size_t j = 0; j < n && j < row.size(); ++j) {
      width[j] = std::max(width[j], DisplayWidth(OneLine(row[j])));
    }
  }
  auto line = [&](const std::vector<std::string>& cells) {
    std::string out;
    for (size_t j = 0; j < n; ++j) {
      const std::string cell = j < cells.size() ? OneLine(cells[j]) : "";
      const bool last = j + 1 == n;
      out += last && !table.right[j] ? cell : Pad(cell, width[j], table.right[j]);
      if (!last) out += "  ";
    }
    while (!out.empty() && out.back() == ' ') out.pop_back();
    return out + "\n";
  };
  std::string out = line(table.headers);
  size_t total = 0;
  for (size_t j = 0; j < n; ++j) total += width[j] + (j + 1 < n ? 2 : 0);
  out += std::string(total, '-') + "\n";
  for (const auto& row : table.rows) out += line(row);
  return out;
}

std::string Join(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (size_t k = 0; k < items.size(); ++k) out += (k ? separator : "") + items[k];
  return out;
}

std::string RenderMarkdown(const TextTable& table) {
  std::string out = "|";
  for (const std::string& h : table.headers) out += " " + MarkdownCell(h) + " |";
  out += "\n|";
  for (bool right : table.right) out += right ? " ---: |" : " --- |";
  out += "\n";
  for (const auto& row : table.rows) {
    out += "|";
    for (size_t j = 0; j < table.headers.size(); ++j) {
      out += " " + MarkdownCell(j < row.size() ? row[j] : "") + " |";
    }
    out += "\n";
  }
  return out;
}

}  // namespace axis
