// The O-grid about a thin section (mesh/section_ogrid.hpp): nodes exactly on the section
// and on the box, the wall spacing asked for along the section's normal, no folded cell
// (straight or deflected section), the interior quadrilateral, and clear refusals.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "mesh/section_ogrid.hpp"

namespace narwhal::ogrid {
namespace {

// The stern appendages' section (reference_data/suboff/suboff_geometry.md, section 4),
// chord 1: round leading edge, sharp trailing edge.
Real half_thickness(Real u) {
  return 0.29690 * std::sqrt(u) - 0.12600 * u - 0.35160 * u * u + 0.28520 * u * u * u - 0.10450 * u * u * u * u;
}

// The section turned by `angle` (radians, trailing edge towards -w for positive) about
// the quarter chord: a deflected control surface.
Section fin_section(Real angle = 0.0) {
  const Real c = std::cos(angle), s = std::sin(angle);
  auto turned = [c, s](Real x, Real w) {
    const Real dx = x - 0.25;
    return Point(0.25 + c * dx + s * w, -s * dx + c * w);
  };
  return {[=](Real u) { return turned(u, half_thickness(u)); }, [=](Real u) { return turned(u, -half_thickness(u)); }};
}

std::vector<Point> line(Point a, Point b, int n) {
  std::vector<Point> p;
  for (int k = 0; k <= n; ++k) p.push_back(a + (b - a) * (static_cast<Real>(k) / n));
  return p;
}

// A box from -0.3 to 1.4 along the chord and 0.4 to each side.
Box box(int across = 8, int along = 40) {
  const Point lf(-0.3, -0.4), uf(-0.3, 0.4), ub(1.4, 0.4), lb(1.4, -0.4);
  return {line(lf, uf, across), line(uf, ub, along), line(ub, lb, across), line(lb, lf, along)};
}

Spec spec() {
  Spec s;
  s.cells_normal = 32;
  s.first_spacing = 1e-5;
  s.outer_spacing = 0.05;
  s.leading_edge_spacing = 2e-3;
  s.trailing_edge_spacing = 2e-3;
  s.layer = 0.05;
  return s;
}

// The smallest sine of a cell's corner angles (negative: a concave or folded cell).
Real smallest_corner_sine(const Point& a, const Point& b, const Point& c, const Point& d) {
  const Point p[4] = {a, b, c, d};
  Real worst = 1.0;
  for (int m = 0; m < 4; ++m) {
    const Point e1 = p[(m + 1) % 4] - p[m], e0 = p[(m + 3) % 4] - p[m];
    worst = std::min(worst, (e1[0] * e0[1] - e1[1] * e0[0]) / (e1.norm() * e0.norm()));
  }
  return worst;
}

// The smallest doubled area or corner sine, and the largest doubled area, over the O's cells.
std::pair<Real, Real> area_range(const OGrid& o) {
  Real lo = 1e300, hi = -1e300;
  for (int t = 0; t < o.cells_normal(); ++t)
    for (int s = 0; s < o.cells_around(); ++s) {
      const auto& r0 = o.ring[static_cast<std::size_t>(t)];
      const auto& r1 = o.ring[static_cast<std::size_t>(t + 1)];
      const std::size_t a = static_cast<std::size_t>(s), b = a + 1;
      const Real area = quad_area2(r0[a], r0[b], r1[b], r1[a]);
      lo = std::min(lo, std::min(area, smallest_corner_sine(r0[a], r0[b], r1[b], r1[a])));
      hi = std::max(hi, area);
    }
  return {lo, hi};
}

TEST(SectionOGrid, SectionNodesLieOnTheSectionAndTheOuterRingIsTheBox) {
  const Section sec = fin_section();
  const Box b = box();
  const OGrid o = make_section_ogrid(sec, b, spec());
  EXPECT_EQ(o.cells_around(), 8 + 40 + 8 + 40);
  EXPECT_EQ((std::array<int, 5>{0, 8, 48, 56, 96}), o.split);
  const auto& wall = o.ring.front();
  for (int s = 0; s <= o.cells_around(); ++s) {
    const Point p = wall[static_cast<std::size_t>(s)];
    const Real u = o.u[static_cast<std::size_t>(s)];
    const Point on = p[1] >= 0.0 ? sec.upper(u) : sec.lower(u);
    EXPECT_LT((p - on).norm(), 1e-15) << "node " << s;
  }
  EXPECT_EQ(o.u[4], 0.0);   // the leading edge is the front arc's middle node
  EXPECT_EQ(o.u[52], 1.0);  // the trailing edge the back arc's
  // The box's nodes, bit for bit: the surrounding grid shares them.
  const auto& edge = o.ring.back();
  for (int k = 0; k <= 8; ++k) EXPECT_EQ(edge[static_cast<std::size_t>(k)], b.front[static_cast<std::size_t>(k)]);
  for (int k = 0; k <= 40; ++k) EXPECT_EQ(edge[static_cast<std::size_t>(8 + k)], b.top[static_cast<std::size_t>(k)]);
  for (int k = 0; k <= 8; ++k) EXPECT_EQ(edge[static_cast<std::size_t>(48 + k)], b.back[static_cast<std::size_t>(k)]);
  for (int k = 0; k < 40; ++k) EXPECT_EQ(edge[static_cast<std::size_t>(56 + k)], b.bottom[static_cast<std::size_t>(k)]);
}

TEST(SectionOGrid, TheFirstCellsHaveTheWallSpacingAlongTheNormal) {
  const Section sec = fin_section();
  const OGrid o = make_section_ogrid(sec, box(), spec());
  Real worst_angle = 0.0, worst_spacing = 0.0;
  for (int s = 0; s < o.cells_around(); ++s) {
    const std::size_t a = static_cast<std::size_t>(s);
    worst_spacing = std::max(worst_spacing, std::abs((o.ring[1][a] - o.ring[0][a]).norm() / 1e-5 - 1.0));
    // The edges have no tangent, and the normals fan over three nodes either side of the
    // trailing edge.
    if (s == 4 || std::abs(s - 52) <= 3) continue;
    const Real u = o.u[a], h = 1e-7;
    const auto& side = o.ring[0][a][1] >= 0.0 ? sec.upper : sec.lower;
    const Point tangent = (side(std::min(1.0, u + h)) - side(std::max(0.0, u - h))).normalized();
    const Point d = (o.ring[1][a] - o.ring[0][a]).normalized();
    worst_angle = std::max(worst_angle, std::abs(std::asin(d.dot(tangent))));
  }
  EXPECT_LT(worst_spacing, 1e-9);
  EXPECT_LT(worst_angle * 180.0 / M_PI, 1e-3);
}

TEST(SectionOGrid, NoCellFoldsStraightOrDeflected) {
  // Rudders and planes are swept over +-10 degrees in the captive runs (at -15 a corner
  // beside the trailing edge turns concave: larger deflections need more).
  for (const Real deg : {0.0, 10.0, -10.0, 12.0, -12.0}) {
    const OGrid o = make_section_ogrid(fin_section(deg * M_PI / 180.0), box(), spec());
    EXPECT_GT(area_range(o).first, 0.0) << deg << " degrees";
  }
}

TEST(SectionOGrid, TheLinesStretchGently) {
  const OGrid o = make_section_ogrid(fin_section(), box(), spec());
  Real worst = 1.0;
  for (int s = 0; s < o.cells_around(); ++s)
    for (int t = 1; t < o.cells_normal(); ++t) {
      const std::size_t a = static_cast<std::size_t>(s), k = static_cast<std::size_t>(t);
      const Real inner = (o.ring[k][a] - o.ring[k - 1][a]).norm(), outer = (o.ring[k + 1][a] - o.ring[k][a]).norm();
      worst = std::max(worst, std::max(outer / inner, inner / outer));
    }
  // The fastest growth is the boundary layer's: geometric from the first spacing to the
  // layer in half the cells, r with 1e-5 (r^16 - 1) / (r - 1) = 0.05.
  Real lo = 1.0, hi = 3.0;
  for (int it = 0; it < 100; ++it) {
    const Real r = 0.5 * (lo + hi);
    (1e-5 * (std::pow(r, 16) - 1.0) / (r - 1.0) < 0.05 ? lo : hi) = r;
  }
  EXPECT_LT(worst, 1.01 * lo);
  EXPECT_GT(worst, 0.99 * lo);
}

TEST(SectionOGrid, TheCapIsBoundedByTheSectionNodesAndNoCellIsConcave) {
  for (const Real deg : {0.0, 10.0}) {
    const Section sec = fin_section(deg * M_PI / 180.0);
    const OGrid o = make_section_ogrid(sec, box(8, 40), spec());
    const SectionCap cap = section_cap(o, sec, 3);
    ASSERT_EQ(cap.ring.size(), 4u);
    EXPECT_EQ(cap.ring.front(), o.ring.front());  // the section's nodes, bit for bit
    ASSERT_EQ(cap.core.size(), 41u);
    ASSERT_EQ(cap.core[0].size(), 9u);
    const auto& edge = cap.ring.back();
    for (int a = 0; a <= 40; ++a) {
      EXPECT_EQ(cap.core[static_cast<std::size_t>(a)][0], edge[static_cast<std::size_t>(96 - a)]);  // lower side
      EXPECT_EQ(cap.core[static_cast<std::size_t>(a)][8], edge[static_cast<std::size_t>(8 + a)]);   // upper side
    }
    for (int b = 0; b <= 8; ++b) {
      EXPECT_EQ(cap.core[0][static_cast<std::size_t>(b)], edge[static_cast<std::size_t>(b)]);        // front
      EXPECT_EQ(cap.core[40][static_cast<std::size_t>(b)], edge[static_cast<std::size_t>(56 - b)]);  // back
    }
    // Ring cells run the O's way round but inwards: clockwise; the core's counter-clockwise.
    Real ring_worst = 1.0, core_worst = 1.0;
    for (std::size_t t = 0; t + 1 < cap.ring.size(); ++t)
      for (std::size_t q = 0; q < 96; ++q)
        ring_worst = std::min(ring_worst, smallest_corner_sine(cap.ring[t][q], cap.ring[t + 1][q], cap.ring[t + 1][q + 1],
                                                               cap.ring[t][q + 1]));
    for (std::size_t a = 0; a < 40; ++a)
      for (std::size_t b = 0; b < 8; ++b)
        core_worst = std::min(core_worst, smallest_corner_sine(cap.core[a][b], cap.core[a + 1][b],
                                                               cap.core[a + 1][b + 1], cap.core[a][b + 1]));
    EXPECT_GT(ring_worst, 0.0) << deg << " degrees";
    EXPECT_GT(core_worst, 0.0) << deg << " degrees";
  }
}

TEST(SectionOGrid, CountsThatCannotMakeAnOGridAreRefused) {
  EXPECT_THROW(
      {
        try {
          make_section_ogrid(fin_section(), box(7, 40), spec());
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("even number of cells"), std::string::npos) << e.what();
          throw;
        }
      },
      Error);
  Box broken = box();
  broken.top.front() = Point(-0.3, 0.5);
  EXPECT_THROW(make_section_ogrid(fin_section(), broken, spec()), Error);
  Box uneven = box(8, 40);
  uneven.bottom = line(Point(1.4, -0.4), Point(-0.3, -0.4), 32);
  EXPECT_THROW(section_cap(make_section_ogrid(fin_section(), uneven, spec()), fin_section(), 3), Error);
}

}  // namespace
}  // namespace narwhal::ogrid
