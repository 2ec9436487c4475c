// A recorded experiment's data: named columns of equal length, read from a
// CSV file (io/csv.h ReadCsv: the header names the columns) or a MATLAB MAT
// file (io/mat_file.h ReadMatFile: each variable that is a numeric vector
// as long as the time variable is a column). ReadDataTable picks the reader
// by the file name's extension.
#ifndef IO_DATA_TABLE_H_
#define IO_DATA_TABLE_H_

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace axis {

// A numeric table: one name and one column of values per named series (SI
// or whatever unit the file uses), every column with one value per row.
struct DataTable {
  // The file format, which words the messages: a CSV file has "column"s and
  // its row i is line i + 2 of the file; a MAT file has "variable"s and its
  // row i is element i + 1 (1-based, as MATLAB counts) of each vector; a
  // JSON log (io/json_log.h) has "key"s and its row i is entries[i]
  // (0-based, as JSON indexes arrays).
  enum class Format { kCsv, kMat, kJson };

  std::string path;                          // file it was read from
  Format format = Format::kCsv;
  std::vector<std::string> names;            // in file order
  std::vector<std::vector<double>> columns;  // columns[j][row], all the same length
  // MAT files only: the variables that are not columns, each with what it is
  // (e.g. {"kp", "a 1x1 double"}), and what a column must be
  // (`column_rule`, e.g. "a real numeric vector of 24841 finite values, as
  // long as the time variable 't'"). Empty for a CSV file.
  std::vector<std::pair<std::string, std::string>> not_columns;
  std::string column_rule;
  // JSON logs only: the log's own numbers beside its entries (a BAM log's
  // `mass`, `length`, `kp`, `vin`, `dt`), in file order. Empty otherwise.
  std::vector<std::pair<std::string, double>> constants;

  // Number of rows (the length of every column); 0 without columns.
  size_t num_rows() const;

  // Index j (0-based, into `names` and `columns`) of the column called
  // `name`; names are compared exactly (case-sensitive). Throws
  // std::invalid_argument "<path>: no column 'q'; expected one of: t_s,
  // qm_m, ..." listing every column name ("variable" for a MAT file), or for
  // a MAT variable that is not a column "<path>: variable 'kp': expected
  // <column_rule>, got a 1x1 double".
  size_t ColumnIndex(const std::string& name) const;

  // The values of column `name`, one per row (length num_rows()). Throws as
  // ColumnIndex.
  const std::vector<double>& Column(const std::string& name) const;

  // Whether a column is called `name`. Never throws.
  bool HasColumn(const std::string& name) const;
  // "t_s, qm_m, ..." (or "(no columns)"), for messages.
  std::string NameList() const;

  // For messages: "column" (CSV), "variable" (MAT) or "key" (JSON).
  std::string ColumnWord() const;
  // Where row `row` (0-based) of the data is, for messages: "<path>:<line>"
  // (line row + 2) for a CSV file, "<path>: sample <row + 1>" for a MAT file,
  // "<path>: entries[<row>]" for a JSON log.
  std::string RowLocation(size_t row) const;
  // What a column name of this table must be, for an "expected …" message:
  // "a column of <path> (t_s, qm_m, ...)" or "a variable of <path> that is
  // <column_rule> (t, qm, ...)".
  std::string ColumnExpectation() const;
  // `name` for a "got …" message: "'q'", or for a MAT variable that is not
  // a column "'kp' (a 1x1 double)".
  std::string DescribeName(const std::string& name) const;
};

}  // namespace axis

#endif  // IO_DATA_TABLE_H_
