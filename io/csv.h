// Numeric CSV files: measured data in, simulated traces out.
//
// Reading is strict: one header row of unique names, then rows of finite
// numbers, all with the header's field count. Tokenizing (quotes, CRLF) is
// done by libcsv. Errors are std::invalid_argument with the message
//   "<path>:<line>: expected <what>, got <what>"
// (lines are 1-based, the header is line 1) so that a user can find the
// offending cell. Writing goes through a temporary file and a rename, so a
// reader never sees a half-written file.
#ifndef IO_CSV_H_
#define IO_CSV_H_

#include <cstddef>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/data_table.h"

namespace axis {

// The table ReadCsv returns (io/data_table.h): format kCsv, one column per
// header field.
using CsvTable = DataTable;

// Reads a CSV with a header row followed by numeric rows: fields separated by
// commas, optionally in double quotes (inner quotes doubled), rows ended by
// LF, CRLF or CR, spaces and tabs around unquoted fields ignored, an optional
// UTF-8 byte order mark. Numbers are anything std::strtod accepts in the C
// locale (e.g. "1", "-2.5e-3"), with nothing else in the cell but spaces.
// The result has one name and one column per header field, every column with
// one value per data row; `path` is stored as given.
//
// Throws std::invalid_argument with a message that starts with "<path>:"
// (and "<path>:<line>:" where a line is at fault) and says what was expected
// and what was got, for: a file that cannot be opened or read; an empty file
// (or only blank lines); a header with no data rows ("expected at least one
// data row after the header, got none"); an empty or duplicated column name;
// a row whose field count differs from the header's; a blank line followed by
// more rows; an empty cell ("expected a number in column 'x', got an empty
// cell"); a non-numeric cell; a NaN or infinite cell (including overflow such
// as 1e999); malformed quoting; a line break inside a quoted field (each row
// must be one line, so that row i is line i + 2); bytes that are not UTF-8
// text (a NUL byte, a UTF-16 file; Utf8Checker's "<path>:<line>: expected
// UTF-8 text, got … at byte offset N (not UTF-8 text …)", io/internal/utf8_text.h).
// Blank trailing lines are ignored. Throws std::bad_alloc if memory runs out.
CsvTable ReadCsv(const std::string& path);

// As ReadCsv, from the text of a CSV file held in memory; `name` stands for
// the path in messages and in CsvTable::path (fuzz/csv_fuzz.cc).
CsvTable ParseCsv(const std::string& text, const std::string& name);

// Checks that column `column` of `table` (CSV or MAT) is strictly increasing
// (e.g. a time axis). Throws std::invalid_argument
//   "<path>:<line>: expected column 't' strictly increasing, got 0.002 after
//   0.002"
// at the first row that is not greater than the one before (or is NaN), where
// <line> is the file line of that row (row index + 2, as laid out by
// ReadCsv); for a MAT file "<path>: sample <row + 1>: expected variable 't'
// ..." (DataTable::RowLocation). Throws as DataTable::ColumnIndex if there
// is no such column.
void CheckStrictlyIncreasing(const CsvTable& table, const std::string& column);

// `text` as one CSV field: as is, or in double quotes (inner quotes
// doubled) if it holds a comma, a quote or a line break; what WriteCsvAtomic
// does with the header's names. Never throws (except std::bad_alloc).
std::string CsvField(const std::string& text);

// Formats a CSV: the header `names` (quoted only where needed, e.g. a comma
// or a quote in a name), then one row per index, columns[j][row] printed with
// "%.*g" of `precision` significant digits (17 reproduces every double
// exactly), "\n" line endings; and writes it with WriteFileAtomic. The result
// reads back with ReadCsv if the names are unique and non-empty and there is
// at least one row.
//
// Throws std::invalid_argument (writing nothing) if the column count differs
// from names.size(), the columns differ in length, a value is NaN or infinite
// (ReadCsv would reject it), or `precision` is outside [1, 17]; and
// std::runtime_error as WriteFileAtomic.
void WriteCsvAtomic(const std::string& path,
                    const std::vector<std::string>& names,
                    const std::vector<std::vector<double>>& columns,
                    int precision = 12);

}  // namespace axis

#endif  // IO_CSV_H_
