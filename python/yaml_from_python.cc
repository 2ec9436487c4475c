#include "python/yaml_from_python.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace py = pybind11;

namespace axis::python {
namespace {

std::string Repr(py::handle value) {
  std::string text = py::repr(value).cast<std::string>();
  constexpr size_t kMax = 60;
  if (text.size() > kMax) text = text.substr(0, kMax) + "...";
  return text;
}

[[noreturn]] void Throw(const std::string& document, const std::string& key,
                        const std::string& expected, const std::string& got) {
  throw std::invalid_argument(document + ": key '" + key + "': expected " + expected +
                              ", got " + got);
}

std::string FloatText(double x) {
  if (std::isnan(x)) return ".nan";
  if (std::isinf(x)) return x > 0 ? ".inf" : "-.inf";
  return py::repr(py::float_(x)).cast<std::string>();  // shortest round trip
}

bool IsMapping(py::handle value) {
  return py::isinstance<py::dict>(value) ||
         py::isinstance(value, py::module_::import("collections.abc").attr("Mapping"));
}

}  // namespace

YAML::Node ToYamlNode(py::handle value, const std::string& document,
                      const std::string& key) {
  if (value.is_none()) return YAML::Node(YAML::NodeType::Null);
  // bool before int: bool is a subclass of int.
  if (py::isinstance<py::bool_>(value)) {
    return YAML::Node(value.cast<bool>() ? "true" : "false");
  }
  if (py::isinstance<py::int_>(value)) return YAML::Node(py::str(value).cast<std::string>());
  if (py::isinstance<py::float_>(value)) return YAML::Node(FloatText(value.cast<double>()));
  if (py::isinstance<py::str>(value)) return YAML::Node(value.cast<std::string>());
  if (IsMapping(value)) {
    YAML::Node map(YAML::NodeType::Map);
    for (const py::handle item : value.attr("items")()) {
      const py::tuple pair = py::reinterpret_borrow<py::tuple>(item);
      if (!py::isinstance<py::str>(pair[0])) {
        Throw(document, key, "a str key", Repr(pair[0]));
      }
      const std::string name = pair[0].cast<std::string>();
      map[name] = ToYamlNode(pair[1], document, key.empty() ? name : key + "." + name);
    }
    return map;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    YAML::Node sequence(YAML::NodeType::Sequence);
    size_t index = 0;
    for (const py::handle item : value) {
      sequence.push_back(
          ToYamlNode(item, document, key + "[" + std::to_string(index++) + "]"));
    }
    return sequence;
  }
  if (py::hasattr(value, "tolist")) {  // NumPy arrays and scalars
    return ToYamlNode(value.attr("tolist")(), document, key);
  }
  if (py::hasattr(value, "__fspath__")) {  // pathlib.Path
    return YAML::Node(py::module_::import("os").attr("fspath")(value).cast<std::string>());
  }
  Throw(document, key, "a dict, list, str, number, bool or None",
        std::string(py::str(py::type::of(value).attr("__name__"))) + " " + Repr(value));
}

std::string ToYamlText(py::handle value, const std::string& document) {
  YAML::Emitter emitter;
  emitter << ToYamlNode(value, document);
  if (!emitter.good()) {
    throw std::invalid_argument(document + ": expected a value YAML can hold, got " +
                                emitter.GetLastError());
  }
  return std::string(emitter.c_str()) + "\n";
}

}  // namespace axis::python
