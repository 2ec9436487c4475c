#include "python/progress_stream.h"

#include <Python.h>

#include <utility>

namespace py = pybind11;

namespace axis::python {

ProgressBuffer::ProgressBuffer(py::object callback) : callback_(std::move(callback)) {}

ProgressBuffer::~ProgressBuffer() = default;

ProgressBuffer::int_type ProgressBuffer::overflow(int_type ch) {
  if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
  const char c = traits_type::to_char_type(ch);
  Append(&c, 1);
  return ch;
}

std::streamsize ProgressBuffer::xsputn(const char* s, std::streamsize n) {
  Append(s, static_cast<size_t>(n));
  return n;
}

void ProgressBuffer::Append(const char* s, size_t n) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (size_t k = 0; k < n; ++k) {
    if (s[k] != '\n') {
      pending_ += s[k];
      continue;
    }
    Send(pending_);
    pending_.clear();
  }
}

void ProgressBuffer::Send(const std::string& line) {
  if (callback_.is_none() || error_) return;  // no GIL needed to read these
  py::gil_scoped_acquire gil;
  try {
    const py::object text = py::reinterpret_steal<py::object>(PyUnicode_DecodeUTF8(
        line.data(), static_cast<Py_ssize_t>(line.size()), "replace"));
    if (!text) throw py::error_already_set();
    callback_(text);
  } catch (py::error_already_set& e) {
    error_ = std::move(e);
  }
}

void ProgressBuffer::Finish() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!pending_.empty()) {
    Send(pending_);
    pending_.clear();
  }
  if (error_) {
    py::error_already_set e = std::move(*error_);
    error_.reset();
    throw e;
  }
}

}  // namespace axis::python
