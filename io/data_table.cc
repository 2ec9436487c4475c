#include "io/data_table.h"

#include <cctype>
#include <filesystem>
#include <stdexcept>
#include <string>


namespace axis {

size_t DataTable::num_rows() const {
  return columns.empty() ? 0 : columns.front().size();
}

std::string DataTable::NameList() const {
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return list.empty() ? "(no " + ColumnWord() + "s)" : list;
}

std::string DataTable::ColumnWord() const {
  switch (format) {
    case Format::kMat:
      return "variable";
    case Format::kJson:
      return "key";
    case Format::kCsv:
      break;
  }
  return "column";
}

std::string DataTable::RowLocation(size_t row) const {
  if (format == Format::kMat) return path + ": sample " + std::to_string(row + 1);
  if (format == Format::kJson) return path + ": entries[" + std::to_string(row) + "]";
  return path + ":" + std::to_string(row + 2);
}

std::string DataTable::ColumnExpectation() const {
  return "a " + ColumnWord() + " of " + path +
         (column_rule.empty() ? "" : " that is " + column_rule) + " (" +
         NameList() + ")";
}

std::string DataTable::DescribeName(const std::string& name) const {
  for (const auto& [other, what] : not_columns) {
    if (other == name) return "'" + name + "' (" + what + ")";
  }
  return "'" + name + "'";
}

size_t DataTable::ColumnIndex(const std::string& name) const {
  for (size_t j = 0; j < names.size(); ++j) {
    if (names[j] == name) return j;
  }
  for (const auto& [other, what] : not_columns) {
    if (other == name) {
      throw std::invalid_argument(path + ": " + ColumnWord() + " '" + name +
                                  "': expected " + column_rule + ", got " + what);
    }
  }
  throw std::invalid_argument(path + ": no " + ColumnWord() + " '" + name +
                              "'; expected one of: " + NameList());
}

const std::vector<double>& DataTable::Column(const std::string& name) const {
  return columns.at(ColumnIndex(name));
}

bool DataTable::HasColumn(const std::string& name) const {
  for (const std::string& n : names) {
    if (n == name) return true;
  }
  return false;
}

}  // namespace axis
