// The fleet table's files (fit-fleet's output folder): the table as CSV,
// Markdown, HTML (fleet/internal/fleet_html.h) and JSON (fleet/fleet_table.h).
#ifndef FLEET_WRITE_FLEET_TABLE_H_
#define FLEET_WRITE_FLEET_TABLE_H_

#include <string>

#include "fleet/fleet_table.h"

namespace axis {

// Writes fleet.csv (a row per job: axis, log, status, verdict, s2,
// effects, discovered, per free parameter of any row its value and
// "<name>_se", per channel "fit_<experiment>_<channel>" (%), seconds,
// rank, folder, error; empty cells where a row has none), fleet.md,
// fleet.html (fleet/internal/fleet_html.h) and last fleet.json into `dir` (created
// with its parents if missing), each atomically (WriteFileAtomic). Throws
// std::runtime_error naming what cannot be written.
void WriteFleetTable(const std::string& dir, const FleetTable& table);

}  // namespace axis

#endif  // FLEET_WRITE_FLEET_TABLE_H_
