// The `frequency_response:` key of a fit job: whether the run estimates the
// frequency response of its fitted experiments (AnalyseFrequencyResponse,
// discovery/frequency_response.h; docs/frequency-response.md) and the least
// number of Welch averages it asks of a record.
#ifndef DISCOVERY_FREQUENCY_RESPONSE_SETTINGS_H_
#define DISCOVERY_FREQUENCY_RESPONSE_SETTINGS_H_

#include <string>

#include <yaml-cpp/yaml.h>

namespace axis {

struct FrequencyResponseSettings {
  // Estimate it (the default); false: no frequency-response phase, table,
  // report.json entry or Bode plot.
  bool enabled = true;
  // Welch segments (Hann, 50 % overlap) a record must hold at least, 2..64:
  // the segment length is the longest power of two of 16..4096 samples that
  // gives this many (WelchSegmentLength, common/spectral.h). More averages:
  // a smaller random error of H1 (∝ 1/√averages, H1RandomError; Bendat &
  // Piersol Table 9.6), a coarser frequency grid.
  int min_averages = 8;

  // The keys of `frequency_response:` (io/settings_reader.h).
  template <typename Archive>
  void Serialize(Archive* a) {
    a->Visit("enabled", &enabled);
    a->Visit("min_averages", &min_averages, 2, 64);
  }
};

// Reads `frequency_response:` of job file `file` into `s`: a mapping of the
// keys above, or null (the defaults). Throws std::invalid_argument
// "<file>:<line>: key 'frequency_response.<key>': expected …, got …" for an
// unknown key or a value out of range.
void ReadFrequencyResponseSettings(const YAML::Node& node, const std::string& file,
                                   FrequencyResponseSettings* s);

}  // namespace axis

#endif  // DISCOVERY_FREQUENCY_RESPONSE_SETTINGS_H_
