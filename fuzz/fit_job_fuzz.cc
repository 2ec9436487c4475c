// libFuzzer target: the fit-job loader (run/load_fit_job.h ParseFitJob) on arbitrary
// YAML text, relative paths resolved in configs/jobs (so that the seed
// corpus's models and data files load).
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_common.h"
#include "run/load_fit_job.h"
#include "io/yaml_util.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  axis::fuzz::Expect(data, size, [](const std::string& text) {
    axis::ParseFitJob(axis::ParseYamlText(text, "fuzz.yaml"), "fuzz.yaml",
                      PROJECT_SOURCE_DIR "/configs/jobs");
  });
  return 0;
}
