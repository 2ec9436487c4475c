#include "fleet/write_fleet_table.h"

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "fleet/internal/fleet_html.h"
#include "fleet/fleet_table.h"
#include "io/atomic_file.h"

namespace axis {

namespace fs = std::filesystem;

void WriteFleetTable(const std::string& dir, const FleetTable& table) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw std::runtime_error(dir + ": cannot create the folder: " + error.message());
  WriteFileAtomic(dir + "/fleet.csv", FleetCsv(table));
  WriteFileAtomic(dir + "/fleet.md", FormatFleetMarkdown(table));
  WriteFileAtomic(dir + "/fleet.html", RenderFleetHtml(table));
  // Invalid UTF-8 (an error message quoting a data file) as U+FFFD, not an exception.
  WriteFileAtomic(dir + "/fleet.json",
                  FleetTableToJson(table).dump(2, ' ', false,
                                               nlohmann::json::error_handler_t::replace) +
                      "\n");
}

}  // namespace axis
