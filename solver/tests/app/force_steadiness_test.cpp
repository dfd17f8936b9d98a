#include "app/force_steadiness.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.hpp"

namespace narwhal {
namespace {

std::map<std::string, ForceCoefficients> drag(Real cfx, Real cfy = 0.0) {
  ForceCoefficients fc;
  fc.force = Vec3(cfx, cfy, 0.0);
  return {{"plate", fc}};
}

TEST(ForceSteadiness, OffIsAlwaysSteady) {
  const ForceSteadiness f(5, 0.0);
  EXPECT_FALSE(f.enabled());
  EXPECT_TRUE(f.steady());
}

TEST(ForceSteadiness, NotSteadyBeforeTheWindowHasFilled) {
  ForceSteadiness f(3, 1e-6);
  f.observe(drag(0.003));
  f.observe(drag(0.003));
  EXPECT_FALSE(f.steady());
  EXPECT_TRUE(std::isinf(f.span()));
  f.observe(drag(0.003));
  EXPECT_TRUE(f.steady());
  EXPECT_EQ(f.span(), 0.0);
}

TEST(ForceSteadiness, SpanIsTheLargestMoveOverTheWindowRelativeToTheLargestForce) {
  ForceSteadiness f(3, 1e-6);
  f.observe(drag(1.0, 0.0));     // leaves the window below
  f.observe(drag(0.003, 1e-9));  // the side force moves by 1e-9, the drag by 2e-9
  f.observe(drag(0.003000002, 0.0));
  f.observe(drag(0.003000001, 0.0));
  EXPECT_NEAR(f.span(), 2e-9 / 0.003000001, 1e-15);
  EXPECT_TRUE(f.steady());
  f.observe(drag(0.0030001, 0.0));  // a move of 1e-7 against 3e-3: 3.3e-5
  EXPECT_FALSE(f.steady());
}

TEST(ForceSteadiness, RestoredWindowJudgesAsTheOriginal) {
  ForceSteadiness a(4, 1e-5);
  for (Real cf : {0.0031, 0.00300001, 0.003, 0.003000005}) a.observe(drag(cf, -1e-4));
  ForceSteadiness b(4, 1e-5);
  b.restore(a.state(), 3);
  EXPECT_EQ(b.span(), a.span());
  EXPECT_EQ(b.steady(), a.steady());
  a.observe(drag(0.003, -1e-4));
  b.observe(drag(0.003, -1e-4));
  EXPECT_EQ(b.span(), a.span());
  EXPECT_TRUE(b.steady());
  EXPECT_THROW(b.restore({1.0, 2.0}, 3), Error);
}

}  // namespace
}  // namespace narwhal
