// Deflected rudders and stern planes (mesh/appendage_box.cpp, "A deflected control
// surface"): the box's grid deformed about the turned surface. The wall nodes lie on the
// turned fins and the hull, nothing outside the boxes moves, the grid stays unfolded and
// preserves the free stream, a rudder's opposite deflections are mirror images, and the
// case keys are checked against the configuration.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <unordered_map>

#include <fmt/format.h>

#include "config/case_config.hpp"
#include "core/error.hpp"
#include "mesh/appended_suboff.hpp"
#include "mesh/grid_quality.hpp"
#include "mesh/setup.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

constexpr Real kDegree = 3.14159265358979323846 / 180.0;

AppendedSuboffSpec deflected_spec(Real rudder_deg, Real planes_deg) {
  AppendedSuboffSpec s = test::small_appended_spec("stern4");
  s.box_half_width = s.cells_around / 2;  // half a sector, as on the family's members
  s.deflections.rudder = rudder_deg * kDegree;
  s.deflections.stern_planes = planes_deg * kDegree;
  return s;
}

bool in_a_fin_box(const std::string& block) {
  for (const char* tag : {"rud_up_", "rud_lo_", "plane_sb_", "plane_pt_"})
    if (block.rfind(tag, 0) == 0) return true;
  return false;
}

// How far the wall nodes lie from the surfaces they belong to: the turned fins (turned back,
// |n| = t(x, s) in the fin's plane, or on an edge), the turned tip planes (the radius R_max
// about the hull's axis before the turn) and the hull.
struct WallMiss {
  Real fin = 0.0, tip = 0.0, hull = 0.0;  // feet, feet, grid units
  int fin_nodes = 0;
};

WallMiss wall_miss(const Grid& g, const AppendedSuboffSpec& spec) {
  const Real ft = spec.length / suboff::kOverallLength;
  const suboff::Configuration fins = suboff::make_configuration(spec.configuration, spec.deflections);
  WallMiss m;
  test::for_each_patch_node(g, [&](const Block& b, const Patch& p, const Vec3& x) {
    if (p.label == "farfield") return;
    if (p.label == "body") {
      m.hull = std::max(m.hull, std::abs(std::hypot(x[1], x[2]) - suboff::hull_radius(x[0] / ft) * ft));
      return;
    }
    const auto& fin = **std::find_if(fins.appendages.begin(), fins.appendages.end(),
                                     [&](const auto& a) { return a->name() == p.label; });
    const Vec3 c = fin.plane_coordinates(suboff::from_grid_axes(x / ft));
    const Vec3 back = fin.plane_coordinates(fin.turned(c[0], c[1], c[2], -fin.deflection));
    if (b.name.find("_cap_") != std::string::npos) {
      m.tip = std::max(m.tip, std::abs(std::hypot(back[1], back[2]) - suboff::kMaxRadius));
      return;
    }
    const Real s = std::min(back[1], fin.tip(back[0]) * (1.0 - 1e-9));
    const Real miss = std::abs(back[2]) < 1e-12
                          ? std::min(std::abs(back[0] - fin.leading_edge(s)), std::abs(back[0] - fin.trailing_edge(s)))
                          : std::abs(std::abs(back[2]) - fin.half_thickness(back[0], s));
    m.fin = std::max(m.fin, miss);
    ++m.fin_nodes;
  });
  return m;
}

TEST(AppendedSuboff, DeflectedControlSurfacesDeformOnlyTheirBoxes) {
  const AppendedSuboffSpec spec = deflected_spec(10.0, -10.0), straight_spec = deflected_spec(0.0, 0.0);
  Grid g = make_appended_suboff(spec);
  const Grid straight = make_appended_suboff(straight_spec);

  // The wall nodes lie on the turned surfaces as the undeflected grid's lie on theirs. (Its
  // tip level passes R_max by up to 5e-5 ft between stations, where the section's nodes
  // stand 4e-7 ft off the tip section: mesh/appendage_box.cpp, surface_angle.)
  const WallMiss turned = wall_miss(g, spec), before = wall_miss(straight, straight_spec);
  EXPECT_GT(turned.fin_nodes, 4 * 6 * 8 * 8);
  EXPECT_LT(turned.fin, before.fin + 1e-8);  // feet
  EXPECT_LT(turned.tip, before.tip + 1e-8);  // feet
  EXPECT_LT(turned.hull, before.hull + 1e-9 * spec.length);
  EXPECT_LT(turned.hull, 1e-6 * spec.length);
  RecordProperty("largest_offset_from_turned_fin_ft", fmt::format("{:.2e} (undeflected {:.2e})", turned.fin, before.fin));
  RecordProperty("largest_offset_from_hull_ft",
                 fmt::format("{:.2e} (undeflected {:.2e})", turned.hull * suboff::kOverallLength / spec.length,
                             before.hull * suboff::kOverallLength / spec.length));

  // Outside the fins' boxes, every block as the undeflected grid's, bit for bit; inside, the
  // box's faces against the hull grid (its O's last ring) too, so the boxes still connect.
  std::map<std::string, const Block*> undeflected;
  for (const Block& b : straight.blocks) undeflected[b.name] = &b;
  int moved_boxes = 0;
  for (const Block& b : g.blocks) {
    const Block& a = *undeflected.at(b.name);
    ASSERT_EQ(a.dims(), b.dims()) << b.name;
    bool same = true;
    for (int k = 0; k <= b.nk; ++k)
      for (int j = 0; j <= b.nj; ++j)
        for (int i = 0; i <= b.ni; ++i) same = same && a.x(i, j, k) == b.x(i, j, k);
    if (!in_a_fin_box(b.name)) {
      EXPECT_TRUE(same) << b.name;
    }
    moved_boxes += !same;
    if (in_a_fin_box(b.name) && b.name.find("_cap_") == std::string::npos) {
      for (int k = 0; k <= b.nk; ++k)
        for (int i = 0; i <= b.ni; ++i) EXPECT_TRUE(a.x(i, b.nj, k) == b.x(i, b.nj, k)) << b.name;
    }
  }
  EXPECT_EQ(moved_boxes, 4 * 20);

  for (const auto& label : test::kAppendageLabels) assign_bc(g, label, {BcType::Dirichlet});
  assign_bc(g, "body", {BcType::Dirichlet});
  assign_bc(g, "farfield", {BcType::Dirichlet});
  finalize_grid(g);
  const Real r = test::relative_free_stream_residual(g);
  EXPECT_LT(r, 1e-12);
  const GridQuality q = measure_grid_quality(g, {"body", "upper_rudder"}, 0.0);
  EXPECT_EQ(q.folded_cells, 0u) << q.min_corner_jacobian.block;
  RecordProperty("smallest_scaled_corner_jacobian", fmt::format("{:.3f}", q.min_corner_jacobian.value));
}

// The undeflected grid is its own mirror image in the x-z plane (port to starboard) but for
// round-off; a rudder's deflection to port mirrored is the same deflection to starboard:
// what makes Y' and N' odd in the rudder angle. Every node of the rudders' boxes at +10
// degrees, mirrored, is a node of the -10 degree grid's.
TEST(AppendedSuboff, ARudderDeflectionsMirrorImageIsTheOppositeDeflection) {
  const Grid port = make_appended_suboff(deflected_spec(10.0, 0.0));
  const Grid starboard = make_appended_suboff(deflected_spec(-10.0, 0.0));
  const Real cell = 1e-5;  // hash cell, grid units; the test's tolerance is well inside it
  auto key = [cell](const Vec3& x) {
    const auto c = [cell](Real v) { return static_cast<long long>(std::floor(v / cell)); };
    return (c(x[0]) * 73856093LL) ^ (c(x[1]) * 19349663LL) ^ (c(x[2]) * 83492791LL);
  };
  std::unordered_multimap<long long, Vec3> nodes;
  for (const Block& b : starboard.blocks)
    if (b.name.rfind("rud_", 0) == 0)
      for (int k = 0; k <= b.nk; ++k)
        for (int j = 0; j <= b.nj; ++j)
          for (int i = 0; i <= b.ni; ++i) nodes.emplace(key(b.x(i, j, k)), b.x(i, j, k));
  Real worst = 0.0;
  int compared = 0;
  for (const Block& b : port.blocks) {
    if (b.name.rfind("rud_", 0) != 0) continue;
    for (int k = 0; k <= b.nk; ++k)
      for (int j = 0; j <= b.nj; ++j)
        for (int i = 0; i <= b.ni; ++i) {
          const Vec3 m(b.x(i, j, k)[0], -b.x(i, j, k)[1], b.x(i, j, k)[2]);
          Real nearest = std::numeric_limits<Real>::infinity();
          for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dz = -1; dz <= 1; ++dz) {
                const auto range = nodes.equal_range(key(m + cell * Vec3(dx, dy, dz)));
                for (auto it = range.first; it != range.second; ++it) nearest = std::min(nearest, (it->second - m).norm());
              }
          worst = std::max(worst, nearest);
          ++compared;
        }
  }
  EXPECT_GT(compared, 1000);
  EXPECT_LT(worst, 1e-8);  // grid units (L = 1)
  RecordProperty("largest_mirror_mismatch_L", fmt::format("{:.2e}", worst));
}

// The sail planes turned in their tube (mesh/sail_plane_tube.cpp): their section walls on
// the turned planes, their roots still on the sail's side, nothing outside the tube moved,
// no fold, and the free stream preserved.
TEST(AppendedSuboff, DeflectedSailPlanesDeformOnlyTheirTube) {
  const AppendedSuboffSpec straight = test::small_appended_spec("full");
  for (const Real degrees : {-10.0, 10.0}) {
    AppendedSuboffSpec s = straight;
    s.deflections.sail_planes = degrees * kDegree;
    Grid g = make_appended_suboff(s);
    const Grid g0 = make_appended_suboff(straight);
    ASSERT_EQ(g.blocks.size(), g0.blocks.size());
    const suboff::Configuration config = suboff::make_configuration("full", s.deflections);
    const Real ft = s.length / suboff::kOverallLength;
    Real worst_section = 0.0, worst_root = 0.0;
    int section = 0;
    test::for_each_patch_node(g, [&](const Block& b, const Patch& p, const Vec3& x) {
      if (p.label == "sail" && b.name.rfind("sp", 0) == 0) {
        worst_root = std::max(worst_root, std::abs(std::abs(x[1]) / ft - suboff::Sail::section_half_thickness(x[0] / ft)));
        return;
      }
      if (p.label.find("sail_plane") == std::string::npos || b.name.find("cap") != std::string::npos ||
          b.name.find("core") != std::string::npos)
        return;
      const auto& fin = static_cast<const suboff::Fin&>(**std::find_if(
          config.appendages.begin(), config.appendages.end(), [&](const auto& a) { return a->name() == p.label; }));
      // Turned back about the stock, then |n| = t(x, s) in the plane (or on an edge).
      const Vec3 c = fin.plane_coordinates(suboff::from_grid_axes(x / ft));
      const Vec3 back = fin.plane_coordinates(fin.turned(c[0], c[1], c[2], -fin.deflection));
      const Real s_in = std::min(back[1], fin.shape().tip_span * (1.0 - 1e-12));
      const Real miss = std::abs(back[2]) < 1e-8
                            ? std::hypot(std::min(std::abs(back[0] - fin.leading_edge(s_in)), std::abs(back[0] - fin.trailing_edge(s_in))), back[2])
                            : std::abs(std::abs(back[2]) - fin.half_thickness(back[0], s_in));
      worst_section = std::max(worst_section, miss);
      ++section;
    });
    EXPECT_GT(section, 2 * 8 * 8) << degrees;
    EXPECT_LT(worst_section, 1e-8) << degrees;  // feet: the turn and its inverse's round-off
    EXPECT_LT(worst_root, 1e-9) << degrees;
    // Outside the tube every block as the undeflected grid's, bit for bit.
    for (std::size_t i = 0; i < g.blocks.size(); ++i) {
      const Block &b = g.blocks[i], &a = g0.blocks[i];
      if (b.name.rfind("sp", 0) == 0) continue;
      bool same = a.dims() == b.dims();
      for (int k = 0; same && k <= b.nk; ++k)
        for (int j = 0; j <= b.nj; ++j)
          for (int i2 = 0; i2 <= b.ni; ++i2) same = same && a.x(i2, j, k) == b.x(i2, j, k);
      EXPECT_TRUE(same) << b.name;
    }
    for (const auto& label : test::kAppendageLabels) assign_bc(g, label, {BcType::Dirichlet});
    assign_bc(g, "body", {BcType::Dirichlet});
    assign_bc(g, "farfield", {BcType::Dirichlet});
    finalize_grid(g);
    EXPECT_LT(test::relative_free_stream_residual(g), 1e-12) << degrees;
    RecordProperty(fmt::format("sail_planes_{}_quality", degrees),
                   format_grid_quality(measure_grid_quality(g, {"starboard_sail_plane"}, 1.3e7)));
  }
}

// Where the box has no room for the deflection, the grid is refused naming the box and the
// block and cell that fold (a fin turned by 30 degrees in the small test grid's narrow box).
TEST(AppendedSuboff, ADeflectionItsBoxCannotHoldIsRefusedByName) {
  try {
    make_appended_suboff(deflected_spec(30.0, 0.0));
    FAIL() << "accepted a fold";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("appendage box 'upper_rudder' deflected by 30 degrees"), std::string::npos) << what;
    EXPECT_NE(what.find("block 'rud_up_"), std::string::npos) << what;
  }
}

// The small appended case with both control surfaces deflected.
const std::vector<std::string> kDeflected{"grid.rudder_deflection=5.0", "grid.stern_plane_deflection=-5.0"};


// The keys in degrees (Gertler & Hagen's signs) reach the geometry in radians, and a
// deflection of a surface the configuration lacks is refused naming the key.
TEST(AppendedSuboffCase, DeflectionKeysTurnTheirSurfacesAndAreCheckedAgainstTheConfiguration) {
  const CaseConfig c = parse_case(test::kSmallAppendedCase, "appended.toml", ".", kDeflected);
  EXPECT_NEAR(c.grid.appended.deflections.rudder, 5.0 * kDegree, 1e-15);
  EXPECT_NEAR(c.grid.appended.deflections.stern_planes, -5.0 * kDegree, 1e-15);
  try {
    std::vector<std::string> sets = kDeflected;
    sets.push_back("grid.configuration=\"sail\"");
    parse_case(test::kSmallAppendedCase, "appended.toml", ".", sets);
    FAIL() << "accepted a rudder angle without rudders";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("grid.rudder_deflection"), std::string::npos) << what;
    EXPECT_NE(what.find("no upper_rudder"), std::string::npos) << what;
  }
  EXPECT_THROW(parse_case(test::kSmallAppendedCase, "appended.toml", ".", {"grid.rudder_deflection=45"}), Error);
}

}  // namespace
}  // namespace narwhal
