#include "common/concurrency.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>

namespace axis {

void ForEachConcurrently(size_t n, int threads, const std::function<void(size_t)>& body) {
  std::vector<std::exception_ptr> errors(n);
  std::atomic<size_t> next{0};
  const auto worker = [&]() {
    for (size_t k = next++; k < n; k = next++) {
      try {
        body(k);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    }
  };
  const size_t at_once =
      std::min(static_cast<size_t>(std::max(1, threads)), std::max<size_t>(1, n));
  std::vector<std::thread> pool;
  try {
    for (size_t t = 1; t < at_once; ++t) pool.emplace_back(worker);
  } catch (const std::system_error&) {
    // No more threads to be had: the ones started and this one do the work.
  }
  worker();
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors) {
    if (e) std::rethrow_exception(e);
  }
}

int ProcessThreads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

}  // namespace axis
