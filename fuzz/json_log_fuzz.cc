// libFuzzer target: the JSON log reader (io/json_log.h ParseJsonLog, the
// parser behind ReadJsonLog) on arbitrary bytes.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_common.h"
#include "io/json_log.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  axis::fuzz::Expect(data, size, [](const std::string& text) {
    const axis::DataTable table = axis::ParseJsonLog(text, "fuzz.json");
    (void)table.NameList();
  });
  return 0;
}
