// A data file read by its name: a MATLAB MAT file if the name ends in
// ".mat", a JSON log if it ends in ".json", else a CSV file; each gives the
// same table of named columns (io/data_table.h).
#ifndef IO_DATA_FILE_H_
#define IO_DATA_FILE_H_

#include <string>

#include "io/data_table.h"

namespace axis {

// Reads a data file: a MAT file (ReadMatFile, io/mat_file.h) if `path`
// ends in ".mat" (any case), a JSON log (ReadJsonLog, io/json_log.h) if it
// ends in ".json", else a CSV file (ReadCsv, io/csv.h).
// `time_column` names the time column or variable; only the MAT reader uses
// it (to know how long a column must be). Throws std::invalid_argument as
// the reader does.
DataTable ReadDataTable(const std::string& path, const std::string& time_column);

}  // namespace axis

#endif  // IO_DATA_FILE_H_
