#include "io/data_file.h"

#include <cctype>
#include <filesystem>
#include <string>

#include "io/csv.h"
#include "io/mat_file.h"

namespace axis {

DataTable ReadDataTable(const std::string& path, const std::string& time_column) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".mat" ? ReadMatFile(path, time_column) : ReadCsv(path);
}

}  // namespace axis
