// The run's phases (common/phase_log.h): each phase gets the work counted
// between its beginning and the next, a phase begun again under its own
// name continues, and the line names every phase that took time or work.
#include <string>

#include <gtest/gtest.h>

#include "common/phase_log.h"

namespace axis {
namespace {

TEST(PhaseLogTest, EachPhaseGetsTheWorkDoneInIt) {
  WorkCount counter;
  PhaseLog log([&counter] { return counter; });
  log.Begin("base fit");
  counter.simulations += 5;
  counter.derivative_simulations += 40;
  log.Begin("base fit");  // continues
  counter.simulations += 1;
  log.Begin("discovery step 1");
  counter.derivative_simulations += 7;
  log.End();
  counter.simulations += 100;  // after the end: no phase's
  log.End();                   // nothing to end
  ASSERT_EQ(log.phases().size(), 2u);
  EXPECT_EQ(log.phases()[0].name, "base fit");
  EXPECT_EQ(log.phases()[0].simulations, 6);
  EXPECT_EQ(log.phases()[0].derivative_simulations, 40);
  EXPECT_EQ(log.phases()[1].name, "discovery step 1");
  EXPECT_EQ(log.phases()[1].simulations, 0);
  EXPECT_EQ(log.phases()[1].derivative_simulations, 7);
  for (const RunPhase& p : log.phases()) EXPECT_GE(p.seconds, 0.0);
  const std::string line = FormatPhaseLog(log.phases());
  EXPECT_NE(line.find("base fit"), std::string::npos) << line;
  EXPECT_NE(line.find("6 simulations, 40 with derivatives"), std::string::npos) << line;
  EXPECT_NE(line.find("discovery step 1"), std::string::npos) << line;
}

TEST(PhaseLogTest, WithoutACounterThePhasesStillTime) {
  PhaseLog log;
  log.Begin("a");
  log.Begin("b");
  log.End();
  ASSERT_EQ(log.phases().size(), 2u);
  EXPECT_EQ(log.phases()[1].simulations, 0);
  EXPECT_EQ(FormatPhaseLog({}), "0 s");
}

}  // namespace
}  // namespace axis
