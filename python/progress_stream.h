// A std::ostream whose lines go to a Python callable: how the fit's
// progress lines (run/job_run.h RunJob prints them to a std::ostream) reach
// servo_axis_id.fit(..., progress=callback) while the fit runs with the GIL
// released.
#ifndef PYTHON_PROGRESS_STREAM_H_
#define PYTHON_PROGRESS_STREAM_H_

#include <mutex>
#include <optional>
#include <ostream>
#include <streambuf>
#include <string>

#include <pybind11/pybind11.h>
#include "common/progress.h"

namespace axis::python {

// Collects characters; for each complete line (without its "\n") it
// acquires the GIL and calls `callback(line: str)` (bytes that are not
// UTF-8 become U+FFFD). Safe to write from any thread, one line at a time
// (a mutex guards the buffer; the fit library prints from the calling
// thread only). If the callback raises, the exception is kept, later lines
// are dropped, and Finish() re-raises it. A None callback drops every line.
// Construct and destroy with the GIL held.
class ProgressBuffer : public std::streambuf {
 public:
  explicit ProgressBuffer(pybind11::object callback);
  ~ProgressBuffer() override;
  ProgressBuffer(const ProgressBuffer&) = delete;
  ProgressBuffer& operator=(const ProgressBuffer&) = delete;

  // Sends the last, unterminated line if any, then re-raises the callback's
  // exception if it raised. Call with the GIL held, after the writers are
  // done.
  void Finish();

 protected:
  int_type overflow(int_type ch) override;
  std::streamsize xsputn(const char* s, std::streamsize n) override;

 private:
  void Append(const char* s, size_t n);
  void Send(const std::string& line);  // with mutex_ held

  std::mutex mutex_;
  std::string pending_;
  pybind11::object callback_;
  std::optional<pybind11::error_already_set> error_;
};

// An ostream on a ProgressBuffer.
class ProgressStream : public std::ostream {
 public:
  explicit ProgressStream(pybind11::object callback)
      : std::ostream(nullptr), buffer_(std::move(callback)) {
    rdbuf(&buffer_);
  }
  void Finish() { buffer_.Finish(); }

 private:
  ProgressBuffer buffer_;
};

}  // namespace axis::python

#endif  // PYTHON_PROGRESS_STREAM_H_
