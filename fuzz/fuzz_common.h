// Shared by the libFuzzer targets of fuzz/ (issue 17): what a loader may do
// with arbitrary input is return or throw std::invalid_argument (bad input,
// with a message) — anything else (another exception, a crash, a sanitizer
// report, a leak) is a finding.
#ifndef FUZZ_FUZZ_COMMON_H_
#define FUZZ_FUZZ_COMMON_H_

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>
#include <typeinfo>

namespace axis::fuzz {

// Runs `parse(text)`; returns normally on success or std::invalid_argument,
// aborts (a libFuzzer finding) on any other exception or an empty message.
// std::bad_alloc is let through as libFuzzer's -rss_limit_mb reports it.
template <typename Parse>
void Expect(const uint8_t* data, size_t size, Parse parse) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    parse(text);
  } catch (const std::invalid_argument& e) {
    if (std::string(e.what()).empty()) std::abort();
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "unexpected exception %s: %s\n", typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "unexpected exception of a non-standard type\n");
    std::abort();
  }
}

}  // namespace axis::fuzz

#endif  // FUZZ_FUZZ_COMMON_H_
