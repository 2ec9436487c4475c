// libFuzzer target: the model-config loader (sim/config.h ParseAxisConfig)
// on arbitrary YAML text.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_common.h"
#include "sim/config.h"
#include "io/yaml_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  axis::fuzz::Expect(data, size, [](const std::string& text) {
    axis::ParseAxisConfig(axis::ParseYamlText(text, "fuzz.yaml"), "fuzz.yaml");
  });
  return 0;
}
