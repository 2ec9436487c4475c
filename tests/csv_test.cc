#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/csv.h"

namespace axis {
namespace {

namespace fs = std::filesystem;

// Each test works in its own fresh directory under ::testing::TempDir().
class CsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* info =
        ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           ("csv_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }

  std::string PathOf(const std::string& name) const {
    return (dir_ / name).string();
  }

  // Writes `text` byte for byte to a file in the test directory.
  std::string WriteText(const std::string& name, const std::string& text) {
    const std::string path = PathOf(name);
    std::ofstream out(path, std::ios::binary);
    out << text;
    EXPECT_TRUE(out.good()) << path;
    return path;
  }

  static std::string ReadText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // Names of the files in the test directory.
  std::vector<std::string> Listing() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      names.push_back(entry.path().filename().string());
    }
    return names;
  }

  // Expects ReadCsv of a file holding `text` to throw std::invalid_argument
  // whose message starts with "<path><location>" (e.g. ":3: " or ": ") and
  // contains every one of `parts`; and ParseCsv of the text alike, with its
  // name in place of the path.
  void ExpectReadError(const std::string& text, const std::string& location,
                       const std::vector<std::string>& parts) {
    const std::string path = WriteText("bad.csv", text);
    ExpectInvalidArgument([&] { ReadCsv(path); }, path + location, parts);
    ExpectInvalidArgument([&] { ParseCsv(text, "memory.csv"); }, "memory.csv" + location,
                          parts);
  }

  template <typename F>
  static void ExpectInvalidArgument(F f, const std::string& prefix,
                                    const std::vector<std::string>& parts) {
    EXPECT_THROW(f(), std::invalid_argument);
    try {
      f();
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(prefix, 0), 0u)
          << "expected prefix: " << prefix << "\nmessage: " << message;
      for (const std::string& part : parts) {
        EXPECT_NE(message.find(part), std::string::npos)
            << "expected: " << part << "\nmessage: " << message;
      }
    } catch (...) {
    }
  }

  fs::path dir_;
};

TEST_F(CsvTest, RoundTripIsExactAtPrecision17) {
  const std::vector<std::string> names = {"t_s", "qm_m", "tiny"};
  const std::vector<std::vector<double>> columns = {
      {0.0, 0.1, 1.0 / 3.0, 2.0 / 3.0, 1e-3},
      {-0.0, -1.2345678901234567, 6.02214076e23,
       std::numeric_limits<double>::max(), -std::numeric_limits<double>::min()},
      {std::numeric_limits<double>::denorm_min(), 1e-300,
       std::nextafter(1.0, 2.0), std::nextafter(0.1, 0.0),
       123456789012345678.0},
  };
  const std::string path = PathOf("round_trip.csv");
  WriteCsvAtomic(path, names, columns, 17);
  const CsvTable table = ReadCsv(path);
  EXPECT_EQ(table.path, path);
  EXPECT_EQ(table.names, names);
  ASSERT_EQ(table.columns.size(), columns.size());
  EXPECT_EQ(table.num_rows(), 5u);
  for (size_t j = 0; j < columns.size(); ++j) {
    ASSERT_EQ(table.columns[j].size(), columns[j].size());
    for (size_t i = 0; i < columns[j].size(); ++i) {
      EXPECT_EQ(table.columns[j][i], columns[j][i])
          << "column " << j << " row " << i;
      EXPECT_EQ(std::signbit(table.columns[j][i]), std::signbit(columns[j][i]));
    }
  }
  EXPECT_EQ(Listing(), std::vector<std::string>{"round_trip.csv"});
}

TEST_F(CsvTest, DefaultPrecisionIsTwelveSignificantDigits) {
  const std::string path = PathOf("out.csv");
  WriteCsvAtomic(path, {"x", "y"}, {{0.1 + 0.2, 1e-20}, {1.0 / 3.0, -2.0}});
  EXPECT_EQ(ReadText(path), "x,y\n0.3,0.333333333333\n1e-20,-2\n");
}

TEST_F(CsvTest, WritesNamesThatNeedQuotesAndReadsThemBack) {
  const std::vector<std::string> names = {"a,b", "say \"hi\"", " padded ",
                                          "plain"};
  const std::string path = PathOf("names.csv");
  WriteCsvAtomic(path, names, {{1}, {2}, {3}, {4}});
  EXPECT_EQ(ReadText(path),
            "\"a,b\",\"say \"\"hi\"\"\",\" padded \",plain\n1,2,3,4\n");
  EXPECT_EQ(ReadCsv(path).names, names);
}

TEST_F(CsvTest, ReadsTableAndLooksUpColumns) {
  const std::string path =
      WriteText("in.csv", "t_s,qm_m,u_V\n0,1.5,-2\n0.001,2.5e-3,3\n");
  const CsvTable table = ReadCsv(path);
  EXPECT_EQ(table.names, (std::vector<std::string>{"t_s", "qm_m", "u_V"}));
  EXPECT_EQ(table.num_rows(), 2u);
  EXPECT_EQ(table.ColumnIndex("u_V"), 2u);
  EXPECT_TRUE(table.HasColumn("qm_m"));
  EXPECT_FALSE(table.HasColumn("QM_M"));
  EXPECT_EQ(table.Column("t_s"), (std::vector<double>{0.0, 0.001}));
  EXPECT_EQ(table.Column("qm_m"), (std::vector<double>{1.5, 2.5e-3}));
  EXPECT_EQ(table.Column("u_V"), (std::vector<double>{-2.0, 3.0}));
}

TEST_F(CsvTest, MissingColumnListsTheColumns) {
  const std::string path = WriteText("in.csv", "t_s,qm_m\n0,1\n");
  const CsvTable table = ReadCsv(path);
  for (auto lookup : {+[](const CsvTable& t) { t.ColumnIndex("q"); },
                      +[](const CsvTable& t) { t.Column("q"); }}) {
    ExpectInvalidArgument([&] { lookup(table); }, path + ": ",
                          {"no column 'q'; expected one of: t_s, qm_m"});
  }
  EXPECT_EQ(CsvTable().num_rows(), 0u);
}

TEST_F(CsvTest, ParsesCrlfAndQuotedHeaderNames) {
  const std::string path = WriteText(
      "crlf.csv",
      "\"t_s\",\"q, rad\",\"say \"\"x\"\"\"\r\n0,1,2\r\n0.5,\"3\",4\r\n");
  const CsvTable table = ReadCsv(path);
  EXPECT_EQ(table.names,
            (std::vector<std::string>{"t_s", "q, rad", "say \"x\""}));
  EXPECT_EQ(table.Column("t_s"), (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(table.Column("q, rad"), (std::vector<double>{1.0, 3.0}));
  EXPECT_EQ(table.Column("say \"x\""), (std::vector<double>{2.0, 4.0}));
}

TEST_F(CsvTest, CrlfErrorsReportTheRightLine) {
  ExpectReadError("t,x\r\n0,1\r\n1,2\r\n2,oops\r\n",
                  ":4: ", {"column 'x'", "'oops'"});
  ExpectReadError("t,x\r0,1\r1,2\r2,oops\r", ":4: ", {"'oops'"});  // CR only
}

TEST_F(CsvTest, AcceptsSpacesByteOrderMarkAndNoFinalNewline) {
  const std::string path =
      WriteText("in.csv", "\xEF\xBB\xBF t , x\n  1 ,\t2\t\n\" 3 \", -4e1");
  const CsvTable table = ReadCsv(path);
  EXPECT_EQ(table.names, (std::vector<std::string>{"t", "x"}));
  EXPECT_EQ(table.Column("t"), (std::vector<double>{1.0, 3.0}));
  EXPECT_EQ(table.Column("x"), (std::vector<double>{2.0, -40.0}));
}

TEST_F(CsvTest, IgnoresBlankTrailingLines) {
  const std::string path = WriteText("in.csv", "t,x\n0,1\n1,2\n\n  \n\r\n\n");
  const CsvTable table = ReadCsv(path);
  EXPECT_EQ(table.num_rows(), 2u);
  EXPECT_EQ(table.Column("x"), (std::vector<double>{1.0, 2.0}));
}

TEST_F(CsvTest, FileThatCannotBeOpened) {
  const std::string path = PathOf("missing.csv");
  ExpectInvalidArgument([&] { ReadCsv(path); }, path + ": ",
                        {"cannot open", "No such file"});
  const std::string directory = dir_.string();
  ExpectInvalidArgument([&] { ReadCsv(directory); }, directory + ": ",
                        {"cannot"});
}

TEST_F(CsvTest, EmptyFile) {
  ExpectReadError("", ": ", {"expected a header row, got an empty file"});
  ExpectReadError("\n\r\n  \n", ": ",
                  {"expected a header row, got an empty file"});
}

TEST_F(CsvTest, HeaderWithoutDataRows) {
  for (const char* text : {"t,x", "t,x\n", "t,x\r\n\r\n\n"}) {
    ExpectReadError(text, ": ",
                    {"expected at least one data row after the header, got "
                     "none"});
  }
}

TEST_F(CsvTest, EmptyColumnName) {
  ExpectReadError("t,,x\n0,1,2\n",
                  ":1: ", {"expected a name for column 2", "got an empty one"});
  ExpectReadError("t,x,\n0,1,2\n", ":1: ", {"column 3", "got an empty one"});
  ExpectReadError("t,\"  \"\n0,1\n", ":1: ", {"column 2", "got an empty one"});
}

TEST_F(CsvTest, DuplicatedColumnName) {
  ExpectReadError(
      "t,x,y,x\n0,1,2,3\n", ":1: ",
      {"expected unique column names", "got 'x' twice", "columns 2 and 4"});
}

TEST_F(CsvTest, RowWithWrongFieldCount) {
  ExpectReadError("t,x,y\n0,1,2\n1,2\n",
                  ":3: ", {"expected 3 fields as in the header, got 2"});
  ExpectReadError("t,x,y\n0,1,2\n1,2,3\n2,3,4,5\n",
                  ":4: ", {"expected 3 fields as in the header, got 4"});
  ExpectReadError("t,x\n0,1,\n",
                  ":2: ", {"expected 2 fields as in the header, got 3"});
  // The field count is reported before a bad cell in the same row.
  ExpectReadError("t,x,y\n0,1,2\nabc,2\n", ":3: ", {"got 2"});
}

TEST_F(CsvTest, EmptyCell) {
  ExpectReadError("t,x\n0,1\n1,\n", ":3: ",
                  {"expected a number in column 'x', got an empty cell"});
  ExpectReadError("t,x\n0,1\n,2\n", ":3: ",
                  {"expected a number in column 't', got an empty cell"});
  ExpectReadError("t,x\n0,\"\"\n", ":2: ",
                  {"expected a number in column 'x', got an empty cell"});
  ExpectReadError("t,x\n0,\" \"\n", ":2: ", {"got an empty cell"});
}

TEST_F(CsvTest, NonNumericCell) {
  ExpectReadError("t,x\n0,1\n1,abc\n",
                  ":3: ", {"expected a number in column 'x', got 'abc'"});
  ExpectReadError("t,x\n0,1.5x\n",
                  ":2: ", {"expected a number in column 'x', got '1.5x'"});
  ExpectReadError("t,x\n0,1 2\n", ":2: ", {"got '1 2'"});
  ExpectReadError("t,x\n0,1,5\n", ":2: ", {"expected 2 fields"});
  ExpectReadError("t,x\n0,\"1,5\"\n", ":2: ", {"got '1,5'"});
  ExpectReadError("t,x\n0," + std::string(100, '7') + "z\n",
                  ":2: ", {"got '7777", "...' (101 characters)"});
}

TEST_F(CsvTest, NanOrInfiniteCell) {
  ExpectReadError("t,x\n0,1\n1,nan\n", ":3: ",
                  {"expected a finite number in column 'x', got 'nan' (NaN)"});
  ExpectReadError("t,x\n0,NaN\n", ":2: ", {"got 'NaN' (NaN)"});
  ExpectReadError(
      "t,x\n0,-inf\n", ":2: ",
      {"expected a finite number in column 'x'", "got '-inf' (infinite)"});
  ExpectReadError("t,x\n0,Infinity\n", ":2: ", {"(infinite)"});
  ExpectReadError("t,x\n1e999,0\n",
                  ":2: ", {"column 't'", "got '1e999' (infinite)"});
}

TEST_F(CsvTest, BlankLineBeforeMoreRows) {
  ExpectReadError("t,x\n0,1\n\n1,2\n", ":3: ",
                  {"expected 2 fields as in the header, got a blank line"});
  ExpectReadError("\nt,x\n0,1\n",
                  ":1: ", {"expected the header row, got a blank line"});
}

TEST_F(CsvTest, MalformedQuoting) {
  ExpectReadError(
      "t,x\n0,1\n1,2\"3\n", ":3: ",
      {"expected quotes only around whole fields", "got a stray quote"});
  ExpectReadError("t,x\n0,\"1\"2\n", ":2: ", {"got a stray quote"});
  ExpectReadError("t,x\n0,1\n1,\"2\n", ":3: ",
                  {"expected a closing quote, got the end of the file"});
  ExpectReadError("t,x\n0,1\n1,\"2\n3\"\n", ":3: ",
                  {"expected each row on one line",
                   "got a line break inside a quoted field"});
  ExpectReadError("\"t\nx\"\n0\n",
                  ":1: ", {"got a line break inside a quoted field"});
}

// Bytes that are not UTF-8 text (issue 46): a NUL byte cut the message at
// the NUL and other bytes went into it raw; now the byte, its offset and
// line are named, and an error on an earlier line still comes first.
TEST_F(CsvTest, TextThatIsNotUtf8IsRefusedWithItsOffset) {
  ExpectReadError(std::string("t,x\n0,1\n1,\0\n", 12), ":3: ",
                  {"expected UTF-8 text, got a NUL byte at byte offset 10 (not UTF-8 text"});
  ExpectReadError("t,x\n0,1\n1,\xff\n", ":3: ",
                  {"got byte 0xFF at byte offset 10 (not UTF-8 text"});
  // UTF-16 (little-endian, with its byte order mark) of "t,x\n0,1\n".
  std::string utf16 = "\xff\xfe";
  for (const char c : std::string("t,x\n0,1\n")) utf16 += std::string(1, c) + '\0';
  ExpectReadError(utf16, ":1: ",
                  {"got byte 0xFF at byte offset 0 (not UTF-8 text; a UTF-16 file?"});
  ExpectReadError("t,x\r\n0,1\r\n1,\xc3(\r\n", ":3: ", {"byte 0xC3 at byte offset 12"});
  ExpectReadError("t,x\n0,1\n1,2\xe2\x82", ":3: ",
                  {"byte 0xE2 at byte offset 11, a character cut off by the end of the text"});
  ExpectReadError("t,x\n0,y\n1,\xff\n", ":2: ", {"expected a number in column 'x'"});
  // Beyond the first 64 KiB read (kChunkSize): the offset counts from the file's start.
  std::string big = "t,x\n";
  while (big.size() < 70000) big += "0,1\n";
  const size_t offset = big.size();
  const size_t line = 1 + offset / 4;
  ExpectReadError(big + "\x80,1\n", ":" + std::to_string(line) + ": ",
                  {"byte 0x80 at byte offset " + std::to_string(offset)});
  // UTF-8 names still read, with or without a byte order mark.
  const CsvTable table = ParseCsv("\xef\xbb\xbft,caf\xc3\xa9,\xe2\x82\xac\n0,1,2\n", "utf8.csv");
  EXPECT_EQ(table.names[1], "caf\xc3\xa9");
  EXPECT_EQ(table.names[2], "\xe2\x82\xac");
}

TEST_F(CsvTest, CheckStrictlyIncreasingAcceptsIncreasingColumn) {
  const CsvTable table =
      ReadCsv(WriteText("in.csv", "t,x\n0,5\n0.001,5\n0.002,4\n"));
  EXPECT_NO_THROW(CheckStrictlyIncreasing(table, "t"));
}

TEST_F(CsvTest, CheckStrictlyIncreasingReportsEqualAndDecreasingRows) {
  const std::string path =
      WriteText("in.csv", "t,x\n0,0\n0.001,1\n0.002,2\n0.002,3\n0.003,4\n");
  const CsvTable table = ReadCsv(path);
  ExpectInvalidArgument([&] { CheckStrictlyIncreasing(table, "t"); },
                        path + ":5: ",
                        {"expected column 't' strictly increasing, got 0.002 "
                         "after 0.002"});

  const std::string path2 =
      WriteText("in2.csv", "t,x\r\n0,0\r\n0.1,1\r\n0.3,2\r\n0.2,3\r\n");
  ExpectInvalidArgument(
      [&] { CheckStrictlyIncreasing(ReadCsv(path2), "t"); }, path2 + ":5: ",
      {"expected column 't' strictly increasing, got 0.2 after 0.3"});

  EXPECT_NO_THROW(CheckStrictlyIncreasing(table, "x"));
  ExpectInvalidArgument([&] { CheckStrictlyIncreasing(table, "q"); },
                        path + ": ", {"no column 'q'"});

  CsvTable with_nan;
  with_nan.path = "mem";
  with_nan.names = {"t"};
  with_nan.columns = {{0.0, std::nan(""), 1.0}};
  ExpectInvalidArgument([&] { CheckStrictlyIncreasing(with_nan, "t"); },
                        "mem:3: ", {"got nan after 0"});
}

TEST_F(CsvTest, WriteFileAtomicWritesAndReplaces) {
  const std::string path = PathOf("file.txt");
  WriteFileAtomic(path, "first version, longer\n");
  EXPECT_EQ(ReadText(path), "first version, longer\n");
  WriteFileAtomic(path, "second\n");
  EXPECT_EQ(ReadText(path), "second\n");
  WriteFileAtomic(path, "");
  EXPECT_EQ(ReadText(path), "");
  EXPECT_EQ(Listing(), std::vector<std::string>{"file.txt"});
}

TEST_F(CsvTest, WriteFileAtomicIntoMissingDirectoryThrowsAndLeavesNothing) {
  const std::string path = PathOf("no_such_dir/file.csv");
  EXPECT_THROW(WriteFileAtomic(path, "x\n1\n"), std::runtime_error);
  try {
    WriteFileAtomic(path, "x\n1\n");
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(Listing().empty());
  EXPECT_THROW(WriteCsvAtomic(path, {"x"}, {{1.0}}), std::runtime_error);
  EXPECT_TRUE(Listing().empty());
}

// CheckOutputFile (issue 46: simulate-axis found a folder in the way only
// after its simulation): a folder, a missing folder, a file as folder and
// a read-only folder are refused naming the path; a new or existing file
// in a writable folder is accepted.
TEST_F(CsvTest, CheckOutputFileRefusesWhatWriteFileAtomicWouldFailOn) {
  const std::string expected =
      ": expected an output file (a path in an existing folder this process may write into), got ";
  const auto error_of = [](const std::string& path) -> std::string {
    try {
      CheckOutputFile(path);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(error_of(dir_.string()), dir_.string() + expected + "a folder");
  EXPECT_EQ(error_of(PathOf("sub/")), PathOf("sub/") + expected + "a folder path (ending in '/')");
  EXPECT_EQ(error_of(PathOf("no_such_dir/x.csv")),
            PathOf("no_such_dir/x.csv") + expected + "'" + PathOf("no_such_dir") +
                "', a folder that does not exist");
  const std::string file = WriteText("file.csv", "t\n0\n");
  EXPECT_EQ(error_of(file + "/x.csv"),
            file + "/x.csv" + expected + "'" + file + "', which is not a folder");
  EXPECT_EQ(error_of(""), "''" + expected + "an empty path");
  EXPECT_EQ(error_of(file), "no error");  // replaced
  EXPECT_EQ(error_of(PathOf("new.csv")), "no error");
  if (::geteuid() != 0) {  // root writes anywhere
    const fs::path locked = dir_ / "locked";
    fs::create_directories(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_EQ(error_of((locked / "x.csv").string()),
              (locked / "x.csv").string() + expected + "'" + locked.string() +
                  "', a folder that cannot be written into");
    fs::permissions(locked, fs::perms::owner_all);
  }
}

TEST_F(CsvTest, WriteFileAtomicRemovesTemporaryWhenRenameFails) {
  // A directory cannot be replaced by a file: the rename fails after the
  // temporary was written, which must then be removed.
  fs::create_directories(dir_ / "target");
  const std::string path = PathOf("target");
  try {
    WriteFileAtomic(path, "data\n");
    ADD_FAILURE() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find("renam"), std::string::npos) << message;
  }
  EXPECT_EQ(Listing(), std::vector<std::string>{"target"});
  EXPECT_TRUE(fs::is_directory(path));
}

TEST_F(CsvTest, WriteCsvAtomicRejectsBadShapesAndWritesNothing) {
  const std::string path = PathOf("out.csv");
  ExpectInvalidArgument(
      [&] {
        WriteCsvAtomic(path, {"t", "x"}, {{0.0, 1.0}});
      },
      path + ": ", {"expected one column per name (2), got 1 columns"});
  ExpectInvalidArgument(
      [&] {
        WriteCsvAtomic(path, {"t", "x"}, {{0.0, 1.0}, {1.0}});
      },
      path + ": ",
      {"expected every column as long as column 't' (2 values), got 1 in "
       "column 'x'"});
  ExpectInvalidArgument(
      [&] {
        WriteCsvAtomic(path, {"t", "x"}, {{0.0, 1.0}, {1.0, NAN}});
      },
      path + ": ", {"expected finite values, got nan in column 'x' at row 1"});
  ExpectInvalidArgument([&] { WriteCsvAtomic(path, {"t"}, {{INFINITY}}); },
                        path + ": ", {"got inf in column 't'"});
  ExpectInvalidArgument([&] { WriteCsvAtomic(path, {"t"}, {{0.0}}, 0); },
                        path + ": ",
                        {"expected a precision in [1, 17], got 0"});
  ExpectInvalidArgument([&] { WriteCsvAtomic(path, {"t"}, {{0.0}}, 18); },
                        path + ": ", {"got 18"});
  EXPECT_TRUE(Listing().empty());
}

TEST_F(CsvTest, LargeTableRoundTrip) {
  // The size of the bundled data files: 25k rows x 6 columns.
  const size_t rows = 25000;
  const std::vector<std::string> names = {"t_s",  "u_V", "qm_m",
                                          "qr_m", "i_A", "v_mps"};
  std::vector<std::vector<double>> columns(names.size(),
                                           std::vector<double>(rows));
  for (size_t i = 0; i < rows; ++i) {
    const double t = 0.001 * static_cast<double>(i);
    columns[0][i] = t;
    for (size_t j = 1; j < names.size(); ++j) {
      columns[j][i] =
          std::sin(t * static_cast<double>(j)) * std::pow(10.0, j - 3.0);
    }
  }
  const std::string path = PathOf("large.csv");
  WriteCsvAtomic(path, names, columns, 17);
  const CsvTable table = ReadCsv(path);
  EXPECT_EQ(table.names, names);
  EXPECT_EQ(table.columns, columns);
  EXPECT_NO_THROW(CheckStrictlyIncreasing(table, "t_s"));
  // From memory (several of the parser's 64 KiB chunks): the same table.
  const CsvTable from_text = ParseCsv(ReadText(path), "large.csv");
  EXPECT_EQ(from_text.path, "large.csv");
  EXPECT_EQ(from_text.names, names);
  EXPECT_EQ(from_text.columns, columns);
}

}  // namespace
}  // namespace axis
