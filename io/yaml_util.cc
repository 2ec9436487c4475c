#include "io/yaml_util.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <ios>
#include <iterator>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <yaml-cpp/eventhandler.h>

#include "io/internal/utf8_text.h"

namespace axis {
namespace {

std::string Location(const std::string& file, const YAML::Node& node) {
  std::ostringstream out;
  out << file;
  if (node.IsDefined() && node.Mark().line >= 0) {
    out << ":" << node.Mark().line + 1;
  }
  return out.str();
}

}  // namespace

bool InRange(double x, YamlMap::Range range) {
  switch (range) {
    case YamlMap::Range::kAny: return std::isfinite(x);
    case YamlMap::Range::kPositive: return std::isfinite(x) && x > 0.0;
    case YamlMap::Range::kNonNegative: return std::isfinite(x) && x >= 0.0;
    case YamlMap::Range::kPositiveOrInfinite: return x > 0.0;  // +inf too; NaN compares false
  }
  return false;
}

const char* RangeText(YamlMap::Range range) {
  switch (range) {
    case YamlMap::Range::kAny: return "a finite number";
    case YamlMap::Range::kPositive: return "a finite positive number";
    case YamlMap::Range::kNonNegative: return "a finite number >= 0";
    case YamlMap::Range::kPositiveOrInfinite: return "a positive number or .inf";
  }
  return "a finite number";
}

namespace {

// The key of a mapping entry as the messages name it.
std::string KeyText(const YAML::Node& key) {
  return key.IsScalar() ? key.Scalar() : Describe(key);
}

// Throws on the first key of the mapping `node` given twice; `dot` is its
// key path with a trailing '.' ("" at top level).
void CheckOwnKeys(const YAML::Node& node, const std::string& file, const std::string& dot) {
  std::map<std::string, int> first_line;
  for (const auto& entry : node) {
    const std::string key = KeyText(entry.first);
    // yaml-cpp reads a merge key as an ordinary key named "<<" and merges
    // nothing: the keys it should bring in would be missing without a word.
    if (key == "<<" && entry.first.Tag() != "!") {
      ThrowConfigError(file, entry.first, dot + key,
                       "no YAML merge key (not supported: write the keys out)",
                       "'<<' (a merge key)");
    }
    const auto [where, inserted] = first_line.emplace(key, entry.first.Mark().line + 1);
    if (!inserted) {
      ThrowConfigError(file, entry.first, dot + key, "each key once in a mapping",
                       "'" + key + "' again (first on line " +
                           std::to_string(where->second) + ")");
    }
  }
}

// Throws "<name>:<line>: expected one YAML document, got a second one" at
// the line of the second document's start marker ("---" at the start of a
// line after some content), or with no line if there is none (a bare
// document after "...").
// An event handler that builds nothing: HasSecondDocument only asks whether
// the parser finds a document.
class IgnoreEvents : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

// Whether the text holds a second YAML document. The parser is asked for two
// documents at most: yaml-cpp 0.7's LoadAll never ends on a stray flow
// indicator at the top level (the text "," yields an empty document forever
// without consuming the ','; found by fuzz/model_config_fuzz.cc).
// Throws YAML::Exception on a syntax error.
bool HasSecondDocument(const std::string& text) {
  std::istringstream in(text);
  YAML::Parser parser(in);
  IgnoreEvents ignore;
  return parser.HandleNextDocument(ignore) && parser.HandleNextDocument(ignore);
}

[[noreturn]] void ThrowSecondDocument(const std::string& text, const std::string& name) {
  size_t line = 0;
  bool content = false;  // the first document has begun
  size_t number = 1;
  for (size_t begin = 0; begin < text.size() && line == 0; ++number) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string row = text.substr(begin, end - begin);
    const bool marker = row.compare(0, 3, "---") == 0 &&
                        (row.size() == 3 || row[3] == ' ' || row[3] == '\t' || row[3] == '\r');
    if (marker && content) line = number;
    if (!row.empty() && row[0] != '#' && row[0] != '%' &&
        row.find_first_not_of(" \t\r") != std::string::npos) {
      content = true;
    }
    begin = end + 1;
  }
  if (line == 0) {
    // No '---' after content: the parser split the text itself, as it does
    // at a ',', ']' or '}' outside a flow collection.
    throw std::invalid_argument(name + ": invalid YAML: expected one document, but the parser "
                                "ends the first one early (a ',', ']' or '}' outside [ ] or "
                                "{ }?)");
  }
  throw std::invalid_argument(name + ":" + std::to_string(line) +
                              ": expected one YAML document, got a second one (a '---' line; "
                              "only one document per file is read)");
}

}  // namespace

void CheckUniqueKeys(const YAML::Node& node, const std::string& file,
                     const std::string& prefix) {
  if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) {
      CheckUniqueKeys(node[i], file, prefix + "[" + std::to_string(i) + "]");
    }
    return;
  }
  if (!node.IsMap()) return;
  const std::string dot = prefix.empty() ? "" : prefix + ".";
  CheckOwnKeys(node, file, dot);
  for (const auto& entry : node) CheckUniqueKeys(entry.second, file, dot + KeyText(entry.first));
}

YAML::Node LoadYamlFile(const std::string& file) {
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw std::invalid_argument(file + ": cannot read the file: expected a file, got a directory");
  }
  std::ifstream in(file);
  if (!in) {
    throw std::invalid_argument(file + ": cannot read the file");
  }
  std::string text;
  try {
    text.assign(std::istreambuf_iterator<char>(in), {});
  } catch (const std::ios_base::failure& e) {
    // (found by fuzz/experiment_fuzz.cc: a directory opened as a file)
    throw std::invalid_argument(file + ": cannot read the file: " + e.what());
  }
  return ParseYamlText(text, file);
}

YAML::Node ParseYamlText(const std::string& text, const std::string& name) {
  CheckUtf8Text(text, name);  // before the parser quotes any of it
  YAML::Node root;
  bool second = false;
  try {
    root = YAML::Load(text);
    second = HasSecondDocument(text);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(name + ":" + std::to_string(e.mark.line + 1) +
                                ": invalid YAML: " + e.msg);
  }
  if (second) ThrowSecondDocument(text, name);
  CheckUniqueKeys(root, name, "");
  return root;
}

void ThrowConfigError(const std::string& file, const YAML::Node& node,
                      const std::string& key, const std::string& expected,
                      const std::string& got) {
  throw std::invalid_argument(Location(file, node) + ": key '" + key +
                              "': expected " + expected + ", got " + got);
}

std::string NumberText(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  return "a mapping";
}

YamlMap::YamlMap(const YAML::Node& node, std::string file, std::string prefix)
    : node_(node), file_(std::move(file)), prefix_(std::move(prefix)) {
  if (!node_.IsMap()) {
    const std::string key =
        prefix_.empty() ? "(top level)" : prefix_.substr(0, prefix_.size() - 1);
    ThrowConfigError(file_, node_, key, "a mapping of keys to values",
                     Describe(node_));
  }
  // LoadYamlFile checked the whole document; a document built in code is
  // checked here, each mapping when its loader opens it.
  CheckOwnKeys(node_, file_, prefix_);
}

bool YamlMap::Has(const std::string& key) const {
  return static_cast<bool>(node_[key]);
}

namespace {

// Levenshtein distance between a and b (insertions, deletions and
// substitutions of one byte each).
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = above;
    }
  }
  return row[b.size()];
}

}  // namespace

YAML::Node YamlMap::Required(const std::string& key) {
  used_.insert(key);
  YAML::Node value = node_[key];
  if (!value) {
    // A key of the map that is not a known one and is within two edits of
    // the missing key (a third of its length at most) is named, at its line:
    // a misspelt required key otherwise reads as a missing one.
    if (node_.IsMap()) {
      for (const auto& entry : node_) {
        const std::string other = entry.first.Scalar();
        if (used_.count(other) != 0) continue;
        const size_t d = EditDistance(other, key);
        if (d > 0 && d <= 2 && 3 * d <= key.size()) {
          ThrowConfigError(file_, entry.first, KeyPath(key), "a value (required key)",
                           "nothing; unknown key '" + other + "' here: misspelt?");
        }
      }
    }
    ThrowConfigError(file_, node_, KeyPath(key), "a value (required key)",
                     "nothing");
  }
  return value;
}

YAML::Node YamlMap::Optional(const std::string& key) {
  used_.insert(key);
  return node_[key];
}

double YamlMap::NumberFrom(const YAML::Node& value, const std::string& key_path,
                           Range range) const {
  double x = 0.0;
  bool ok = value.IsScalar();
  if (ok) {
    try {
      x = value.as<double>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
  }
  if (ok) ok = InRange(x, range);
  if (!ok) ThrowConfigError(file_, value, key_path, RangeText(range), Describe(value));
  return x;
}

double YamlMap::Number(const std::string& key, Range range) {
  return NumberFrom(Required(key), KeyPath(key), range);
}

double YamlMap::Number(const std::string& key, double fallback, Range range) {
  const YAML::Node value = Optional(key);
  if (!value) return fallback;
  return NumberFrom(value, KeyPath(key), range);
}

long YamlMap::Integer(const std::string& key, long fallback, long min,
                      long max) {
  const YAML::Node value = Optional(key);
  if (!value) return fallback;
  long x = 0;
  bool ok = value.IsScalar();
  if (ok) {
    try {
      x = value.as<long>();
    } catch (const YAML::Exception&) {
      ok = false;
    }
  }
  if (!ok || x < min || x > max) {
    ThrowConfigError(file_, value, KeyPath(key),
                     "an integer in " + std::to_string(min) + ".." +
                         std::to_string(max),
                     Describe(value));
  }
  return x;
}

std::string YamlMap::String(const std::string& key) {
  const YAML::Node value = Required(key);
  if (!value.IsScalar()) {
    ThrowConfigError(file_, value, KeyPath(key), "a string", Describe(value));
  }
  return value.Scalar();
}

std::string YamlMap::String(const std::string& key,
                            const std::string& fallback) {
  if (!Has(key)) {
    used_.insert(key);
    return fallback;
  }
  return String(key);
}

std::string YamlMap::Choice(const std::string& key,
                            const std::vector<std::string>& choices) {
  const YAML::Node value = Required(key);
  std::string list;
  for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
  if (value.IsScalar()) {
    for (const std::string& c : choices) {
      if (value.Scalar() == c) return c;
    }
  }
  ThrowConfigError(file_, value, KeyPath(key), "one of " + list,
                   Describe(value));
}

std::string YamlMap::Choice(const std::string& key,
                            const std::vector<std::string>& choices,
                            const std::string& fallback) {
  if (!Has(key)) {
    used_.insert(key);
    return fallback;
  }
  return Choice(key, choices);
}

void YamlMap::Finish() const {
  for (const auto& entry : node_) {
    const std::string key = entry.first.Scalar();
    if (used_.count(key)) continue;
    std::string known;
    for (const std::string& k : used_) known += (known.empty() ? "" : ", ") + k;
    ThrowConfigError(file_, entry.first, KeyPath(key),
                     "one of the known keys (" + known + ")",
                     "unknown key '" + key + "'");
  }
}

std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

std::string OutputDirectory(YamlMap* output, const std::string& base_dir) {
  const std::string dir = output->String("dir");
  if (dir.find_first_not_of(" \t") == std::string::npos) {
    ThrowConfigError(output->file(), output->node()["dir"], output->KeyPath("dir"),
                     "a folder path (relative to the file's folder, or absolute)",
                     "'" + dir + "' (an empty path would write into the file's own folder)");
  }
  return ResolvePath(base_dir, dir);
}

std::string ResolvePath(const std::string& base_dir,
                        const std::string& relative) {
  if (!relative.empty() && relative[0] == '/') return relative;
  if (base_dir.empty() || base_dir == ".") return relative;
  return base_dir + "/" + relative;
}

}  // namespace axis
