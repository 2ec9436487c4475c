// libFuzzer target: the MAT file reader (io/mat_file.h ReadMatFile, through
// libmatio and HDF5) on arbitrary bytes. matio reads files only, so each
// input is written to a temporary file of this process first. The seed
// corpus (fuzz/corpus/mat_file/) holds small level 4, 5 (plain and
// compressed) and 7.3 files with vectors, a matrix, text and a struct.
// libmatio and HDF5 are not instrumented: libFuzzer sees the coverage of
// this project's code only, and AddressSanitizer catches their crashes and
// leaks, not their out-of-bounds reads.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz/fuzz_common.h"
#include "io/csv.h"
#include "io/mat_file.h"

namespace {

// "<temp dir>/mat_file_fuzz.<pid>.mat", removed at exit.
const std::string& InputPath() {
  static const std::string path = [] {
    const std::string p = (std::filesystem::temp_directory_path() /
                           ("mat_file_fuzz." + std::to_string(::getpid()) + ".mat"))
                              .string();
    std::atexit([] { std::remove(InputPath().c_str()); });
    return p;
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  axis::fuzz::Expect(data, size, [](const std::string& bytes) {
    std::ofstream(InputPath(), std::ios::binary | std::ios::trunc) << bytes;
    const axis::DataTable table = axis::ReadMatFile(InputPath(), "t");
    axis::CheckStrictlyIncreasing(table, "t");
  });
  return 0;
}
