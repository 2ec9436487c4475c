#include "io/csv.h"

#include <csv.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "io/internal/utf8_text.h"

namespace axis {
namespace {

// Bytes handed to libcsv per csv_parse call.
constexpr size_t kChunkSize = size_t{1} << 16;
// Longest cell text quoted in an error message.
constexpr size_t kMaxQuotedCell = 40;

std::string ErrnoText(int err) { return std::generic_category().message(err); }

bool IsSpace(char c) {
  return std::isspace(static_cast<unsigned char>(c)) != 0;
}

// `text` in single quotes, shortened to kMaxQuotedCell characters.
std::string QuoteCell(const char* text, size_t len) {
  if (len <= kMaxQuotedCell) return "'" + std::string(text, len) + "'";
  return "'" + std::string(text, kMaxQuotedCell) + "...' (" +
         std::to_string(len) + " characters)";
}

// The shortest "%.*g" text that reads back as `value`.
std::string ShortestText(double value) {
  char buf[40];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, value);
    if (std::strtod(buf, nullptr) == value) break;
  }
  return buf;
}

// State of one ReadCsv call, fed by the libcsv callbacks below.
//
// Line numbers: libcsv reports a row at each unquoted CR or LF; with
// CSV_REPALL_NL also an empty row for a bare CR or LF (a blank line, or the LF
// of a CRLF pair, which is not a new line). So the line of a row is the count
// of rows reported before it, minus those CRLF tails, plus one. This assumes
// no line break inside a quoted field; Field() rejects any, so the line of
// data row i is always i + 2.
class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path) { table_.path = path; }

  bool failed() const { return failed_; }
  size_t line() const { return line_; }

  // Stops the reading with "<path>:<line>: <message>"; the first call wins.
  void Fail(size_t line, const std::string& message) {
    if (failed_) return;
    failed_ = true;
    error_ = path_ + ":" + std::to_string(line) + ": " + message;
  }

  // A C++ exception from a callback, stored to be rethrown outside libcsv
  // (it must not unwind through C frames).
  void Store(std::exception_ptr exception) {
    failed_ = true;
    exception_ = std::move(exception);
  }

  // Throws what stopped the reading, if anything.
  void ThrowIfFailed() const {
    if (exception_) std::rethrow_exception(exception_);
    if (failed_) throw std::invalid_argument(error_);
  }

  void Field(const char* text, size_t len) {
    if (failed_) return;
    if (text == nullptr) text = "";  // libcsv passes a buffer; be safe
    if (std::memchr(text, '\n', len) != nullptr ||
        std::memchr(text, '\r', len) != nullptr) {
      Fail(line_,
           "expected each row on one line, got a line break inside a quoted "
           "field");
      return;
    }
    if (!have_header_) {
      header_.emplace_back(text, len);
    } else if (num_fields_ < table_.columns.size() && cell_error_.empty()) {
      ParseCell(text, len, num_fields_);
    }
    ++num_fields_;
  }

  // `terminator` is the CR or LF that ended the row, or -1 at end of file.
  void Row(int terminator) {
    if (failed_) return;
    const size_t num_fields = num_fields_;
    num_fields_ = 0;
    const bool crlf_tail =
        num_fields == 0 && terminator == '\n' && last_terminator_ == '\r';
    last_terminator_ = terminator;
    if (crlf_tail) return;
    const size_t line = line_++;
    if (num_fields == 0) {  // blank (or only spaces): fine if nothing follows
      if (first_blank_line_ == 0) first_blank_line_ = line;
      return;
    }
    if (first_blank_line_ != 0) {
      Fail(first_blank_line_,
           have_header_
               ? "expected " + std::to_string(table_.names.size()) +
                     " fields as in the header, got a blank line (blank "
                     "lines are allowed only at the end of the file)"
               : std::string("expected the header row, got a blank line"));
      return;
    }
    if (!have_header_) {
      FinishHeader(line);
    } else {
      FinishDataRow(line, num_fields);
    }
  }

  // After the whole file was parsed: the table, or throws.
  CsvTable Finish() {
    ThrowIfFailed();
    if (!have_header_) {
      throw std::invalid_argument(path_ +
                                  ": expected a header row, got an empty file");
    }
    if (table_.num_rows() == 0) {
      throw std::invalid_argument(
          path_ +
          ": expected at least one data row after the header, got none");
    }
    return std::move(table_);
  }

 private:
  void FinishHeader(size_t line) {
    std::unordered_map<std::string, size_t> seen;
    for (size_t j = 0; j < header_.size(); ++j) {
      const std::string& name = header_[j];
      bool blank = true;
      for (char c : name) blank = blank && IsSpace(c);
      if (blank) {
        Fail(line, "expected a name for column " + std::to_string(j + 1) +
                       " in the header, got an empty one");
        return;
      }
      const auto [it, inserted] = seen.emplace(name, j);
      if (!inserted) {
        Fail(line, "expected unique column names, got '" + name +
                       "' twice (columns " + std::to_string(it->second + 1) +
                       " and " + std::to_string(j + 1) + ")");
        return;
      }
    }
    table_.names = std::move(header_);
    table_.columns.resize(table_.names.size());
    row_.resize(table_.names.size());
    have_header_ = true;
  }

  void FinishDataRow(size_t line, size_t num_fields) {
    const size_t expected = table_.columns.size();
    if (num_fields != expected) {
      Fail(line, "expected " + std::to_string(expected) +
                     " fields as in the header, got " +
                     std::to_string(num_fields));
    } else if (!cell_error_.empty()) {
      Fail(line, cell_error_);
    } else {
      for (size_t j = 0; j < expected; ++j) {
        table_.columns[j].push_back(row_[j]);
      }
    }
    cell_error_.clear();
  }

  // Parses field `j` of the current data row into row_[j], or sets
  // cell_error_ (reported at the end of the row, after the field count).
  void ParseCell(const char* text, size_t len, size_t j) {
    const char* begin = text;
    const char* end = text + len;
    while (begin < end && IsSpace(*begin)) ++begin;
    while (end > begin && IsSpace(end[-1])) --end;
    if (begin == end) {
      cell_error_ = "expected a number in column '" + table_.names[j] +
                    "', got an empty cell";
      return;
    }
    // The field is NUL-terminated (CSV_APPEND_NULL), so strtod stops at the
    // end of the field at the latest.
    char* stop = nullptr;
    const double value = std::strtod(begin, &stop);
    if (stop != end) {
      cell_error_ = "expected a number in column '" + table_.names[j] +
                    "', got " + QuoteCell(text, len);
    } else if (std::isnan(value)) {
      cell_error_ = "expected a finite number in column '" + table_.names[j] +
                    "', got " + QuoteCell(text, len) + " (NaN)";
    } else if (std::isinf(value)) {
      cell_error_ = "expected a finite number in column '" + table_.names[j] +
                    "', got " + QuoteCell(text, len) + " (infinite)";
    } else {
      row_[j] = value;
    }
  }

  const std::string& path_;
  CsvTable table_;
  std::vector<std::string> header_;  // names collected from line 1
  std::vector<double> row_;          // values of the current data row
  std::string cell_error_;           // first bad cell of the current row
  bool have_header_ = false;
  size_t num_fields_ = 0;  // fields so far in the current row
  size_t line_ = 1;        // line of the row being parsed
  int last_terminator_ = 0;
  size_t first_blank_line_ = 0;  // 0: no blank line pending
  bool failed_ = false;
  std::string error_;
  std::exception_ptr exception_;
};

void OnField(void* text, size_t len, void* data) {
  Reader* reader = static_cast<Reader*>(data);
  try {
    reader->Field(static_cast<const char*>(text), len);
  } catch (...) {
    reader->Store(std::current_exception());
  }
}

void OnRow(int terminator, void* data) {
  Reader* reader = static_cast<Reader*>(data);
  try {
    reader->Row(terminator);
  } catch (...) {
    reader->Store(std::current_exception());
  }
}

// Frees a libcsv parser on scope exit.
struct ParserDeleter {
  void operator()(csv_parser* parser) const { csv_free(parser); }
};

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

// Whether `name` must be quoted in a CSV header to read back unchanged.
bool NeedsQuotes(const std::string& name) {
  if (name.empty()) return true;
  if (IsSpace(name.front()) || IsSpace(name.back())) return true;
  return name.find_first_of(",\"\r\n") != std::string::npos;
}

void AppendName(const std::string& name, std::string* out) {
  if (!NeedsQuotes(name)) {
    out->append(name);
    return;
  }
  out->push_back('"');
  for (char c : name) {
    if (c == '"') out->push_back('"');
    out->push_back(c);
  }
  out->push_back('"');
}

// Parses the CSV delivered by `read_chunk(buffer, capacity)` (the bytes
// read, 0 at the end; throws on a read error) as ReadCsv describes; `path`
// names it in messages.
template <typename ReadChunk>
CsvTable ParseChunks(const std::string& path, ReadChunk read_chunk) {
  csv_parser parser_storage;
  if (csv_init(&parser_storage, CSV_STRICT | CSV_STRICT_FINI | CSV_APPEND_NULL |
                                    CSV_REPALL_NL) != 0) {
    throw std::bad_alloc();
  }
  std::unique_ptr<csv_parser, ParserDeleter> parser(&parser_storage);

  Reader reader(path);
  Utf8Checker utf8;  // the bytes before a refused one are parsed: an earlier error comes first
  std::vector<char> buffer(kChunkSize);
  bool first_chunk = true;
  while (!reader.failed() && !utf8.failed()) {
    size_t size = read_chunk(buffer.data(), buffer.size());
    if (size == 0) break;
    size = utf8.Feed(buffer.data(), size);
    size_t begin = 0;
    if (first_chunk && size >= 3 &&
        std::memcmp(buffer.data(), "\xEF\xBB\xBF", 3) == 0) {
      begin = 3;  // UTF-8 byte order mark
    }
    first_chunk = false;
    const size_t parsed = csv_parse(parser.get(), buffer.data() + begin,
                                    size - begin, OnField, OnRow, &reader);
    reader.ThrowIfFailed();
    if (parsed != size - begin) {
      const int status = csv_error(parser.get());
      if (status == CSV_ENOMEM) throw std::bad_alloc();
      if (status == CSV_EPARSE) {
        reader.Fail(reader.line(),
                    "expected quotes only around whole fields (inner quotes "
                    "doubled), got a stray quote");
      } else {
        reader.Fail(reader.line(), std::string("expected valid CSV, got: ") +
                                       csv_strerror(status));
      }
    }
  }
  if (!reader.failed() && !utf8.Finish()) {
    reader.ThrowIfFailed();
    throw std::invalid_argument(utf8.Error(path));
  }
  if (!reader.failed() &&
      csv_fini(parser.get(), OnField, OnRow, &reader) != 0) {
    reader.Fail(reader.line(),
                "expected a closing quote, got the end of the file");
  }
  return reader.Finish();
}

}  // namespace

CsvTable ReadCsv(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) {
    throw std::invalid_argument(
        path + ": cannot open for reading: " + ErrnoText(errno));
  }
  return ParseChunks(path, [&](char* buffer, size_t capacity) {
    const size_t size = std::fread(buffer, 1, capacity, file.get());
    if (size == 0 && std::ferror(file.get())) {
      throw std::invalid_argument(path + ": cannot read: " + ErrnoText(errno));
    }
    return size;
  });
}

CsvTable ParseCsv(const std::string& text, const std::string& name) {
  size_t offset = 0;
  return ParseChunks(name, [&](char* buffer, size_t capacity) {
    const size_t size = std::min(capacity, text.size() - offset);
    std::memcpy(buffer, text.data() + offset, size);
    offset += size;
    return size;
  });
}

void CheckStrictlyIncreasing(const CsvTable& table, const std::string& column) {
  const std::vector<double>& values =
      table.columns.at(table.ColumnIndex(column));
  for (size_t i = 1; i < values.size(); ++i) {
    if (!(values[i] > values[i - 1])) {
      throw std::invalid_argument(
          table.RowLocation(i) + ": expected " + table.ColumnWord() + " '" +
          column + "' strictly increasing, got " + ShortestText(values[i]) +
          " after " + ShortestText(values[i - 1]));
    }
  }
}

std::string CsvField(const std::string& text) {
  std::string out;
  AppendName(text, &out);
  return out;
}

void WriteCsvAtomic(const std::string& path,
                    const std::vector<std::string>& names,
                    const std::vector<std::vector<double>>& columns,
                    int precision) {
  if (precision < 1 || precision > 17) {
    throw std::invalid_argument(path +
                                ": expected a precision in [1, 17], got " +
                                std::to_string(precision));
  }
  if (columns.size() != names.size()) {
    throw std::invalid_argument(path + ": expected one column per name (" +
                                std::to_string(names.size()) + "), got " +
                                std::to_string(columns.size()) + " columns");
  }
  const size_t rows = columns.empty() ? 0 : columns.front().size();
  for (size_t j = 0; j < columns.size(); ++j) {
    if (columns[j].size() != rows) {
      throw std::invalid_argument(
          path + ": expected every column as long as column '" + names[0] +
          "' (" + std::to_string(rows) + " values), got " +
          std::to_string(columns[j].size()) + " in column '" + names[j] + "'");
    }
    for (size_t i = 0; i < rows; ++i) {
      if (!std::isfinite(columns[j][i])) {
        throw std::invalid_argument(path + ": expected finite values, got " +
                                    ShortestText(columns[j][i]) +
                                    " in column '" + names[j] + "' at row " +
                                    std::to_string(i) + " (would be line " +
                                    std::to_string(i + 2) + ")");
      }
    }
  }

  std::string out;
  out.reserve(64 +
              rows * columns.size() * (static_cast<size_t>(precision) + 8));
  for (size_t j = 0; j < names.size(); ++j) {
    if (j > 0) out.push_back(',');
    AppendName(names[j], &out);
  }
  out.push_back('\n');
  char buf[48];
  for (size_t i = 0; i < rows; ++i) {
    for (size_t j = 0; j < columns.size(); ++j) {
      if (j > 0) out.push_back(',');
      const int n =
          std::snprintf(buf, sizeof(buf), "%.*g", precision, columns[j][i]);
      out.append(buf, static_cast<size_t>(n));
    }
    out.push_back('\n');
  }
  WriteFileAtomic(path, out);
}

}  // namespace axis
