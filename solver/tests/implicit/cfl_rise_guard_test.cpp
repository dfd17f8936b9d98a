// The CFL ceiling a sustained residual rise lowers (implicit/cfl_rise_guard.hpp), on
// made-up residual histories.
#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>

#include "implicit/cfl_rise_guard.hpp"

namespace narwhal {
namespace {

// Feeds `norms` to an armed `g` at CFL `cfl`: none but the last may cut; whether it did.
bool last_cuts(CflRiseGuard& g, std::initializer_list<Real> norms, Real cfl, Real floor = 1.0) {
  g.arm();
  bool cut = false;
  for (Real norm : norms) {
    EXPECT_FALSE(cut) << "cut before the last norm";
    cut = g.observe(norm, cfl, floor);
  }
  return cut;
}

TEST(CflRiseGuard, UnarmedItCutsNothing) {
  CflRiseGuard g;  // the CFL has not reached its cap: SER answers rises itself
  for (Real norm : {1.0, 4.0, 16.0, 64.0}) EXPECT_FALSE(g.observe(norm, 10.0, 1.0));
  EXPECT_TRUE(std::isinf(g.ceiling()));
}

TEST(CflRiseGuard, AFallingOrBumpyHistoryKeepsNoCeiling) {
  CflRiseGuard g;
  g.arm();
  Real norm = 1.0;
  for (int it = 1; it <= 300; ++it) {
    norm *= it % 3 == 0 ? 1.4 : 0.8;  // one rise at a time, 40 % each
    EXPECT_FALSE(g.observe(norm, 1e3, 1.0)) << it;
  }
  EXPECT_TRUE(std::isinf(g.ceiling()));
}

TEST(CflRiseGuard, TwoRisesBelowTheLimitCutNothing) {
  CflRiseGuard g;
  g.arm();
  for (Real norm : {1.0, 1.2, 1.44, 1.0, 1.2, 1.44}) EXPECT_FALSE(g.observe(norm, 1e3, 1.0));  // 1.44 < 1.5
  EXPECT_EQ(g.cuts(), 0);
}

TEST(CflRiseGuard, ASustainedRiseCutsTheCeilingByTheRise) {
  CflRiseGuard g;
  EXPECT_TRUE(last_cuts(g, {38.0, 77.0, 259.0}, 1e3));  // 6.8-fold in two iterations
  EXPECT_NEAR(g.ceiling(), 1e3 * 38.0 / 259.0, 1e-9);
  // The next cut waits for two new rises, measured from after the cut.
  EXPECT_TRUE(last_cuts(g, {400.0, 500.0, 800.0}, 146.7));  // 2-fold: cut by half at least
  EXPECT_NEAR(g.ceiling(), 146.7 * 0.5, 1e-9);
  EXPECT_EQ(g.cuts(), 2);
}

TEST(CflRiseGuard, AMildSustainedRiseCutsByHalfAndNeverBelowTheFloor) {
  CflRiseGuard g;
  EXPECT_TRUE(last_cuts(g, {1.0, 1.3, 1.6}, 10.0, 8.0));
  EXPECT_EQ(g.ceiling(), 8.0);  // half of 10 is below the floor
}

TEST(CflRiseGuard, TheCeilingNeverRises) {
  CflRiseGuard g;
  g.restore({50.0, {1.0, 2.0}, true});
  EXPECT_TRUE(g.observe(4.0, 1e3, 1.0));  // 1e3 * 0.25 = 250: above the old ceiling, which stays
  EXPECT_EQ(g.ceiling(), 50.0);
}

// A retreat from a divergence (app/retreat.hpp) may put the ceiling below the floor of the
// guard's own cuts; a later rise must not lift it back there.
TEST(CflRiseGuard, AnImposedCeilingBelowTheFloorIsKeptAndArms) {
  CflRiseGuard g;
  g.lower_ceiling(5.0);
  EXPECT_EQ(g.ceiling(), 5.0);
  EXPECT_TRUE(g.state().armed);
  EXPECT_TRUE(last_cuts(g, {1.0, 1.3, 1.6}, 5.0, 8.0));
  EXPECT_EQ(g.ceiling(), 5.0);
  g.lower_ceiling(20.0);  // never raised
  EXPECT_EQ(g.ceiling(), 5.0);
}

TEST(CflRiseGuard, RestoredStateContinuesAsTheUninterruptedGuard) {
  CflRiseGuard a;
  EXPECT_FALSE(last_cuts(a, {1.0, 2.0}, 100.0));
  CflRiseGuard b;
  b.restore(a.state());
  EXPECT_EQ(a.observe(3.0, 100.0, 1.0), b.observe(3.0, 100.0, 1.0));
  EXPECT_EQ(a.ceiling(), b.ceiling());
  EXPECT_NEAR(b.ceiling(), 100.0 / 3.0, 1e-12);
}

}  // namespace
}  // namespace narwhal
