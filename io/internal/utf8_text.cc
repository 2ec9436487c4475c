#include "io/internal/utf8_text.h"

#include <cstdio>
#include <stdexcept>

namespace axis {

size_t Utf8Checker::Feed(const char* data, size_t size) {
  if (failed_) return 0;
  for (size_t k = 0; k < size; ++k) {
    const unsigned char b = static_cast<unsigned char>(data[k]);
    bool ok = true;
    if (pending_ > 0) {
      ok = b >= low_ && b <= high_;
      if (!ok) {  // the character that starts at char_start_ is refused
        failed_ = true;
        bad_offset_ = char_start_;
        bad_line_ = char_line_;
        const size_t piece_start = offset_ - k;
        return char_start_ >= piece_start ? char_start_ - piece_start : 0;
      }
      low_ = 0x80;
      high_ = 0xBF;
      --pending_;
    } else {
      char_start_ = offset_;
      char_line_ = line_;
      lead_ = b;
      if (b == 0x00) {
        ok = false;
      } else if (b < 0x80) {
      } else if (b >= 0xC2 && b <= 0xDF) {
        pending_ = 1;
      } else if (b >= 0xE0 && b <= 0xEF) {
        pending_ = 2;
        if (b == 0xE0) low_ = 0xA0;   // no overlong form
        if (b == 0xED) high_ = 0x9F;  // no surrogate
      } else if (b >= 0xF0 && b <= 0xF4) {
        pending_ = 3;
        if (b == 0xF0) low_ = 0x90;   // no overlong form
        if (b == 0xF4) high_ = 0x8F;  // nothing above U+10FFFF
      } else {
        ok = false;
      }
    }
    if (!ok) {
      failed_ = true;
      bad_offset_ = offset_;
      bad_line_ = line_;
      return k;
    }
    if (b == '\n') {
      if (!after_cr_) ++line_;
    } else if (b == '\r') {
      ++line_;
    }
    after_cr_ = b == '\r';
    ++offset_;
  }
  return size;
}

bool Utf8Checker::Finish() {
  if (!failed_ && pending_ > 0) {
    failed_ = true;
    cut_ = true;
    bad_offset_ = char_start_;
    bad_line_ = char_line_;
  }
  return !failed_;
}

std::string Utf8Checker::Error(const std::string& name) const {
  std::string got;
  if (lead_ == 0) {
    got = "a NUL byte";
  } else {
    char hex[8];
    std::snprintf(hex, sizeof hex, "0x%02X", lead_);
    got = std::string("byte ") + hex;
  }
  // A UTF-16 file holds NUL bytes in ASCII text, or starts with FF FE / FE FF.
  const bool utf16 = lead_ == 0 || (bad_offset_ == 0 && (lead_ == 0xFF || lead_ == 0xFE));
  return name + ":" + std::to_string(bad_line_) + ": expected UTF-8 text, got " + got +
         " at byte offset " + std::to_string(bad_offset_) +
         (cut_ ? ", a character cut off by the end of the text" : "") + " (not UTF-8 text" +
         (utf16 ? "; a UTF-16 file? save it as UTF-8)" : "; save the file as UTF-8)");
}

void CheckUtf8Text(const std::string& text, const std::string& name) {
  Utf8Checker checker;
  checker.Feed(text.data(), text.size());
  if (!checker.Finish()) throw std::invalid_argument(checker.Error(name));
}

}  // namespace axis
