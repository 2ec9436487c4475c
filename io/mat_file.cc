#include "io/mat_file.h"

#include <matio.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace axis {
namespace {

// matio's log function and HDF5's error handling are process-wide: one read
// at a time.
std::mutex& MatioMutex() {
  static std::mutex mutex;
  return mutex;
}

// Where the read under way (holding MatioMutex) keeps the first warning or
// error matio logs; nullptr outside a read.
std::string* g_first_problem = nullptr;

void RecordProblem(int level, const char* message) {
  constexpr int kProblemLevels =
      MATIO_LOG_LEVEL_ERROR | MATIO_LOG_LEVEL_CRITICAL | MATIO_LOG_LEVEL_WARNING;
  if (g_first_problem == nullptr || !g_first_problem->empty() ||
      (level & kProblemLevels) == 0) {
    return;
  }
  std::string text = message != nullptr ? message : "";
  text = text.substr(0, text.find('\n'));  // HDF5's error stacks: the first line
  *g_first_problem = text.empty() ? "(no message)" : text;
}

// matio's log callback takes `char*` up to 1.5.23 and `const char*` later;
// Mat_LogInitFunc's parameter type picks Char.
template <typename Char>
void OnMatioLog(int level, Char* message) {
  RecordProblem(level, message);
}

// For the lifetime of the object (while MatioMutex is held), matio's
// warnings and errors go to *first_problem instead of nowhere (or abort(),
// which matio's default log function calls on MATIO_LOG_LEVEL_ERROR).
class ProblemRecorder {
 public:
  explicit ProblemRecorder(std::string* first_problem) {
    g_first_problem = first_problem;
    Mat_LogInitFunc("servo_axis_id", &OnMatioLog);
  }
  ~ProblemRecorder() { g_first_problem = nullptr; }
  ProblemRecorder(const ProblemRecorder&) = delete;
  ProblemRecorder& operator=(const ProblemRecorder&) = delete;
};

struct MatCloser {
  void operator()(mat_t* mat) const { Mat_Close(mat); }
};
struct VarFreer {
  void operator()(matvar_t* var) const { Mat_VarFree(var); }
};

bool IsNumeric(const matvar_t& v) {
  switch (v.class_type) {
    case MAT_C_DOUBLE:
    case MAT_C_SINGLE:
    case MAT_C_INT8:
    case MAT_C_UINT8:
    case MAT_C_INT16:
    case MAT_C_UINT16:
    case MAT_C_INT32:
    case MAT_C_UINT32:
    case MAT_C_INT64:
    case MAT_C_UINT64:
      return true;
    default:
      return false;
  }
}

// "double", "int16", "logical", "char array", "struct", ... as MATLAB's
// class() would say.
std::string ClassName(const matvar_t& v) {
  if (v.isLogical && v.class_type != MAT_C_SPARSE) return "logical";
  switch (v.class_type) {
    case MAT_C_DOUBLE: return "double";
    case MAT_C_SINGLE: return "single";
    case MAT_C_INT8: return "int8";
    case MAT_C_UINT8: return "uint8";
    case MAT_C_INT16: return "int16";
    case MAT_C_UINT16: return "uint16";
    case MAT_C_INT32: return "int32";
    case MAT_C_UINT32: return "uint32";
    case MAT_C_INT64: return "int64";
    case MAT_C_UINT64: return "uint64";
    case MAT_C_CHAR: return "char array";
    case MAT_C_CELL: return "cell array";
    case MAT_C_STRUCT: return "struct";
    case MAT_C_SPARSE: return "sparse matrix";
    case MAT_C_FUNCTION: return "function handle";
    case MAT_C_OBJECT:
    case MAT_C_OPAQUE: return "object";
    case MAT_C_EMPTY: return "empty array";
  }
  return "variable of unknown class";
}

// The element count of `v`, or false if its dimensions are missing or their
// product overflows.
bool CountElements(const matvar_t& v, size_t* count) {
  if (v.rank <= 0 || v.dims == nullptr) return false;
  size_t n = 1;
  for (int k = 0; k < v.rank; ++k) {
    if (v.dims[k] != 0 && n > SIZE_MAX / v.dims[k]) return false;
    n *= v.dims[k];
  }
  *count = n;
  return true;
}

// Dimensions above 1.
int LongDimensions(const matvar_t& v) {
  int long_dims = 0;
  for (int k = 0; k < v.rank && v.dims != nullptr; ++k) long_dims += v.dims[k] > 1;
  return long_dims;
}

// "a 3x4 double matrix", "a 24841x1 double vector", "a 1x1 double",
// "a 1x5 char array", "a 2x3x4 complex single array".
std::string Describe(const matvar_t& v) {
  std::string shape;
  for (int k = 0; k < v.rank && v.dims != nullptr; ++k) {
    shape += (k > 0 ? "x" : "") + std::to_string(v.dims[k]);
  }
  if (shape.empty()) shape = "?";
  std::string what = "a " + shape + " " + (v.isComplex ? "complex " : "") + ClassName(v);
  size_t count = 0;
  if (!IsNumeric(v) || !CountElements(v, &count) || count == 1) return what;
  if (count == 0) return "a " + shape + " empty " + ClassName(v);
  if (count > 0 && LongDimensions(v) <= 1) return what + " vector";
  return what + (v.rank == 2 ? " matrix" : " array");
}

template <typename T>
bool AppendAs(const matvar_t& v, size_t count, std::vector<double>* out) {
  if (v.data_size != static_cast<int>(sizeof(T))) return false;
  const T* data = static_cast<const T*>(v.data);
  out->reserve(count);
  for (size_t i = 0; i < count; ++i) out->push_back(static_cast<double>(data[i]));
  return true;
}

// The `count` elements of a real numeric `v` as doubles; false if matio
// delivered no data or elements of another size than the class has.
bool ToDoubles(const matvar_t& v, size_t count, std::vector<double>* out) {
  if (v.data == nullptr) return false;
  switch (v.class_type) {
    case MAT_C_DOUBLE: return AppendAs<double>(v, count, out);
    case MAT_C_SINGLE: return AppendAs<float>(v, count, out);
    case MAT_C_INT8: return AppendAs<int8_t>(v, count, out);
    case MAT_C_UINT8: return AppendAs<uint8_t>(v, count, out);
    case MAT_C_INT16: return AppendAs<int16_t>(v, count, out);
    case MAT_C_UINT16: return AppendAs<uint16_t>(v, count, out);
    case MAT_C_INT32: return AppendAs<int32_t>(v, count, out);
    case MAT_C_UINT32: return AppendAs<uint32_t>(v, count, out);
    case MAT_C_INT64: return AppendAs<int64_t>(v, count, out);
    case MAT_C_UINT64: return AppendAs<uint64_t>(v, count, out);
    default: return false;
  }
}

// Deflate's largest compression ratio: no variable of a MAT file holds more
// bytes of data than this many times the size of the file.
constexpr double kMaxExpansion = 1032.0;

// Bytes of one element of a numeric class.
size_t ElementBytes(matio_classes class_type) {
  switch (class_type) {
    case MAT_C_DOUBLE:
    case MAT_C_INT64:
    case MAT_C_UINT64: return 8;
    case MAT_C_SINGLE:
    case MAT_C_INT32:
    case MAT_C_UINT32: return 4;
    case MAT_C_INT16:
    case MAT_C_UINT16: return 2;
    default: return 1;
  }
}

// One variable of the file: what its header says and, once read, its values.
struct Variable {
  std::string name;
  std::string what;        // Describe(), plus the first non-finite value once read
  bool candidate = false;  // real numeric, at most one dimension above 1, not empty
  size_t count = 0;        // elements, for a candidate
  bool vector = false;     // read: a real numeric vector of finite values
  std::vector<double> values;  // if `vector`
};

[[noreturn]] void ThrowDamaged(const std::string& path, const std::string& detail) {
  throw std::invalid_argument(path +
                              ": expected a complete MAT file, got a truncated or damaged "
                              "one (" + detail + ")");
}

std::string NameList(const std::vector<Variable>& variables) {
  std::string list;
  for (const Variable& v : variables) list += (list.empty() ? "" : ", ") + v.name;
  return list.empty() ? "(none)" : list;
}

// Pass 1: the header of every variable of the open file, in matio's order,
// without their data (a header claiming more data than the file can hold is
// never allocated). Throws std::invalid_argument if matio reports a problem,
// a candidate claims more data than the file can hold, or a name repeats.
std::vector<Variable> ReadHeaders(const std::string& path, mat_t* mat,
                                  const std::string& problem, std::uintmax_t file_size) {
  std::vector<Variable> variables;
  while (problem.empty()) {
    const std::unique_ptr<matvar_t, VarFreer> var(Mat_VarReadNextInfo(mat));
    if (!var) break;
    if (var->name == nullptr || var->name[0] == '\0') continue;
    Variable v;
    v.name = var->name;
    v.what = Describe(*var);
    v.candidate = IsNumeric(*var) && !var->isComplex && CountElements(*var, &v.count) &&
                  v.count > 0 && LongDimensions(*var) <= 1;
    if (v.candidate && static_cast<double>(v.count) * ElementBytes(var->class_type) >
                           kMaxExpansion * static_cast<double>(file_size)) {
      ThrowDamaged(path, "variable '" + v.name + "' claims " + std::to_string(v.count) +
                             " elements in a file of " + std::to_string(file_size) + " bytes");
    }
    variables.push_back(std::move(v));
  }
  if (!problem.empty()) ThrowDamaged(path, "matio: " + problem);
  for (size_t i = 0; i < variables.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (variables[i].name == variables[j].name) {
        throw std::invalid_argument(path + ": expected unique variable names, got '" +
                                    variables[i].name + "' twice");
      }
    }
  }
  return variables;
}

// Pass 2: the values of candidate `v` as doubles; `vector` unless one is not
// finite (then `what` says where). Throws std::invalid_argument if matio
// reports a problem or delivers other data than the header announced.
void ReadValues(const std::string& path, mat_t* mat, const std::string& problem,
                Variable* v) {
  const std::unique_ptr<matvar_t, VarFreer> var(Mat_VarRead(mat, v->name.c_str()));
  if (!problem.empty()) ThrowDamaged(path, "matio: " + problem);
  size_t count = 0;
  if (!var || !IsNumeric(*var) || var->isComplex || !CountElements(*var, &count) ||
      count != v->count || !ToDoubles(*var, count, &v->values)) {
    ThrowDamaged(path, "variable '" + v->name + "' without the data its header announces");
  }
  for (size_t i = 0; i < count; ++i) {
    if (!std::isfinite(v->values[i])) {
      v->what += std::string(" with ") +
                 (std::isnan(v->values[i]) ? "NaN" : "an infinite value") + " at sample " +
                 std::to_string(i + 1);
      v->values.clear();
      return;
    }
  }
  v->vector = true;
}

}  // namespace

DataTable ReadMatFile(const std::string& path, const std::string& time_variable) {
  std::uintmax_t file_size = 0;
  {
    std::ifstream probe(path, std::ios::binary);
    std::error_code error;
    file_size = std::filesystem::file_size(path, error);
    if (!probe || error) {
      throw std::invalid_argument(
          path + ": cannot open for reading: " +
          (error ? error.message() : std::generic_category().message(errno)));
    }
    if (file_size == 0) {
      throw std::invalid_argument(path + ": expected a MAT file, got an empty file");
    }
  }
  std::vector<Variable> variables;
  const Variable* time = nullptr;
  {
    const std::lock_guard<std::mutex> lock(MatioMutex());
    std::string problem;
    const ProblemRecorder recorder(&problem);
    const std::unique_ptr<mat_t, MatCloser> mat(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
    if (!mat) {
      throw std::invalid_argument(
          path + ": expected a MAT file (MATLAB level 4, 5 or 7.3), got a file "
                 "matio cannot open as one" +
          (problem.empty() ? "" : " (matio: " + problem + ")"));
    }
    variables = ReadHeaders(path, mat.get(), problem, file_size);
    for (const Variable& v : variables) {
      if (v.name == time_variable) time = &v;
    }
    if (time == nullptr) {
      throw std::invalid_argument(path + ": expected a time variable '" + time_variable +
                                  "', got none; the variables are: " + NameList(variables));
    }
    // The values of the time variable and of every vector as long as it.
    if (time->candidate) {
      const size_t rows = time->count;
      for (Variable& v : variables) {
        if (v.candidate && v.count == rows) ReadValues(path, mat.get(), problem, &v);
      }
    }
  }
  if (!time->vector) {
    throw std::invalid_argument(path + ": variable '" + time_variable +
                                "' (the time): expected a real numeric vector of "
                                "finite values, at least one, got " +
                                time->what);
  }
  DataTable table;
  table.path = path;
  table.format = DataTable::Format::kMat;
  const size_t rows = time->count;
  table.column_rule = "a real numeric vector of " + std::to_string(rows) +
                      " finite values (as long as the time variable '" +
                      time_variable + "')";
  for (Variable& v : variables) {
    if (v.vector && v.values.size() == rows) {
      table.names.push_back(v.name);
      table.columns.push_back(std::move(v.values));
    } else {
      table.not_columns.emplace_back(v.name, v.what);
    }
  }
  return table;
}

}  // namespace axis
