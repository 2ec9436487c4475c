// JSON logs as data tables (io/json_log.h): the entries' keys as columns,
// the log's own numbers as constants, every malformed input refused with
// its place; a real BAM log read whole (testdata/bam_xl330/README.md).
#include "io/json_log.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "io/data_file.h"
#include "run/load_fit_job.h"
#include "test_files.h"

namespace axis {
namespace {

const std::string kRoot = PROJECT_SOURCE_DIR;

std::string ErrorOf(const std::string& text) {
  try {
    ParseJsonLog(text, "log.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(JsonLogTest, EntriesAreColumnsAndTheLogsNumbersAreConstants) {
  const DataTable t = ParseJsonLog(
      R"({"kp": 800, "motor": "xl330", "entries": [
           {"timestamp": 0.0, "position": -0.5, "torque_enable": true},
           {"position": 0.25, "timestamp": 0.005, "torque_enable": false}]})",
      "log.json");
  EXPECT_EQ(t.format, DataTable::Format::kJson);
  ASSERT_EQ(t.names, (std::vector<std::string>{"timestamp", "position", "torque_enable"}));
  EXPECT_EQ(t.num_rows(), 2u);
  EXPECT_EQ(t.Column("position"), (std::vector<double>{-0.5, 0.25}));  // by key, any order
  EXPECT_EQ(t.Column("torque_enable"), (std::vector<double>{1.0, 0.0}));
  ASSERT_EQ(t.constants.size(), 1u);
  EXPECT_EQ(t.constants[0].first, "kp");
  EXPECT_EQ(t.constants[0].second, 800.0);
  EXPECT_EQ(t.RowLocation(1), "log.json: entries[1]");
  // A top-level key named as a column says what it is.
  try {
    t.Column("kp");
    FAIL() << "kp is not a column";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("key 'kp': expected a key of every object of "
                                         "entries[] (numbers or true/false), got a number "
                                         "(800) of the log itself"),
              std::string::npos)
        << e.what();
  }
}

TEST(JsonLogTest, MalformedLogsNameThePlaceAndWhatWasExpected) {
  EXPECT_NE(ErrorOf("{\"entries\": [").find("log.json: expected JSON text, got a parse error"),
            std::string::npos);
  EXPECT_NE(ErrorOf("[1, 2]").find("log.json: expected a JSON object with an array 'entries', "
                                   "got an array of 2 element(s)"),
            std::string::npos);
  EXPECT_NE(ErrorOf("{\"kp\": 1}").find("expected an array 'entries' (one object per sample), "
                                        "got no such key"),
            std::string::npos);
  EXPECT_NE(ErrorOf("{\"entries\": []}").find("expected at least one object in 'entries', got none"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"entries": [{"t": 0, "x": 1}, {"t": 1}]})")
                .find("log.json: entries[1]: expected key 'x' (every entry has the keys of "
                      "entries[0]), got none"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"entries": [{"t": 0}, {"t": 1, "y": 2}]})")
                .find("log.json: entries[1]: expected only the keys of entries[0] (t), got key 'y'"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"entries": [{"t": 0}, {"t": "late"}]})")
                .find("log.json: entries[1]: key 't': expected a finite number or true/false, "
                      "got a string (\"late\")"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"entries": [{"t": 0}, {"t": null}]})").find("got null"), std::string::npos);
  EXPECT_NE(ErrorOf(R"({"entries": [{"t": 0}, 3]})")
                .find("log.json: entries[1]: expected an object of 1 keys, got a number (3)"),
            std::string::npos);
  EXPECT_NE(ErrorOf(R"({"entries": [{"t": 1e999}]})").find("log.json: expected JSON text, got"),
            std::string::npos)
      << ErrorOf(R"({"entries": [{"t": 1e999}]})");
}

// The processed BAM log: 1201 entries at BAM's dt = 0.005 s, its timestamps
// on that grid (to the float printing of the file), the drive on
// throughout this trajectory, and the log's constants as written.
TEST(JsonLogTest, ProcessedBamLogIsAUniformRecord) {
  const std::string path = kRoot + "/testdata/bam_xl330/processed/2026-01-15_10h28m10.json";
  const DataTable t = ReadDataTable(path, "timestamp");  // by its extension
  EXPECT_EQ(t.format, DataTable::Format::kJson);
  ASSERT_EQ(t.num_rows(), 1201u);
  const std::vector<double>& time = t.Column("timestamp");
  for (size_t k = 1; k < time.size(); ++k) EXPECT_NEAR(time[k] - time[k - 1], 0.005, 1e-9) << k;
  for (const char* key : {"position", "speed", "goal_position", "torque_enable"}) {
    EXPECT_TRUE(t.HasColumn(key)) << key;
  }
  std::vector<std::string> names;
  for (const auto& [name, value] : t.constants) names.push_back(name);
  EXPECT_EQ(names, (std::vector<std::string>{"mass", "length", "kp", "vin", "dt"}));
  EXPECT_EQ(t.constants[2].second, 100.0);
  EXPECT_EQ(t.constants[4].second, 0.005);
}

// The raw BAM log (about 190 Hz, irregular timestamps) is refused by a
// job's loader before any work, at the first entry off the median step:
// the log is read, its sampling is not what a record must be.
TEST(JsonLogTest, RawBamLogIsRefusedAtItsFirstIrregularEntry) {
  const std::string job = testing_files::WriteTemp(
      "raw_log_job.yaml",
      "model: " + kRoot + "/configs/axes/x_axis.yaml\n"
      "free:\n  B_a: {initial: 200, lower: 10, upper: 2000}\n"
      "experiments:\n  - name: raw\n"
      "    data: " + kRoot + "/testdata/bam_xl330/raw/2026-01-15_10h28m10.json\n"
      "    time: timestamp\n"
      "    channels: {u: goal_position, x: position}\n"
      "    input: {column: goal_position}\n"
      "    fit: {x: 0.001}\n");
  try {
    LoadFitJob(job);
    FAIL() << "a log with irregular timestamps was accepted";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("raw/2026-01-15_10h28m10.json: entries["), std::string::npos) << what;
    EXPECT_NE(what.find("expected uniform sampling"), std::string::npos) << what;
  }
}

TEST(JsonLogTest, UnreadableFileIsNamed) {
  try {
    ReadJsonLog("/nonexistent/log.json");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent/log.json: expected a readable JSON log, got none");
  }
}

}  // namespace
}  // namespace axis
