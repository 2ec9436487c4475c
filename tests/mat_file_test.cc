// MATLAB MAT files as experiment data (io/mat_file.h, issue 13): the EMPS
// benchmark's original files give the CSVs' samples bit for bit and the same
// fit; bad files (a missing variable, a matrix where a vector is expected,
// unequal lengths, a non-numeric variable, a truncated file, a file that is
// not a MAT file) are std::invalid_argument naming the file and the
// variable and saying what was expected and what was got. The bad files are
// written here with matio's own write API.
#include <matio.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "estimation/fit.h"
#include "estimation/fit_result.h"
#include "run/fit_job.h"
#include "run/load_fit_job.h"
#include "io/csv.h"
#include "io/data_file.h"
#include "io/data_table.h"
#include "io/mat_file.h"
#include "tests/test_files.h"

namespace axis {
namespace {

using testing_files::TestTempDir;
using testing_files::WriteTemp;

const std::string kRoot = PROJECT_SOURCE_DIR;
const std::string kEmps = kRoot + "/testdata/emps/DATA_EMPS.mat";
const std::string kEmpsPulses = kRoot + "/testdata/emps/DATA_EMPS_PULSES.mat";

// A variable to write: its class, element type, dimensions and elements
// (raw bytes, real part; `imag` for a complex one).
struct MatVariable {
  std::string name;
  matio_classes class_type = MAT_C_DOUBLE;
  matio_types data_type = MAT_T_DOUBLE;
  std::vector<size_t> dims;
  std::vector<unsigned char> bytes;
  std::vector<unsigned char> imag;  // non-empty: complex
  bool logical = false;
  bool is_struct = false;  // a struct with no fields (bytes unused)
};

template <typename T>
std::vector<unsigned char> BytesOf(const std::vector<T>& values) {
  std::vector<unsigned char> bytes(values.size() * sizeof(T));
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  return bytes;
}

// A numeric variable of class `class_type` holding `values` (element type T).
template <typename T>
MatVariable Numeric(const std::string& name, matio_classes class_type,
                    matio_types data_type, std::vector<size_t> dims,
                    const std::vector<T>& values) {
  MatVariable v;
  v.name = name;
  v.class_type = class_type;
  v.data_type = data_type;
  v.dims = std::move(dims);
  v.bytes = BytesOf(values);
  return v;
}

// A double column vector (n x 1), or another shape.
MatVariable Doubles(const std::string& name, const std::vector<double>& values,
                    std::vector<size_t> dims = {}) {
  if (dims.empty()) dims = {values.size(), 1};
  return Numeric(name, MAT_C_DOUBLE, MAT_T_DOUBLE, std::move(dims), values);
}

// Writes `variables` to `path` as a MAT file of `version`.
void WriteMat(const std::string& path, const std::vector<MatVariable>& variables,
              mat_ft version = MAT_FT_MAT5,
              matio_compression compression = MAT_COMPRESSION_NONE) {
  mat_t* mat = Mat_CreateVer(path.c_str(), nullptr, version);
  ASSERT_NE(mat, nullptr) << path;
  for (const MatVariable& v : variables) {
    std::vector<size_t> dims = v.dims;
    matvar_t* var = nullptr;
    if (v.is_struct) {
      var = Mat_VarCreateStruct(v.name.c_str(), static_cast<int>(dims.size()),
                                dims.data(), nullptr, 0);
    } else if (!v.imag.empty()) {
      mat_complex_split_t split{const_cast<unsigned char*>(v.bytes.data()),
                                const_cast<unsigned char*>(v.imag.data())};
      var = Mat_VarCreate(v.name.c_str(), v.class_type, v.data_type,
                          static_cast<int>(dims.size()), dims.data(), &split, MAT_F_COMPLEX);
    } else {
      var = Mat_VarCreate(v.name.c_str(), v.class_type, v.data_type,
                          static_cast<int>(dims.size()), dims.data(),
                          const_cast<unsigned char*>(v.bytes.data()),
                          v.logical ? MAT_F_LOGICAL : 0);
    }
    ASSERT_NE(var, nullptr) << v.name;
    EXPECT_EQ(Mat_VarWrite(mat, var, compression), 0) << v.name;
    Mat_VarFree(var);
  }
  Mat_Close(mat);
}

// t = 0, 0.001, ..., (n - 1)·0.001 and x = 0.5·t, both n x 1.
std::vector<MatVariable> Good(size_t n = 5) {
  std::vector<double> t, x;
  for (size_t k = 0; k < n; ++k) {
    t.push_back(0.001 * static_cast<double>(k));
    x.push_back(0.5 * t.back());
  }
  return {Doubles("t", t), Doubles("x", x)};
}

// Writes Good(n) followed by `extra` to `name` in the test's directory.
std::string WriteGoodPlus(const std::string& name, const std::vector<MatVariable>& extra,
                          size_t n = 5) {
  const std::string path = TestTempDir() + name;
  std::vector<MatVariable> variables = Good(n);
  variables.insert(variables.end(), extra.begin(), extra.end());
  WriteMat(path, variables);
  return path;
}

// DataTable::Column's message for a variable `name` of a MAT file with time
// variable 't' of `rows` values, when the variable is `got`.
std::string ColumnError(const std::string& path, const std::string& name, size_t rows,
                        const std::string& got) {
  return path + ": variable '" + name + "': expected a real numeric vector of " +
         std::to_string(rows) + " finite values (as long as the time variable 't'), got " + got;
}

// ReadMatFile's message for a time variable `name` that is `got`.
std::string TimeError(const std::string& path, const std::string& name, const std::string& got) {
  return path + ": variable '" + name +
         "' (the time): expected a real numeric vector of finite values, at least one, got " +
         got;
}

// The message of the std::invalid_argument `f` throws; fails the test if it
// throws nothing or something else.
std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not std::invalid_argument: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no exception";
  return "";
}

// The MAT file `path`, Good() and the variables of `rejected` (name, what it
// is), reads as the columns t and x; naming a rejected variable as a column
// or as the time variable says what it is.
void ExpectRejected(const std::string& path,
                    const std::vector<std::pair<std::string, std::string>>& rejected) {
  const DataTable table = ReadMatFile(path, "t");
  EXPECT_EQ(table.NameList(), "t, x");
  for (const auto& variable : rejected) {
    EXPECT_EQ(ErrorOf([&] { table.Column(variable.first); }),
              ColumnError(path, variable.first, 5, variable.second));
    EXPECT_EQ(ErrorOf([&] { ReadMatFile(path, variable.first); }),
              TimeError(path, variable.first, variable.second));
  }
}

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

std::vector<char> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), {});
}

std::string WriteBytes(const std::string& name, const std::vector<char>& bytes, size_t size) {
  const std::string path = TestTempDir() + name;
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(size));
  return path;
}

// --- The EMPS files --------------------------------------------------------

// The benchmark's MAT files hold exactly the samples of the CSVs the project
// converted from them (testdata/emps/README.md), every bit; the scalars
// gtau, kp and kv are variables but not columns.
TEST(MatFileTest, EmpsFilesHoldTheCsvSamplesBitForBit) {
  const struct {
    std::string mat, csv;
    std::vector<std::pair<std::string, std::string>> pairs;
  } files[] = {
      {kEmps, kRoot + "/testdata/emps/DATA_EMPS.csv",
       {{"t", "t_s"}, {"qm", "qm_m"}, {"qg", "qg_m"}, {"vir", "vir_V"}}},
      {kEmpsPulses, kRoot + "/testdata/emps/DATA_EMPS_PULSES.csv",
       {{"t", "t_s"}, {"qm", "qm_m"}, {"qg", "qg_m"}, {"vir", "vir_V"},
        {"pulses_N", "pulse_inj_V"}}},
  };
  for (const auto& file : files) {
    const DataTable mat = ReadMatFile(file.mat, "t");
    const CsvTable csv = ReadCsv(file.csv);
    EXPECT_EQ(mat.format, DataTable::Format::kMat);
    EXPECT_EQ(mat.num_rows(), 24841u);
    EXPECT_EQ(mat.names.size(), file.pairs.size()) << mat.NameList();
    for (const auto& [variable, column] : file.pairs) {
      const std::vector<double>& a = mat.Column(variable);
      const std::vector<double>& b = csv.Column(column);
      ASSERT_EQ(a.size(), b.size()) << variable;
      size_t differ = 0;
      for (size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
      EXPECT_EQ(differ, 0u) << file.mat << ": " << variable << " vs " << column;
    }
    EXPECT_EQ(mat.DescribeName("kp"), "'kp' (a 1x1 double)");
    EXPECT_EQ(ErrorOf([&] { mat.Column("gtau"); }),
              ColumnError(file.mat, "gtau", 24841, "a 1x1 double"));
  }
}

// ReadDataTable picks the reader by the extension, in any case.
TEST(MatFileTest, ReadDataTableChoosesTheReaderByExtension) {
  const std::string upper = TestTempDir() + "good.MAT";
  WriteMat(upper, Good());
  EXPECT_EQ(ReadDataTable(upper, "t").format, DataTable::Format::kMat);
  const std::string csv = WriteTemp("good.csv", "t,x\n0,1\n0.001,2\n");
  EXPECT_EQ(ReadDataTable(csv, "t").format, DataTable::Format::kCsv);
  // A CSV named .mat is read as a MAT file, and says it is not one.
  const std::string text = WriteTemp("text.mat", "t,x\n0,1\n0.001,2\n");
  EXPECT_CONTAINS(ErrorOf([&] { ReadDataTable(text, "t"); }),
                  text + ": expected a MAT file (MATLAB level 4, 5 or 7.3), got a file "
                         "matio cannot open as one");
}

// --- What a column may be --------------------------------------------------

// Row and column vectors and every numeric class are columns, converted to
// double exactly; compressed level 5, level 7.3 (HDF5) and level 4 files
// read alike.
TEST(MatFileTest, ReadsNumericClassesShapesAndFileVersions) {
  const std::vector<double> t = {0.0, 0.5, 1.0};
  std::vector<MatVariable> variables = {
      Doubles("t", t, {1, 3}),  // a row vector
      Numeric("s", MAT_C_SINGLE, MAT_T_SINGLE, {3, 1}, std::vector<float>{0.25f, -1.5f, 3.0f}),
      Numeric("i16", MAT_C_INT16, MAT_T_INT16, {3, 1}, std::vector<int16_t>{-32768, 0, 32767}),
      Numeric("u8", MAT_C_UINT8, MAT_T_UINT8, {1, 3}, std::vector<uint8_t>{0, 1, 255}),
      Numeric("i64", MAT_C_INT64, MAT_T_INT64, {3, 1},
              std::vector<int64_t>{-(int64_t{1} << 53), 7, int64_t{1} << 53}),
      Numeric("u32", MAT_C_UINT32, MAT_T_UINT32, {1, 1, 3}, std::vector<uint32_t>{1, 2, 4294967295u}),
  };
  MatVariable flag = Numeric("flag", MAT_C_UINT8, MAT_T_UINT8, {3, 1}, std::vector<uint8_t>{1, 0, 1});
  flag.logical = true;
  variables.push_back(flag);
  const struct {
    const char* name;
    mat_ft version;
    matio_compression compression;
  } kinds[] = {{"v5.mat", MAT_FT_MAT5, MAT_COMPRESSION_NONE},
               {"v5z.mat", MAT_FT_MAT5, MAT_COMPRESSION_ZLIB},
               {"v73.mat", MAT_FT_MAT73, MAT_COMPRESSION_NONE}};
  for (const auto& kind : kinds) {
    SCOPED_TRACE(kind.name);
    const std::string path = TestTempDir() + kind.name;
    WriteMat(path, variables, kind.version, kind.compression);
    const DataTable table = ReadMatFile(path, "t");
    // Level 7.3 (HDF5) lists the variables by name.
    EXPECT_EQ(table.NameList(), kind.version == MAT_FT_MAT73 ? "flag, i16, i64, s, t, u32, u8"
                                                             : "t, s, i16, u8, i64, u32, flag");
    EXPECT_TRUE(table.not_columns.empty());
    EXPECT_EQ(table.Column("t"), t);
    EXPECT_EQ(table.Column("s"), (std::vector<double>{0.25, -1.5, 3.0}));
    EXPECT_EQ(table.Column("i16"), (std::vector<double>{-32768, 0, 32767}));
    EXPECT_EQ(table.Column("u8"), (std::vector<double>{0, 1, 255}));
    EXPECT_EQ(table.Column("i64"), (std::vector<double>{-9007199254740992.0, 7, 9007199254740992.0}));
    EXPECT_EQ(table.Column("u32"), (std::vector<double>{1, 2, 4294967295.0}));
    EXPECT_EQ(table.Column("flag"), (std::vector<double>{1, 0, 1}));
  }
  // Level 4 holds doubles only.
  const std::string v4 = TestTempDir() + "v4.mat";
  WriteMat(v4, Good(), MAT_FT_MAT4);
  const DataTable table = ReadMatFile(v4, "t");
  EXPECT_EQ(table.NameList(), "t, x");
  EXPECT_EQ(table.Column("x")[4], 0.5 * 0.004);
}

// --- Bad input: each case names the file and the variable ------------------

TEST(MatFileTest, MissingVariable) {
  const std::string path = WriteGoodPlus("data.mat", {});
  const DataTable table = ReadMatFile(path, "t");
  EXPECT_EQ(ErrorOf([&] { table.Column("qm"); }),
            path + ": no variable 'qm'; expected one of: t, x");
  // The time variable itself.
  EXPECT_EQ(ErrorOf([&] { ReadMatFile(path, "time"); }),
            path + ": expected a time variable 'time', got none; the variables are: t, x");
}

TEST(MatFileTest, MatrixWhereAVectorIsExpected) {
  const std::string path =
      WriteGoodPlus("matrix.mat", {Doubles("M", std::vector<double>(12, 1.0), {3, 4}),
                                   Doubles("A", std::vector<double>(30, 1.0), {5, 3, 2})});
  ExpectRejected(path, {{"M", "a 3x4 double matrix"}, {"A", "a 5x3x2 double array"}});
}

TEST(MatFileTest, UnequalLengths) {
  const std::string path =
      WriteGoodPlus("lengths.mat", {Doubles("short", {1.0, 2.0, 3.0, 4.0}),
                                    Doubles("long_row", std::vector<double>(6, 0.0), {1, 6})});
  const DataTable table = ReadMatFile(path, "t");
  EXPECT_EQ(ErrorOf([&] { table.Column("short"); }),
            ColumnError(path, "short", 5, "a 4x1 double vector"));
  EXPECT_CONTAINS(ErrorOf([&] { table.Column("long_row"); }), "got a 1x6 double vector");
  // Measured from the time variable: with `short` as the time, x is the odd one.
  const DataTable by_short = ReadMatFile(path, "short");
  EXPECT_EQ(by_short.NameList(), "short");
  EXPECT_CONTAINS(ErrorOf([&] { by_short.Column("x"); }),
                  "expected a real numeric vector of 4 finite values (as long as the time "
                  "variable 'short'), got a 5x1 double vector");
}

TEST(MatFileTest, NonNumericVariables) {
  MatVariable record;
  record.name = "record";
  record.dims = {1, 1};
  record.is_struct = true;
  MatVariable complex = Doubles("z", std::vector<double>(5, 1.0));
  complex.imag = BytesOf(std::vector<double>(5, 2.0));
  const std::string path = WriteGoodPlus(
      "kinds.mat",
      {Numeric("label", MAT_C_CHAR, MAT_T_UTF8, {1, 5}, std::vector<char>{'h', 'e', 'l', 'l', 'o'}),
       record, complex});
  ExpectRejected(path, {{"label", "a 1x5 char array"},
                        {"record", "a 1x1 struct"},
                        {"z", "a 5x1 complex double vector"}});
}

TEST(MatFileTest, NonFiniteAndEmptyVariables) {
  const std::string path = WriteGoodPlus(
      "nan.mat",
      {Doubles("gap", {1.0, 2.0, std::nan(""), 4.0, 5.0}),
       Doubles("big", {1.0, 2.0, 3.0, 4.0, std::numeric_limits<double>::infinity()}),
       Doubles("none", {}, {0, 0})});
  ExpectRejected(path, {{"gap", "a 5x1 double vector with NaN at sample 3"},
                        {"big", "a 5x1 double vector with an infinite value at sample 5"},
                        {"none", "a 0x0 empty double"}});
}

// A time variable that does not increase: the sample is named, 1-based.
TEST(MatFileTest, TimeNotIncreasingNamesTheSample) {
  const std::string path = TestTempDir() + "time.mat";
  WriteMat(path, {Doubles("t", {0.0, 2.0, 1.0}), Doubles("x", {1.0, 2.0, 3.0})});
  const DataTable table = ReadMatFile(path, "t");
  EXPECT_EQ(ErrorOf([&] { CheckStrictlyIncreasing(table, "t"); }),
            path + ": sample 3: expected variable 't' strictly increasing, got 1 after 2");
}

// matio does not write a name twice: the second name is patched in the
// bytes of an uncompressed file ("dup2" stored as a 4-byte small element).
TEST(MatFileTest, DuplicateVariableNames) {
  const std::string written =
      WriteGoodPlus("two.mat", {Doubles("dup1", std::vector<double>(5, 1.0)),
                                Doubles("dup2", std::vector<double>(5, 2.0))});
  std::vector<char> bytes = ReadBytes(written);
  const std::string text(bytes.begin(), bytes.end());
  const size_t at = text.find("dup2");
  ASSERT_NE(at, std::string::npos);
  ASSERT_EQ(text.find("dup2", at + 1), std::string::npos);
  bytes[at + 3] = '1';
  const std::string path = WriteBytes("twice.mat", bytes, bytes.size());
  EXPECT_EQ(ErrorOf([&] { ReadMatFile(path, "t"); }),
            path + ": expected unique variable names, got 'dup1' twice");
}

// A file cut short: the EMPS file at half its length (inside the compressed
// data of a variable) and one byte short.
TEST(MatFileTest, TruncatedFile) {
  const std::vector<char> bytes = ReadBytes(kEmps);
  ASSERT_GT(bytes.size(), 1000u);
  for (const size_t size : {bytes.size() / 2, bytes.size() - 1}) {
    const std::string path = WriteBytes("truncated.mat", bytes, size);
    const std::string error = ErrorOf([&] { ReadMatFile(path, "t"); });
    EXPECT_CONTAINS(error, path + ": expected a complete MAT file, got a truncated or "
                                  "damaged one (matio: ");
  }
}

// Cut anywhere (every 97th byte of a small uncompressed and a small
// compressed file, and 40 places in the EMPS file), a file is either
// rejected or, cut between two variables, a complete file of fewer
// variables: never a column of wrong values.
TEST(MatFileTest, TruncatedAnywhereNeverGivesWrongValues) {
  std::vector<MatVariable> variables = Good(200);
  variables.push_back(Doubles("y", std::vector<double>(200, 3.25)));
  const std::string plain = TestTempDir() + "plain.mat";
  const std::string zipped = TestTempDir() + "zipped.mat";
  WriteMat(plain, variables);
  WriteMat(zipped, variables, MAT_FT_MAT5, MAT_COMPRESSION_ZLIB);
  for (const std::string& source : {plain, zipped, kEmps}) {
    const std::vector<char> bytes = ReadBytes(source);
    const DataTable full = ReadMatFile(source, "t");
    const size_t stride = source == kEmps ? bytes.size() / 40 : 97;
    int rejected = 0, shorter = 0;
    for (size_t size = 0; size < bytes.size(); size += stride) {
      const std::string path = WriteBytes("cut.mat", bytes, size);
      try {
        const DataTable table = ReadMatFile(path, "t");
        ++shorter;
        EXPECT_LT(table.names.size() + table.not_columns.size(),
                  full.names.size() + full.not_columns.size())
            << source << " cut at " << size;
        for (const std::string& name : table.names) {
          EXPECT_EQ(table.Column(name), full.Column(name)) << source << " cut at " << size;
        }
      } catch (const std::invalid_argument& e) {
        ++rejected;
        EXPECT_NE(std::string(e.what()).find(path + ": "), std::string::npos) << e.what();
      }
    }
    RecordProperty(std::filesystem::path(source).filename().string() + "_rejected", rejected);
    EXPECT_GT(rejected, shorter) << source;
  }
}

TEST(MatFileTest, NotAMatFile) {
  const std::string text = WriteTemp("notes.mat", std::string(300, 'x'));
  EXPECT_CONTAINS(ErrorOf([&] { ReadMatFile(text, "t"); }),
                  text + ": expected a MAT file (MATLAB level 4, 5 or 7.3), got a file matio "
                         "cannot open as one");
  const std::string empty = WriteTemp("empty.mat", "");
  EXPECT_EQ(ErrorOf([&] { ReadMatFile(empty, "t"); }),
            empty + ": expected a MAT file, got an empty file");
  const std::string missing = TestTempDir() + "missing.mat";
  EXPECT_EQ(ErrorOf([&] { ReadMatFile(missing, "t"); }),
            missing + ": cannot open for reading: No such file or directory");
  EXPECT_CONTAINS(ErrorOf([&] { ReadMatFile(TestTempDir(), "t"); }), "cannot open for reading");
  // A MAT header and nothing after it: a file without variables.
  const std::string bare = WriteBytes("header_only.mat", ReadBytes(kEmps), 128);
  EXPECT_EQ(ErrorOf([&] { ReadMatFile(bare, "t"); }),
            bare + ": expected a time variable 't', got none; the variables are: (none)");
}

// --- In a fit job ----------------------------------------------------------

void ExpectSameSignal(const InputSignal& a, const InputSignal& b, const std::string& what) {
  EXPECT_EQ(a.kind, b.kind) << what;
  EXPECT_EQ(a.hold, b.hold) << what;
  EXPECT_EQ(a.offset, b.offset) << what;
  EXPECT_EQ(a.times, b.times) << what;
  EXPECT_EQ(a.values, b.values) << what;
}

// configs/jobs/emps_mat.yaml loads every experiment exactly as
// configs/jobs/emps.yaml: the same samples, drive signals, initial states
// and time grids.
TEST(MatFileJobTest, EmpsJobLoadsTheSameExperimentsAsFromTheCsvs) {
  const FitJob csv = LoadFitJob(kRoot + "/configs/jobs/emps.yaml");
  const FitJob mat = LoadFitJob(kRoot + "/configs/jobs/emps_mat.yaml");
  const std::vector<FitExperiment>* lists[][2] = {{&csv.problem.experiments, &mat.problem.experiments},
                                                  {&csv.problem.validate, &mat.problem.validate}};
  size_t compared = 0;
  for (const auto& pair : lists) {
    ASSERT_EQ(pair[0]->size(), pair[1]->size());
    for (size_t i = 0; i < pair[0]->size(); ++i) {
      const FitExperiment& a = (*pair[0])[i];
      const FitExperiment& b = (*pair[1])[i];
      SCOPED_TRACE(a.name);
      EXPECT_EQ(a.name, b.name);
      EXPECT_EQ(a.t, b.t);
      EXPECT_EQ(a.t_offset, b.t_offset);
      EXPECT_EQ(a.measured_channels, b.measured_channels);
      EXPECT_EQ(a.measured, b.measured);
      EXPECT_EQ(a.fitted.size(), b.fitted.size());
      EXPECT_EQ(a.initial_state, b.initial_state);
      EXPECT_EQ(a.options.duration, b.options.duration);
      EXPECT_EQ(a.options.output_period, b.options.output_period);
      EXPECT_EQ(a.drive.closed_loop, b.drive.closed_loop);
      EXPECT_EQ(a.drive.has_injection, b.drive.has_injection);
      ExpectSameSignal(a.drive.input, b.drive.input, "input");
      ExpectSameSignal(a.drive.reference.table, b.drive.reference.table, "reference");
      ExpectSameSignal(a.drive.injection, b.drive.injection, "injection");
      EXPECT_EQ(a.input_notes.size(), b.input_notes.size());
      ++compared;
    }
  }
  EXPECT_EQ(compared, 3u);
}

// The EMPS job's fit on the first 2 s of the estimation run, from the CSV
// and from the MAT file: the same estimates, standard errors and cost, to
// the last bit.
TEST(MatFileJobTest, ShortEmpsFitIsTheSameFromTheMatFile) {
  const auto job = [](const std::string& data, const std::string& time,
                      const std::string& channels, const std::string& reference) {
    return "model: " + kRoot + "/configs/axes/emps.yaml\n"
           "simulation: {step: 1.0e-4}\n"
           "free:\n"
           "  M:   {initial: 80,  lower: 10, upper: 500}\n"
           "  B_a: {initial: 150, lower: 1,  upper: 2000}\n"
           "experiments:\n"
           "  - name: emps\n"
           "    data: " + kRoot + "/testdata/emps/" + data + "\n"
           "    time: " + time + "\n"
           "    window: [0, 2]\n"
           "    channels: " + channels + "\n"
           "    reference: {column: " + reference + "}\n"
           "    fit: {x: 5.0e-6, u: 0.1}\n"
           "solver: {threads: 1, probe_rounds: 0}\n"
           "uncertainty: {method: gauss_newton}\n";
  };
  FitJob from_csv = LoadFitJob(
      WriteTemp("csv.yaml", job("DATA_EMPS.csv", "t_s", "{x: qm_m, u: vir_V}", "qg_m")));
  FitJob from_mat =
      LoadFitJob(WriteTemp("mat.yaml", job("DATA_EMPS.mat", "t", "{x: qm, u: vir}", "qg")));
  from_csv.problem.solver.progress = false;
  from_mat.problem.solver.progress = false;
  const FitResult a = FitParameters(from_csv.problem);
  const FitResult b = FitParameters(from_mat.problem);
  ASSERT_EQ(a.parameters.size(), b.parameters.size());
  for (size_t i = 0; i < a.parameters.size(); ++i) {
    EXPECT_EQ(a.parameters[i].name, b.parameters[i].name);
    EXPECT_EQ(a.parameters[i].value, b.parameters[i].value) << a.parameters[i].name;
    if (a.parameters[i].free) {
      EXPECT_EQ(a.parameters[i].std_error, b.parameters[i].std_error) << a.parameters[i].name;
      RecordProperty(a.parameters[i].name, std::to_string(a.parameters[i].value));
    }
  }
  EXPECT_EQ(a.final_cost, b.final_cost);
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_TRUE(a.converged);
}

// A job naming a MAT variable that is not a column: the error names the
// YAML file, line and key, the MAT file and the variable, and says what it
// is; a missing one lists the variables.
TEST(MatFileJobTest, JobErrorsNameTheKeyTheFileAndTheVariable) {
  const std::string data =
      WriteGoodPlus("log.mat", {Doubles("M", std::vector<double>(12, 1.0), {3, 4})}, 50);
  const auto job = [&](const std::string& channels) {
    return WriteTemp("job.yaml",
                     "model: " + kRoot + "/configs/axes/emps.yaml\n"
                     "free:\n"
                     "  M: {initial: 95, lower: 10, upper: 500}\n"
                     "experiments:\n"
                     "  - name: log\n"
                     "    data: " + data + "\n"
                     "    channels: " + channels + "\n"
                     "    input: {column: x}\n"
                     "    fit: {x: 1.0e-6}\n");
  };
  const std::string matrix = job("{x: M}");
  EXPECT_EQ(ErrorOf([&] { LoadFitJob(matrix); }),
            matrix + ":7: key 'experiments[0].channels.x': expected a variable of " + data +
                " that is a real numeric vector of 50 finite values (as long as the time "
                "variable 't') (t, x), got 'M' (a 3x4 double matrix)");
  const std::string missing = job("{x: qm}");
  EXPECT_CONTAINS(ErrorOf([&] { LoadFitJob(missing); }),
                  "key 'experiments[0].channels.x': expected a variable of " + data);
  EXPECT_CONTAINS(ErrorOf([&] { LoadFitJob(missing); }), "(t, x), got 'qm'");
  const FitJob good = LoadFitJob(job("{x: x}"));
  EXPECT_EQ(good.problem.experiments[0].measured[0].size(), 50u);
}

// One dropped sample in a MAT log's time (issue 46) is named at its sample,
// with the step found there, not at sample 2 against a mean period the gap
// skews.
TEST(MatFileJobTest, ADroppedSampleIsNamedAtItsSample) {
  std::vector<double> t, x;
  for (int k = 0; k < 50; ++k) {
    if (k == 20) continue;  // dropped
    t.push_back(0.001 * k);
    x.push_back(0.5 * t.back());
  }
  const std::string data = TestTempDir() + "gap.mat";
  WriteMat(data, {Doubles("t", t), Doubles("x", x)});
  const std::string job = WriteTemp("gap.yaml",
                                    "model: " + kRoot + "/configs/axes/emps.yaml\n"
                                    "free:\n  M: {initial: 95, lower: 10, upper: 500}\n"
                                    "experiments:\n  - name: log\n    data: " + data + "\n"
                                    "    channels: {x: x}\n    input: {column: x}\n"
                                    "    fit: {x: 1.0e-6}\n");
  EXPECT_EQ(ErrorOf([&] { LoadFitJob(job); }),
            data + ": sample 21: expected uniform sampling (the median step 0.001 s within "
                   "0.1 %), got a step of 0.002 s from 0.019 to 0.021 s (a gap: a dropped "
                   "sample?)");
}

}  // namespace
}  // namespace axis
