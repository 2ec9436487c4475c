// Recorded data from MATLAB MAT files (e.g. the EMPS benchmark's
// DATA_EMPS.mat), read with libmatio: levels 4 and 5, and 7.3 (HDF5) where
// matio was built with HDF5 (Debian's libmatio-dev is). Each variable that is
// a numeric vector as long as the time variable is a column of the table,
// exactly as a CSV file's columns (io/data_table.h, io/csv.h).
#ifndef IO_MAT_FILE_H_
#define IO_MAT_FILE_H_

#include <string>

#include "io/data_table.h"

namespace axis {

// Reads the MAT file `path` into a table of format kMat. `time_variable`
// (e.g. "t", in seconds as the file has it) must be a real numeric vector of
// at least one finite value. Every variable (the time variable included)
// that is a real numeric vector of that length with finite values is a
// column, in the order matio lists them (file order; by name in a level 7.3
// file), converted to double: a row or column vector or any
// array with at most one dimension above 1; classes double, single,
// int8…uint64 and logical. Every other variable goes to `not_columns` with
// what it is ("a 1x1 double", "a 3x4 double matrix", "a 1x5 char array",
// "a 24841x1 double vector with NaN at sample 17", …), so that naming it as
// a column says why it is not one (DataTable::ColumnIndex).
//
// Throws std::invalid_argument with a message that starts with "<path>:" and
// says what was expected and what was got, for: a file that cannot be
// opened; an empty file; a file matio cannot open as a MAT file; a truncated
// or damaged file (anything matio warns about while reading the variables,
// its message quoted; a numeric vector whose header claims more data than
// 1032 times the file's size, deflate's largest ratio, is refused before
// anything is allocated for it); a variable name twice; no variable `time_variable`
// ("expected a time variable 't', got none; the variables are: …"); a time
// variable that is not a real numeric vector of finite values, at least
// one ("variable 't' (the time): expected …, got a 3x4 double matrix").
// Reads the headers of all variables first and then the data of the time
// variable and of the vectors as long as it only. Never crashes on a bad
// file as far as matio does not. Serialised by a mutex (matio's log
// function and HDF5 are process-wide).
DataTable ReadMatFile(const std::string& path, const std::string& time_variable);

}  // namespace axis

#endif  // IO_MAT_FILE_H_
