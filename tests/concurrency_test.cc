// ForEachConcurrently (common/concurrency.h): every item once, on the threads
// asked for, and the lowest item's exception after all items have run.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "common/concurrency.h"

namespace axis {
namespace {

TEST(ConcurrencyTest, EveryItemRunsOnceOnAtMostTheThreadsAskedFor) {
  for (const int threads : {1, 2, 3}) {
    SCOPED_TRACE(threads);
    const size_t n = 40;
    std::vector<std::atomic<int>> runs(n);
    std::mutex mutex;
    std::set<std::thread::id> ids;
    std::atomic<int> running{0};
    int most = 0;
    ForEachConcurrently(n, threads, [&](size_t k) {
      const int now = ++running;
      {
        std::lock_guard<std::mutex> lock(mutex);
        ids.insert(std::this_thread::get_id());
        most = std::max(most, now);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      ++runs[k];
      --running;
    });
    for (size_t k = 0; k < n; ++k) EXPECT_EQ(runs[k], 1) << k;
    EXPECT_LE(static_cast<int>(ids.size()), threads);
    EXPECT_LE(most, threads);
    // The calling thread is one of them.
    EXPECT_EQ(ids.count(std::this_thread::get_id()), 1u);
  }
}

TEST(ConcurrencyTest, NoItemsAndThreadsBelowOne) {
  int calls = 0;
  ForEachConcurrently(0, 4, [&](size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
  ForEachConcurrently(3, 0, [&](size_t) { ++calls; });  // one thread: no race on calls
  EXPECT_EQ(calls, 3);
}

TEST(ConcurrencyTest, TheLowestItemsExceptionIsRethrownAfterEveryItemRan) {
  const size_t n = 20;
  std::vector<std::atomic<int>> runs(n);
  try {
    ForEachConcurrently(n, 2, [&](size_t k) {
      ++runs[k];
      if (k == 7 || k == 13) throw std::runtime_error("item " + std::to_string(k));
    });
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "item 7");
  }
  for (size_t k = 0; k < n; ++k) EXPECT_EQ(runs[k], 1) << k;
}

// Two items that each wait for the other (up to 10 s) finish only if they
// run at the same time.
TEST(ConcurrencyTest, TwoThreadsRunTwoItemsAtOnce) {
  std::atomic<int> arrived{0};
  std::atomic<int> met{0};
  ForEachConcurrently(2, 2, [&](size_t) {
    ++arrived;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (arrived < 2 && std::chrono::steady_clock::now() < until) std::this_thread::yield();
    if (arrived == 2) ++met;
  });
  EXPECT_EQ(met, 2);
}

TEST(ConcurrencyTest, ProcessThreadsAreTheHardwareThreads) {
  const unsigned hardware = std::thread::hardware_concurrency();
  EXPECT_EQ(ProcessThreads(), hardware == 0 ? 1 : static_cast<int>(hardware));
}

}  // namespace
}  // namespace axis
