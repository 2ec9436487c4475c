#include "common/progress.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

#include <sys/ioctl.h>

namespace axis {

// Forwards every character to the destination stream's buffer; on a
// terminal, erases the status line before the first character of other
// text (and remembers that it is gone).
class ProgressStream::Buffer : public std::streambuf {
 public:
  Buffer(std::ostream& out, bool terminal) : out_(out), terminal_(terminal) {}

  // Writes the status line (terminal only), replacing what is on it.
  void Draw(const std::string& line) {
    out_ << "\r\033[K" << line;
    out_.flush();
    visible_ = true;
  }
  // Erases the status line if it is shown.
  void Erase() {
    if (!visible_) return;
    out_ << "\r\033[K";
    visible_ = false;
  }
  // Whether the last text written ended its line (a status line may be
  // drawn below it).
  bool AtLineStart() const { return at_line_start_; }
  void Flush() { out_.flush(); }

 protected:
  int_type overflow(int_type c) override {
    if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
    const char ch = traits_type::to_char_type(c);
    return xsputn(&ch, 1) == 1 ? c : traits_type::eof();
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    if (n <= 0) return 0;
    if (terminal_) Erase();
    out_.write(s, n);
    at_line_start_ = s[n - 1] == '\n';
    return out_ ? n : 0;
  }
  int sync() override {
    out_.flush();
    return out_ ? 0 : -1;
  }

 private:
  std::ostream& out_;
  bool terminal_;
  bool visible_ = false;
  bool at_line_start_ = true;
};

int TerminalColumns(int fd) {
  if (::isatty(fd) == 0) return 0;
  struct winsize size {};
  if (::ioctl(fd, TIOCGWINSZ, &size) == 0 && size.ws_col > 0) return size.ws_col;
  return 80;
}

std::string FormatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) seconds = 0.0;
  const long s = std::lround(seconds);
  char buf[48];
  if (s < 60) {
    std::snprintf(buf, sizeof(buf), "%ld s", s);
  } else if (s < 3600) {
    std::snprintf(buf, sizeof(buf), "%ld min %02ld s", s / 60, s % 60);
  } else {
    std::snprintf(buf, sizeof(buf), "%ld h %02ld min", s / 3600, (s % 3600) / 60);
  }
  return buf;
}

ProgressStream::ProgressStream(std::ostream& out, int columns)
    : std::ostream(nullptr),
      buffer_(std::make_unique<Buffer>(out, columns > 0)),
      columns_(columns > 0 ? columns : 0),
      start_(std::chrono::steady_clock::now()),
      phase_start_(start_),
      last_draw_(start_) {
  rdbuf(buffer_.get());
}

ProgressStream::~ProgressStream() {
  if (terminal()) buffer_->Erase();
  buffer_->Flush();
}

bool ProgressStream::terminal() const { return columns_ > 0; }

double ProgressStream::Elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressStream::BeginPhase(const std::string& name) {
  phase_ = name;
  phase_start_ = std::chrono::steady_clock::now();
  phase_total_ = 0.0;
}

double ProgressStream::InPhase() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - phase_start_).count();
}

std::string ProgressStream::Line() const {
  std::string line = FormatDuration(Elapsed()) + " elapsed; " + status_;
  // Counts down between status reports; dropped once overdue.
  const double left = phase_total_ - InPhase();
  if (phase_total_ > 0.0 && left > 0.0) {
    line += "; " + (phase_.empty() ? std::string("phase") : phase_) + " ~" +
            FormatDuration(left) + " left";
  }
  return line;
}

void ProgressStream::Redraw(bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_draw_ < std::chrono::milliseconds(200)) return;
  last_draw_ = now;
  flush();
  if (!buffer_->AtLineStart()) return;  // text is mid-line: draw after it
  std::string line = Line();
  if (!detail_.empty()) line += " | " + detail_;
  // Cut to the width in code points (UTF-8 continuation bytes take none).
  const size_t width = static_cast<size_t>(columns_ > 1 ? columns_ - 1 : 1);
  size_t points = 0, cut = line.size();
  for (size_t k = 0; k < line.size(); ++k) {
    if ((static_cast<unsigned char>(line[k]) & 0xC0) == 0x80) continue;
    if (points == width) {
      cut = k;
      break;
    }
    ++points;
  }
  buffer_->Draw(line.substr(0, cut));
}

void ProgressStream::Status(const std::string& what, double done) {
  status_ = what;
  detail_.clear();
  // The phase's whole time extrapolated from the share done so far.
  const double in_phase = InPhase();
  phase_total_ = std::isfinite(done) && done > 0.0 && done < 1.0 && in_phase >= 1.0
                     ? in_phase / done
                     : 0.0;
  if (terminal()) {
    Redraw(true);
  } else {
    *this << "progress: " << Line() << "\n";
    flush();
  }
}

void ProgressStream::Detail(const std::string& detail) {
  if (!terminal()) return;
  detail_ = detail;
  Redraw(false);
}

ProgressStream* AsProgressStream(std::ostream* out) {
  return dynamic_cast<ProgressStream*>(out);
}

}  // namespace axis
