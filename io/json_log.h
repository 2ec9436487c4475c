// JSON logs as data tables: a file whose top-level object holds an array
// `entries` of one object per sample, each with the same keys (numbers or
// true/false), as the BAM project's servo logs are written (Duclusaud et
// al., ICRA 2025; shared/data/bam_xl330/README.md: `timestamp`,
// `position`, `goal_position`, `torque_enable`, ...). The entries' keys
// become columns; the log's other numbers (a BAM log's `mass`, `length`,
// `kp`, `vin`, `dt`) become DataTable::constants. Parsing is nlohmann_json's
// (Debian nlohmann-json3-dev).
#ifndef IO_JSON_LOG_H_
#define IO_JSON_LOG_H_

#include <string>

#include "io/data_table.h"

namespace axis {

// Reads the JSON log at `path` into a table of format kJson: one column per
// key of entries[0], in that entry's order, one row per entry; true is 1 and
// false 0 (a drive-enable flag). Top-level numbers (and true/false) are
// `constants`, in file order; every top-level key but `entries` is listed
// in `not_columns` with what it is, so that naming it as a column says so.
// No check of the time base: a job's loader checks the sampling
// (run/load_fit_job.h), and a log with irregular timestamps (BAM's raw logs)
// is refused there with the entry at fault.
//
// Throws std::invalid_argument with a message that starts with "<path>:"
// (and "<path>: entries[i]:" where an entry is at fault) and says what was
// expected and what was got, for: a file that cannot be opened; text that
// is not JSON (nlohmann_json's parse error, with its byte offset); a top
// level that is not an object, or has no `entries` array; no entries; an
// entry that is not an object, lacks a key of entries[0] or has one more;
// a value that is neither a finite number nor true/false. Throws
// std::bad_alloc if memory runs out.
DataTable ReadJsonLog(const std::string& path);

// As ReadJsonLog, from the text of a log held in memory; `name` stands for
// the path in messages and in DataTable::path.
DataTable ParseJsonLog(const std::string& text, const std::string& name);

}  // namespace axis

#endif  // IO_JSON_LOG_H_
