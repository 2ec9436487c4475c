// Python objects as YAML text, so that experiments and fit jobs given as
// Python dicts go through the same strict loaders as files (sim/config.h
// ParseExperiment, run/load_fit_job.h ParseFitJob) and fail with the same messages.
#ifndef PYTHON_YAML_FROM_PYTHON_H_
#define PYTHON_YAML_FROM_PYTHON_H_

#include <string>

#include <pybind11/pybind11.h>
#include <yaml-cpp/yaml.h>

namespace axis::python {

// The YAML node for `value` (call with the GIL held):
// - a dict (any collections.abc.Mapping) → a mapping in the dict's order;
//   its keys must be str;
// - a list or tuple → a sequence;
// - an object with tolist() (a NumPy array or scalar) → what tolist()
//   returns, converted again;
// - bool → true/false; int → its decimal text; float → its shortest
//   round-trip text (repr), inf/-inf/nan as .inf/-.inf/.nan;
// - str → the string; an os.PathLike → os.fspath(value); None → null.
// `document` names the document and `key` the key path of `value`
// ("" at the top, "experiments[0].window" further down) in messages.
// Throws std::invalid_argument "<document>: key '<key>': expected a str
// key, got <repr>" for another key type and "<document>: key '<key>':
// expected a dict, list, str, number, bool or None, got <type> <repr>"
// for anything else.
YAML::Node ToYamlNode(pybind11::handle value, const std::string& document,
                      const std::string& key = "");

// ToYamlNode(value) emitted as block-style YAML text: the document the
// loaders read, whose line numbers their messages name. Throws as
// ToYamlNode.
std::string ToYamlText(pybind11::handle value, const std::string& document);

}  // namespace axis::python

#endif  // PYTHON_YAML_FROM_PYTHON_H_
