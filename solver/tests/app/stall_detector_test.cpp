// The stall rule (app/stall_detector.hpp) on made-up histories.
#include <gtest/gtest.h>

#include <cmath>

#include "app/stall_detector.hpp"

namespace narwhal {
namespace {

TEST(StallDetector, APlateauStallsAfterTheWindow) {
  StallDetector s(10, 2.0);
  EXPECT_FALSE(s.observe(1, 1.0));
  for (int it = 2; it <= 10; ++it) EXPECT_FALSE(s.observe(it, 0.6)) << it;  // 0.6 > 1/2: no progress
  EXPECT_TRUE(s.observe(11, 0.6));
  EXPECT_EQ(s.anchor_iteration(), 1);
  EXPECT_EQ(s.anchor(), 1.0);
}

TEST(StallDetector, SteadyOrBurstyProgressNeverStalls) {
  StallDetector s(10, 2.0);
  Real m = 1.0;
  for (int it = 1; it <= 1000; ++it) {
    m *= it % 9 == 0 ? 0.1 : 1.05;  // rises for 8 iterations, then falls tenfold
    EXPECT_FALSE(s.observe(it, m)) << it;
  }
}

TEST(StallDetector, AnOscillationAroundAPlateauStalls) {
  StallDetector s(50, 2.0);
  int stalled_at = -1;
  for (int it = 1; it <= 200 && stalled_at < 0; ++it)
    if (s.observe(it, 1e-3 * (it % 2 ? 1.0 : 0.7))) stalled_at = it;
  EXPECT_EQ(stalled_at, 51);
}

TEST(StallDetector, WindowZeroNeverStalls) {
  StallDetector s(0, 2.0);
  for (int it = 1; it <= 10000; ++it) EXPECT_FALSE(s.observe(it, 1.0));
}

TEST(StallDetector, RestoredStateJudgesAsTheUninterruptedOne) {
  StallDetector a(10, 2.0), b(10, 2.0);
  const auto m = [](int it) { return it < 5 ? std::pow(0.3, it) : 0.3 * std::pow(0.3, 4); };
  for (int it = 1; it <= 7; ++it) a.observe(it, m(it));
  b.restore(a.anchor(), a.anchor_iteration());
  for (int it = 8; it <= 20; ++it) EXPECT_EQ(a.observe(it, m(it)), b.observe(it, m(it))) << it;
}

}  // namespace
}  // namespace narwhal
