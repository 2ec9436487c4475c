// libFuzzer target: the CSV reader (io/csv.h ParseCsv, the parser behind
// ReadCsv) on arbitrary bytes.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_common.h"
#include "io/csv.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  axis::fuzz::Expect(data, size, [](const std::string& text) {
    const axis::CsvTable table = axis::ParseCsv(text, "fuzz.csv");
    if (table.HasColumn("t")) axis::CheckStrictlyIncreasing(table, "t");
  });
  return 0;
}
