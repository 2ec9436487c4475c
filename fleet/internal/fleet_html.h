// fleet.html (issues 12 and 14): the fleet table as one self-contained page
// (report/html_report.h's style sheet and sorting script inline; nothing
// loaded): the changes since the baseline on top, one row per axis and log,
// sortable by a click on any header, each axis linking to its own
// report.html (<axis>/<log>/report.html beside fleet.html), the failed jobs
// with their errors and what the incomplete models still miss. Every text
// from the manifest, the jobs or the data is HTML-escaped.
#ifndef FLEET_INTERNAL_FLEET_HTML_H_
#define FLEET_INTERNAL_FLEET_HTML_H_

#include <string>

#include "fleet/fleet_table.h"

namespace axis {

// The page as text; section ids "changes" (only if table.compared),
// "axes", "failed" (only if a job failed) and "remains" (only if a verdict
// is incomplete). Never throws (except std::bad_alloc).
std::string RenderFleetHtml(const FleetTable& table);

}  // namespace axis

#endif  // FLEET_INTERNAL_FLEET_HTML_H_
