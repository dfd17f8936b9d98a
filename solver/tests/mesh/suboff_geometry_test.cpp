// The SUBOFF appendages (mesh/suboff_geometry.hpp): the equations against the properties
// the report states (continuity, closure, the section's maximum) and against the design
// values Roddy (1990, Table 1) printed independently of them; the deflection conventions.
#include <gtest/gtest.h>

#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "mesh/suboff_geometry.hpp"

namespace narwhal::suboff {
namespace {

constexpr Real kDeg = M_PI / 180.0;

TEST(SuboffSail, SectionIsContinuousAndClosed) {
  // §3: Z1 reaches Z_max at both ends of the parallel part (D = 1, E = 1) and vanishes at
  // the leading and trailing edges.
  const Real eps = 1e-9;
  EXPECT_NEAR(Sail::section_half_thickness(3.358507 - eps), Sail::kMaxHalfThickness, 1e-6);
  EXPECT_NEAR(Sail::section_half_thickness(3.559028 + eps), Sail::kMaxHalfThickness, 1e-6);
  EXPECT_NEAR(Sail::section_half_thickness(Sail::kLeadingEdge + eps), 0.0, 1e-4);
  EXPECT_NEAR(Sail::section_half_thickness(Sail::kTrailingEdge - eps), 0.0, 1e-6);
  Real largest = 0.0;
  for (int n = 0; n <= 10000; ++n)
    largest = std::max(largest, Sail::section_half_thickness(3.0 + 1.3 * n / 10000));
  EXPECT_NEAR(largest, Sail::kMaxHalfThickness, 1e-12);
}

TEST(SuboffSail, MatchesRoddysDesignValues) {
  // Roddy (1990) Table 1: chord 1.208 ft, FP to sail leading edge 3.033 ft, span 0.729 ft
  // (hull top to the cap's crest), printed to 3 decimals.
  const Sail sail;
  EXPECT_NEAR(sail.trailing_edge(1.0) - sail.leading_edge(1.0), 1.208, 5e-4);
  EXPECT_NEAR(sail.leading_edge(1.0), 3.033, 5e-4);
  EXPECT_NEAR(sail.tip(3.45) - kMaxRadius, 0.729, 5e-4);
  // The cap closes the section: no thickness at or above its crest.
  for (const Real x : {3.1, 3.45, 4.0}) {
    EXPECT_GT(sail.half_thickness(x, sail.tip(x) - 1e-3), 0.0) << x;
    EXPECT_EQ(sail.half_thickness(x, sail.tip(x) + 1e-12), 0.0) << x;
    EXPECT_NEAR(sail.half_thickness(x, Sail::kUniformTop), Sail::section_half_thickness(x), 1e-15);
  }
}

TEST(SuboffFin, SectionAndChordLaw) {
  // §4: the coefficients sum to zero (a closed trailing edge); the largest z/c is 0.100 at
  // xi ~ 0.30 (NACA 0020 type).
  EXPECT_NEAR(0.29690 - 0.12600 - 0.35160 + 0.28520 - 0.10450, 0.0, 1e-15);
  Real largest = 0.0, where = 0.0;
  for (int n = 1; n < 100000; ++n) {
    const Real xi = n / 100000.0, z = Fin::section(xi);
    if (z > largest) largest = z, where = xi;
  }
  EXPECT_NEAR(largest, 0.1000, 5e-4);
  EXPECT_NEAR(where, 0.30, 0.02);
  // Roddy Table 1: tip chord 0.500, root chord 0.704 ft at 0.438 ft of span inside the tip.
  const auto fin = make_stern_appendage(SternAppendage::UpperRudder);
  EXPECT_NEAR(fin->chord(kMaxRadius), 0.500, 1e-6);
  EXPECT_NEAR(fin->chord(kMaxRadius - 0.438), 0.704, 5e-4);
  // The report's flat tip: the section ends whole at s = R_max.
  EXPECT_EQ(fin->half_thickness(12.9, kMaxRadius), 0.0);
  EXPECT_GT(fin->half_thickness(12.9, kMaxRadius - 1e-4), 0.0);
  const Real s = 0.6, x = fin->leading_edge(s) + 0.3 * fin->chord(s);
  EXPECT_NEAR(fin->half_thickness(x, s), fin->chord(s) * Fin::section(0.3), 1e-14);
}

TEST(SuboffFin, DeflectionsFollowTheStatedConventions) {
  // Positive rudder angle: trailing edges to port (+z); positive stern- and sail-plane
  // angles: trailing edges down (-y). The stock stays put and the fin turns rigidly.
  const Real delta = 10.0 * kDeg, s_mid = 0.6;
  struct Case {
    std::unique_ptr<Fin> fin;
    Vec3 trailing_edge_moves;
  };
  std::vector<Case> cases;
  cases.push_back({make_stern_appendage(SternAppendage::UpperRudder, delta), Vec3::UnitZ()});
  cases.push_back({make_stern_appendage(SternAppendage::LowerRudder, delta), Vec3::UnitZ()});
  cases.push_back({make_stern_appendage(SternAppendage::StarboardPlane, delta), -Vec3::UnitY()});
  cases.push_back({make_stern_appendage(SternAppendage::PortPlane, delta), -Vec3::UnitY()});
  cases.push_back({make_sail_plane(true, delta), -Vec3::UnitY()});
  cases.push_back({make_sail_plane(false, delta), -Vec3::UnitY()});
  for (const auto& c : cases) {
    const Fin& f = *c.fin;
    const Real s = f.shape().on_sail ? 0.3 : s_mid;
    const Real te = f.trailing_edge(s), le = f.leading_edge(s);
    const Vec3 moved = f.deflected(te, s, 0.0);
    Fin straight(f.name(), f.shape());
    straight.origin = f.origin, straight.span_direction = f.span_direction, straight.offset_direction = f.offset_direction;
    const Vec3 rest = straight.deflected(te, s, 0.0);
    EXPECT_NEAR((moved - rest).normalized().dot(c.trailing_edge_moves), std::cos(0.5 * delta), 1e-12) << f.name();
    EXPECT_NEAR((f.deflected(f.stock_x, s, 0.0) - straight.deflected(f.stock_x, s, 0.0)).norm(), 0.0, 1e-15);
    const Real x_mid = 0.5 * (le + te);
    EXPECT_NEAR((f.surface_point(le + 0.1, s, 1) - f.surface_point(x_mid, s, -1)).norm(),
                (straight.surface_point(le + 0.1, s, 1) - straight.surface_point(x_mid, s, -1)).norm(), 1e-14)
        << f.name();
    // The stock is inside the planform at mid-span.
    EXPECT_GT(f.stock_x, le);
    EXPECT_LT(f.stock_x, te);
  }
}

TEST(SuboffConfigurations, ByName) {
  EXPECT_EQ(make_configuration("bare").appendages.size(), 0u);
  EXPECT_EQ(make_configuration("sail").appendages.size(), 1u);
  EXPECT_EQ(make_configuration("stern4").appendages.size(), 4u);
  EXPECT_EQ(make_configuration("sail_stern4").appendages.size(), 5u);
  EXPECT_EQ(make_configuration("full").appendages.size(), 7u);
  try {
    make_configuration("aff8");
    FAIL() << "accepted an unknown configuration";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("aff8"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("sail_stern4"), std::string::npos);
  }
}


}  // namespace
}  // namespace narwhal::suboff
