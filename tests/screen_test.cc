// GoOnPastScreen and RanksByBound (discovery/internal/screen.h): which competing refits
// go on past the screen under the lowest-BIC rule, against rankings worked out
// by hand.
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "discovery/internal/screen.h"

namespace axis {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(GoOnPastScreenTest, AtMostTwiceTopAllGoOn) {
  // 6 candidates, top 3: the two judges could name 6 different ones.
  const std::vector<size_t> score_rank = {1, 2, 3, 4, 5, 6};
  const std::vector<double> bound = {60, 50, 40, 30, 20, 10};
  EXPECT_EQ(GoOnPastScreen(score_rank, bound, 3), std::vector<bool>(6, true));
}

TEST(GoOnPastScreenTest, TheUnionOfTheTopByScoreAndByBound) {
  // Score ranks 1..8 in batch order; the three lowest bounds are those of
  // the candidates at indices 7 (1.0), 2 (2.0) and 5 (3.0). Top 2 by score:
  // indices 0, 1; top 2 by bound: 7, 2.
  const std::vector<size_t> score_rank = {1, 2, 3, 4, 5, 6, 7, 8};
  const std::vector<double> bound = {9.0, 8.0, 2.0, 7.0, 6.0, 3.0, 5.0, 1.0};
  const std::vector<bool> expected = {true, true, true, false, false, false, false, true};
  EXPECT_EQ(GoOnPastScreen(score_rank, bound, 2), expected);
}

TEST(GoOnPastScreenTest, ScoreRankIsTheStepsNotTheBatchOrder) {
  // A front-end family queued together puts a lower-ranked member early in
  // the batch: its place in the score ranking decides, not its index.
  const std::vector<size_t> score_rank = {1, 9, 2, 3, 4, 5, 6};
  const std::vector<double> bound = {5, 6, 7, 8, 9, 10, 1};
  // Top 1 by score: index 0; top 1 by bound: index 6 (bound 1).
  const std::vector<bool> expected = {true, false, false, false, false, false, true};
  EXPECT_EQ(GoOnPastScreen(score_rank, bound, 1), expected);
}

TEST(GoOnPastScreenTest, AFailedScreenGoesOnToItsRetry) {
  const std::vector<size_t> score_rank = {1, 2, 3, 4, 5};
  const std::vector<double> bound = {5, 4, 3, kInf, std::nan("")};
  // Top 1 by score: 0; top 1 by bound: 2; 3 and 4 have no finite bound.
  const std::vector<bool> expected = {true, false, true, true, true};
  EXPECT_EQ(GoOnPastScreen(score_rank, bound, 1), expected);
}

TEST(GoOnPastScreenTest, TiesInTheBoundGoByIndex) {
  const std::vector<size_t> score_rank = {1, 2, 3, 4, 5};
  const std::vector<double> bound = {9, 2, 2, 2, 2};
  // Top 1 by score: 0; the lowest bound is shared, the first index (1) wins.
  const std::vector<bool> expected = {true, true, false, false, false};
  EXPECT_EQ(GoOnPastScreen(score_rank, bound, 1), expected);
}

TEST(RanksByBoundTest, LowestFirstNonFiniteLastTiesByIndex) {
  const std::vector<double> bound = {3.0, std::nan(""), 1.0, 3.0, kInf, 2.0};
  const std::vector<size_t> expected = {3, 5, 1, 4, 6, 2};
  EXPECT_EQ(RanksByBound(bound), expected);
}

TEST(GoOnPastScreenTest, ThrowsOnMismatchedLengthsOrZeroTop) {
  EXPECT_THROW(GoOnPastScreen({1, 2}, {1.0}, 1), std::invalid_argument);
  EXPECT_THROW(GoOnPastScreen({1, 2}, {1.0, 2.0}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace axis
