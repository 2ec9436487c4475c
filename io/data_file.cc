#include "io/data_file.h"

#include <cctype>
#include <filesystem>
#include <string>

#include "io/csv.h"
#include "io/json_log.h"
#include "io/mat_file.h"

namespace axis {

DataTable ReadDataTable(const std::string& path, const std::string& time_column) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".mat") return ReadMatFile(path, time_column);
  if (extension == ".json") return ReadJsonLog(path);
  return ReadCsv(path);
}

}  // namespace axis
