// Text inputs (YAML files, CSV files) are read as UTF-8: a NUL byte, a
// UTF-16 file or bytes of another encoding are refused with the byte offset
// and line of the first such byte, before any parser sees them (a NUL cut
// the parsers' messages short, and other bytes went into them raw).
#ifndef IO_INTERNAL_UTF8_TEXT_H_
#define IO_INTERNAL_UTF8_TEXT_H_

#include <cstddef>
#include <string>

namespace axis {

// Checks a text read in pieces (Feed each piece in order, then Finish).
// Accepts well-formed UTF-8 (RFC 3629: no overlong forms, no surrogates,
// nothing above U+10FFFF) without NUL bytes; a UTF-8 byte order mark is
// well-formed UTF-8 and accepted.
class Utf8Checker {
 public:
  // Checks the next `size` bytes. Returns the number of bytes before the
  // first refused one (`size` if all are fine; then the checker goes on with
  // the next piece). After a refusal the checker stays failed and returns 0.
  size_t Feed(const char* data, size_t size);
  // At the end of the text: false if the last character is cut off (also
  // false if Feed refused a byte).
  bool Finish();
  bool failed() const { return failed_; }
  // The message for the refusal (call only when failed()):
  //   "<name>:<line>: expected UTF-8 text, got byte 0xFF at byte offset 0
  //   (not UTF-8 text; a UTF-16 file? save it as UTF-8)"
  // naming the first byte of the refused character (a NUL byte as "a NUL
  // byte"; a character cut off by the end of the text adds so), its byte
  // offset (0-based from the start of the text) and its line (1-based; LF,
  // CRLF and CR ends counted).
  std::string Error(const std::string& name) const;

 private:
  size_t offset_ = 0;        // bytes accepted so far
  size_t line_ = 1;          // line of the next byte
  bool after_cr_ = false;    // the last byte was a CR (a following LF ends no line)
  int pending_ = 0;          // continuation bytes still expected
  unsigned char low_ = 0x80, high_ = 0xBF;  // range of the next continuation byte
  size_t char_start_ = 0;    // offset, line and first byte of the character being read
  size_t char_line_ = 1;
  unsigned char lead_ = 0;
  bool failed_ = false;
  bool cut_ = false;         // the text ended inside a character
  size_t bad_offset_ = 0;    // where the refused character starts
  size_t bad_line_ = 1;
};

// Throws std::invalid_argument with Utf8Checker::Error's message if `text`
// is not UTF-8 text; `name` stands for its file.
void CheckUtf8Text(const std::string& text, const std::string& name);

}  // namespace axis

#endif  // IO_INTERNAL_UTF8_TEXT_H_
