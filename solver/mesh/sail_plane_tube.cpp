#include "mesh/sail_plane_tube.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <fmt/format.h>

#include "core/error.hpp"
#include "mesh/grid_quality.hpp"
#include "mesh/level_stack.hpp"
#include "mesh/turned_fin.hpp"
#include "mesh/meridian.hpp"

namespace narwhal {
namespace {

using ogrid::Point;

constexpr int kCapRingCells = 8;  // as the appendage boxes' caps: three multigrid levels

Point chart_of(const Vec3& p) { return {p[0], std::hypot(p[1], p[2])}; }

Vec3 to_space(const TubeLevel& level, const Point& c) {
  const Real phi = level.azimuth(c[0], c[1]);
  return {c[0], c[1] * std::cos(phi), c[1] * std::sin(phi)};
}

// The plane's coordinates (x, s, n; feet) of a grid point.
Vec3 plane_coordinates(const suboff::Fin& fin, Real feet, const Vec3& p) {
  return fin.plane_coordinates(suboff::from_grid_axes(p / feet));
}

// The point of the level at chart x whose offset from the plane is n (feet): a secant
// solve along r from the plane's height.
Real r_at_offset(const TubeLevel& level, const suboff::Fin& fin, Real feet, Real x, Real n, Real r_guess) {
  auto f = [&](Real r) { return plane_coordinates(fin, feet, to_space(level, {x, r}))[2] - n; };
  Real r0 = r_guess, f0 = f(r0);
  Real r1 = r_guess * (1.0 + 1e-4), f1 = f(r1);
  for (int it = 0; it < 100 && std::abs(f1) > 1e-15 && f1 != f0; ++it) {
    const Real r2 = r1 - f1 * (r1 - r0) / (f1 - f0);
    r0 = r1, f0 = f1;
    r1 = r2, f1 = f(r1);
  }
  if (!(std::abs(f1) < 1e-9)) fail("sail planes' tube: no point of a level at offset {:.4g} ft from '{}'", n, fin.name());
  return r1;
}

// The plane's section on a level: the point at chord fraction u on its upper (larger r)
// or lower side, as a chart point. The span is held inside the tip (the tip level may
// cross it between stations by a hair, as the boxes' levels do).
struct SectionOnLevel {
  const TubeLevel& level;
  const suboff::Fin& fin;
  Real feet, r_plane;
  Point at(Real u, bool upper) const {
    const Real tip = fin.shape().tip_span * (1.0 - 1e-12);
    Real x = 0.0, r = r_plane;
    Real s = std::min(plane_coordinates(fin, feet, to_space(level, {fin.leading_edge(0.0) * feet, r}))[1], tip);
    for (int it = 0; it < 50; ++it) {
      const Real x_ft = fin.leading_edge(s) + u * fin.chord(s);
      // At the edges exactly in the plane: the chord fraction's round-off under the leading
      // edge's square root would put the two sides 2e-9 ft apart there.
      const Real n = u <= 0.0 || u >= 1.0 ? 0.0 : (upper ? -1.0 : 1.0) * fin.half_thickness(x_ft, s);
      const Real x_new = x_ft * feet;
      r = r_at_offset(level, fin, feet, x_new, n, r);
      const Real s_new = std::min(plane_coordinates(fin, feet, to_space(level, {x_new, r}))[1], tip);
      const bool settled = std::abs(x_new - x) < 1e-14 * feet && std::abs(s_new - s) < 1e-14;
      x = x_new, s = s_new;
      if (settled) break;
    }
    return {x, r};
  }
};

// The host's nodes of a level on the tube's outline, as chart points, in the O's running
// order (ogrid::Box): front lower -> upper, top front -> back, back upper -> lower,
// bottom back -> front; and the same nodes in space.
struct Outline {
  ogrid::Box chart;
  std::vector<Vec3> ring;  // front, top, back, bottom without their last nodes
};

Outline outline_of(const SailPlaneTube& tube, const TubeLevel& level) {
  Outline o;
  std::vector<Vec3> front, top, back, bottom;
  for (int k = tube.level_low; k <= tube.level_high; ++k) front.push_back(level.node(tube.station_first, k));
  for (int i = tube.station_first; i <= tube.station_last; ++i) top.push_back(level.node(i, tube.level_high));
  for (int k = tube.level_high; k >= tube.level_low; --k) back.push_back(level.node(tube.station_last, k));
  for (int i = tube.station_last; i >= tube.station_first; --i) bottom.push_back(level.node(i, tube.level_low));
  auto charted = [](const std::vector<Vec3>& side) {
    std::vector<Point> c;
    for (const Vec3& p : side) c.push_back(chart_of(p));
    return c;
  };
  o.chart = {charted(front), charted(top), charted(back), charted(bottom)};
  for (const auto* side : {&front, &top, &back, &bottom}) o.ring.insert(o.ring.end(), side->begin(), side->end() - 1);
  o.ring.push_back(o.ring.front());
  return o;
}

// Which plane a level belongs to: 0 from the first level to the first tip, 1 from the
// second tip to the last, -1 between the tips (the cap).
int plane_of_level(const SailPlaneTube& tube, int l) {
  if (l < tube.tips[0]) return 0;
  if (l > tube.tips[1]) return 1;
  return -1;
}

// The height over which a level lies beyond its nearer tip (grid units): the distance
// between their mid nodes.
Real beyond_tip(const SailPlaneTube& tube, int l) {
  const int mid_station = (tube.station_first + tube.station_last) / 2;
  const auto at = [&](int level) { return tube.levels[static_cast<std::size_t>(level)].node(mid_station, tube.level_mid); };
  const int tip = std::abs(l - tube.tips[0]) <= std::abs(l - tube.tips[1]) ? tube.tips[0] : tube.tips[1];
  return (at(l) - at(tip)).norm();
}

// A section side sampled at u = v^2 (v uniform: the round leading edge) and interpolated
// linearly in v: the cap's levels beyond a tip, where the outline is no wall, take the
// tip's section this way instead of solving for it at every point the O asks for.
std::function<Point(Real)> tabulated(const std::function<Point(Real)>& f) {
  constexpr int n = 4000;
  auto table = std::make_shared<std::vector<Point>>();
  for (int k = 0; k <= n; ++k) table->push_back(f(static_cast<Real>(k) * k / (static_cast<Real>(n) * n)));
  return [table](Real u) -> Point {
    const Real v = std::sqrt(std::clamp(u, 0.0, 1.0)) * n;
    const int k = std::min(static_cast<int>(v), n - 1);
    const Real w = v - k;
    return (1.0 - w) * (*table)[static_cast<std::size_t>(k)] + w * (*table)[static_cast<std::size_t>(k + 1)];
  };
}

// The tip sections in the chart: each plane's on its tip level (the cap's lowest face),
// exact, and tabulated for the levels beyond.
struct TipSections {
  std::array<ogrid::Section, 2> exact, table;
};

TipSections tip_sections(const SailPlaneTube& tube) {
  TipSections s;
  for (std::size_t p = 0; p < 2; ++p) {
    const TubeLevel& level = tube.levels[static_cast<std::size_t>(tube.tips[p])];
    const Real r_plane =
        chart_of(level.node((tube.station_first + tube.station_last) / 2, tube.level_mid))[1];
    const SectionOnLevel on{level, *tube.planes[p], tube.feet, r_plane};
    s.exact[p] = {[on](Real u) { return on.at(u, true); }, [on](Real u) { return on.at(u, false); }};
    s.table[p] = {tabulated(s.exact[p].upper), tabulated(s.exact[p].lower)};
  }
  return s;
}


Level make_tube_level(const SailPlaneTube& tube, int l, const TipSections& tips) {
  const TubeLevel& level = tube.levels[static_cast<std::size_t>(l)];
  const int owner = plane_of_level(tube, l);
  const bool cap = owner < 0 || l == tube.tips[0] || l == tube.tips[1];
  const Outline outline = outline_of(tube, level);
  const Real r_plane = chart_of(level.node((tube.station_first + tube.station_last) / 2, tube.level_mid))[1];

  // The section: the plane's own up to its tip; beyond, the nearer tip's, widened by up
  // to twice its thickness over cap_growth (its chart points the same on every level).
  const Real grown = owner < 0 && tube.cap_growth > 0.0 ? revolution::smoothstep(beyond_tip(tube, l) / tube.cap_growth)
                                                         : 0.0;
  ogrid::Section section;
  if (owner >= 0 && !(l == tube.tips[0] || l == tube.tips[1])) {
    const SectionOnLevel on{level, *tube.planes[static_cast<std::size_t>(owner)], tube.feet, r_plane};
    section = {[on](Real u) { return on.at(u, true); }, [on](Real u) { return on.at(u, false); }};
  } else {
    const std::size_t nearer = l - tube.tips[0] <= tube.tips[1] - l ? 0 : 1;
    const ogrid::Section& tip = l == tube.tips[nearer] ? tips.exact[nearer] : tips.table[nearer];
    auto widened = [tip, grown](bool upper) {
      return [tip, grown, upper](Real u) -> Point {
        const Point a = tip.upper(u), b = tip.lower(u), mean = 0.5 * (a + b);
        return mean + (1.0 + grown) * ((upper ? a : b) - mean);
      };
    };
    section = {widened(true), widened(false)};
  }

  ogrid::Spec spec = tube.section_grid;
  // The O's last cells as the host's next to the outline.
  Real host = std::numeric_limits<Real>::max();
  const auto& c = outline.chart;
  host = std::min({host, (c.front[1] - c.front[0]).norm(), (c.top[1] - c.top[0]).norm(),
                   (c.back[1] - c.back[0]).norm(), (c.bottom[1] - c.bottom[0]).norm()});
  spec.outer_spacing = std::min(spec.outer_spacing, host);
  if (grown > 0.0) {
    // Far from a tip the lines from the widened outline may be short: no more than a
    // quarter of the mean spacing of the shortest (as the boxes' caps).
    Real shortest = std::min(section.upper(0.0)[0] - c.front.front()[0], c.back.front()[0] - section.upper(1.0)[0]);
    for (const Point& p : c.top) shortest = std::min(shortest, p[1] - section.upper(0.5)[1]);
    for (const Point& p : c.bottom) shortest = std::min(shortest, section.lower(0.5)[1] - p[1]);
    const Real most = 0.25 * std::min(spec.outer_spacing, shortest / spec.cells_normal);
    spec.first_spacing += grown * (std::max(most, spec.first_spacing) - spec.first_spacing);
  }
  const ogrid::OGrid o = ogrid::make_section_ogrid(section, outline.chart, spec);

  Level lv;
  lv.split = o.split;
  const int n = o.cells_normal(), around = o.cells_around();
  if (static_cast<int>(outline.ring.size()) != around + 1) fail("sail planes' tube: internal: outline ring");
  lv.ring.assign(static_cast<std::size_t>(n + 1), std::vector<Vec3>(static_cast<std::size_t>(around + 1)));
  for (int t = 0; t <= n; ++t)
    for (int s = 0; s <= around; ++s) {
      const std::size_t ut = static_cast<std::size_t>(t), us = static_cast<std::size_t>(s);
      lv.ring[ut][us] = t == n ? outline.ring[us] : to_space(level, o.ring[ut][us]);
    }
  for (int t = 0; t < n; ++t) lv.ring[static_cast<std::size_t>(t)].back() = lv.ring[static_cast<std::size_t>(t)].front();
  if (cap) {
    const ogrid::SectionCap sc = ogrid::section_cap(o, section, kCapRingCells);
    for (const auto& row : sc.ring) {
      std::vector<Vec3> r;
      for (const Point& p : row) r.push_back(to_space(level, p));
      lv.cap_ring.push_back(std::move(r));
    }
    lv.cap_ring.front() = lv.ring.front();
    for (const auto& row : sc.core) {
      std::vector<Vec3> r;
      for (const Point& p : row) r.push_back(to_space(level, p));
      lv.core.push_back(std::move(r));
    }
    tie_core_to_cap_ring(lv);
  }
  return lv;
}

// ---- Deflected sail planes (as the boxes' control surfaces, mesh/DESIGN.md) ----
// A plane's levels turn about its stock by the deflection times a weight: 1 on the section
// and through the O's wall layer (its first half), falling smoothly to 0 at the outline
// (the host's nodes stay bit for bit); 1 from the root to the tip, falling over
// cap_growth beyond it. The root level stays on the sail's side: each section column
// slides along the turned surface by the span shift that puts its root node back on the
// side, fading to nothing at the tip, and the rest of the root level moves across the
// sail's plane onto the side, that correction fading over the span too.
void deflect_plane(const SailPlaneTube& tube, std::size_t which, std::vector<Level>& lv) {
  const suboff::Fin& fin = *tube.planes[which];
  if (!fin.is_deflected()) return;
  if (!(tube.cap_growth > 0.0))
    fail("sail planes' tube: a deflection needs cap_growth > 0 (the distance over which the turn fades)");
  const Real feet = tube.feet;
  // Off the sail's side: across the sail's plane (grid y).
  const TurnedFin f{fin, feet, [feet](const Vec3& node) {
                      return std::abs(node[1]) - suboff::Sail::section_half_thickness(node[0] / feet) * feet;
                    }};
  const int last = static_cast<int>(lv.size()) - 1, tip = tube.tips[which];
  const int n = static_cast<int>(lv.front().ring.size()) - 1;
  const std::size_t around = lv.front().ring.front().size();
  // Levels counted from this plane's root; its half of the tube only.
  auto level = [&](int depth) { return which == 0 ? depth : last - depth; };
  const int tip_depth = which == 0 ? tip : last - tip, half = last / 2;
  auto turn_weight = [&](int depth) {
    if (depth <= tip_depth) return 1.0;
    return 1.0 - revolution::smoothstep(beyond_tip(tube, level(depth)) / tube.cap_growth);
  };
  auto ring_weight = [&](int t) {
    const int layer = n / 2;
    return t <= layer ? 1.0 : 1.0 - revolution::smoothstep(static_cast<Real>(t - layer) / (n - layer));
  };
  // How far up the span a level lies, 0 at the root and 1 at the tip, by the distance of
  // its mid node (the levels crowd towards the tip's clustered ring: by index, the root's
  // corrections stopped 1e-5 ft short of it across levels 1e-6 ft apart, and folded them).
  const int mid_station = (tube.station_first + tube.station_last) / 2;
  const auto mid = [&](int depth) { return tube.levels[static_cast<std::size_t>(level(depth))].node(mid_station, tube.level_mid); };
  const Real root_to_tip = (mid(tip_depth) - mid(0)).norm();
  auto height = [&](int depth) { return depth >= tip_depth ? 1.0 : (mid(depth) - mid(0)).norm() / root_to_tip; };
  const Level& root = lv[static_cast<std::size_t>(level(0))];
  auto wall_coordinates = [&](const Vec3& node) {
    const Vec3 c = f.plane(node);
    return std::array<Real, 3>{fin.chord_fraction(c[0], c[1]), c[1], c[2] >= 0.0 ? 1.0 : -1.0};
  };
  std::vector<Real> root_shift(around);
  for (std::size_t s = 0; s < around; ++s) {
    const auto [xi, span, side] = wall_coordinates(root.ring.front()[s]);
    root_shift[s] = root_span_shift(f, xi, span, static_cast<int>(side));
  }
  for (int depth = 0; depth <= half; ++depth) {
    const Real weight = turn_weight(depth);
    if (weight == 0.0) continue;
    Level& l = lv[static_cast<std::size_t>(level(depth))];
    const Real fade = 1.0 - revolution::smoothstep(height(depth));
    std::vector<Vec3> slide(around, Vec3::Zero());
    if (depth < tip_depth)
      for (std::size_t s = 0; s < around; ++s) {
        const auto [xi, span, side] = wall_coordinates(l.ring.front()[s]);
        slide[s] = f.surface(xi, span + fade * root_shift[s], static_cast<int>(side)) -
                   f.surface(xi, span, static_cast<int>(side));
      }
    for (int t = 0; t <= n; ++t) {
      const Real w = ring_weight(t);
      if (w == 0.0) continue;
      for (std::size_t s = 0; s < around; ++s) {
        Vec3& node = l.ring[static_cast<std::size_t>(t)][s];
        node = f.turn(node, weight * w * fin.deflection) + w * slide[s];
      }
    }
    for (auto* nodes : {&l.cap_ring, &l.core})
      for (auto& row : *nodes)
        for (Vec3& node : row) node = f.turn(node, weight * fin.deflection);
  }
  // The root level's nodes off the section back onto the sail's side, across its plane;
  // the same correction fades over the span.
  for (int t = 1; t < n; ++t)
    for (std::size_t s = 0; s < around; ++s) {
      const Real miss = f.off_root(lv[static_cast<std::size_t>(level(0))].ring[static_cast<std::size_t>(t)][s]);
      for (int depth = 0; depth < tip_depth; ++depth) {
        Vec3& node = lv[static_cast<std::size_t>(level(depth))].ring[static_cast<std::size_t>(t)][s];
        const Real by = miss * (1.0 - revolution::smoothstep(height(depth)));
        node[1] -= (node[1] > 0.0 ? 1.0 : -1.0) * by;
      }
    }
  // The nodes the rings and the cap share, bit for bit as make_tube_level had them.
  for (int depth = 0; depth <= half; ++depth) {
    Level& l = lv[static_cast<std::size_t>(level(depth))];
    for (int t = 0; t < n; ++t) l.ring[static_cast<std::size_t>(t)].back() = l.ring[static_cast<std::size_t>(t)].front();
    if (l.cap_ring.empty()) continue;
    l.cap_ring.front() = l.ring.front();
    tie_core_to_cap_ring(l);
  }
}

}  // namespace

std::function<Real(Real x, Real r)> patch_azimuth(std::vector<std::vector<Vec3>> nodes, std::function<Real(Real x)> side,
                                                  Real follow, Real plane, Real sign) {
  const int ni = static_cast<int>(nodes.size()) - 1, nk = ni >= 0 ? static_cast<int>(nodes.front().size()) - 1 : -1;
  if (ni < 1 || nk < 1) fail("sail planes' tube: a layer's patch needs at least one cell");
  struct Node {
    Point c;
    Real beyond;  // the node's distance from the plane less `follow` times the side's
  };
  auto grid = std::make_shared<std::vector<std::vector<Node>>>();
  for (const auto& column : nodes) {
    std::vector<Node> col;
    for (const Vec3& p : column) {
      // The distance from the plane: r sin(phi - plane), beyond the side.
      const Point c = chart_of(p);
      const Real across = std::abs(c[1] * std::sin(std::atan2(p[2], p[1]) - plane));
      col.push_back({c, across - follow * side(c[0])});
    }
    grid->push_back(std::move(col));
  }
  return [grid, ni, nk, side, follow, plane, sign](Real x, Real r) -> Real {
    const auto& g = *grid;
    // The column by x along the middle row, the row by r along that column; then Newton
    // on the cell's bilinear map, stepping to the neighbour the solution points to.
    auto locate = [](int n, auto value, Real target) {
      int lo = 0, hi = n;
      while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (value(mid) <= target ? lo : hi) = mid;
      }
      return lo;
    };
    int i = locate(ni, [&](int q) { return g[static_cast<std::size_t>(q)][static_cast<std::size_t>(nk / 2)].c[0]; }, x);
    int k = locate(nk, [&](int q) { return g[static_cast<std::size_t>(i)][static_cast<std::size_t>(q)].c[1]; }, r);
    Real a = 0.5, b = 0.5;
    for (int move = 0; move < ni + nk + 4; ++move) {
      const auto& p00 = g[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
      const auto& p10 = g[static_cast<std::size_t>(i + 1)][static_cast<std::size_t>(k)];
      const auto& p01 = g[static_cast<std::size_t>(i)][static_cast<std::size_t>(k + 1)];
      const auto& p11 = g[static_cast<std::size_t>(i + 1)][static_cast<std::size_t>(k + 1)];
      a = 0.5, b = 0.5;
      for (int it = 0; it < 30; ++it) {
        const Point f = (1 - a) * (1 - b) * p00.c + a * (1 - b) * p10.c + (1 - a) * b * p01.c + a * b * p11.c -
                        Point(x, r);
        const Point da = (1 - b) * (p10.c - p00.c) + b * (p11.c - p01.c);
        const Point db = (1 - a) * (p01.c - p00.c) + a * (p11.c - p10.c);
        const Real det = da[0] * db[1] - da[1] * db[0];
        const Real step_a = (f[0] * db[1] - f[1] * db[0]) / det, step_b = (da[0] * f[1] - da[1] * f[0]) / det;
        a -= step_a, b -= step_b;
        if (std::abs(step_a) + std::abs(step_b) < 1e-15) break;
      }
      // On a cell's edge round-off may put the point either side: a hair outside counts.
      constexpr Real hair = 1e-9;
      const int di = a < -hair && i > 0 ? -1 : a > 1.0 + hair && i + 1 < ni ? 1 : 0;
      const int dk = b < -hair && k > 0 ? -1 : b > 1.0 + hair && k + 1 < nk ? 1 : 0;
      if (di == 0 && dk == 0) {
        const Real beyond = (1 - a) * (1 - b) * p00.beyond + a * (1 - b) * p10.beyond + (1 - a) * b * p01.beyond + a * b * p11.beyond;
        return plane + sign * std::asin((follow * side(x) + beyond) / r);
      }
      i += di, k += dk;
    }
    fail("sail planes' tube: chart point ({:.6g}, {:.6g}) not found on a layer (patch x {:.6g}..{:.6g}, r {:.6g}..{:.6g}; "
         "last cell {} {}, a {:.3g} b {:.3g})",
         x, r, g.front()[static_cast<std::size_t>(nk / 2)].c[0], g.back()[static_cast<std::size_t>(nk / 2)].c[0],
         g[static_cast<std::size_t>(ni / 2)].front().c[1], g[static_cast<std::size_t>(ni / 2)].back().c[1], i, k, a, b);
  };
}

std::vector<Block> make_sail_plane_tube(const SailPlaneTube& tube, const std::string& root) {
  const int last = static_cast<int>(tube.levels.size()) - 1;
  if (tube.planes[0] == nullptr || tube.planes[1] == nullptr || last < 4)
    fail("sail planes' tube: needs its two planes and its levels");
  if (!(0 < tube.tips[0] && tube.tips[0] < tube.tips[1] && tube.tips[1] < last))
    fail("sail planes' tube: the tips ({}, {}) must lie inside its levels 0..{}", tube.tips[0], tube.tips[1], last);
  if (tube.level_mid - tube.level_low != tube.level_high - tube.level_mid)
    fail("sail planes' tube: its front and back are halved at the planes' height: level_mid must be the middle");
  const auto tips = tip_sections(tube);
  std::vector<Level> lv;
  for (int l = 0; l <= last; ++l) lv.push_back(make_tube_level(tube, l, tips));
  for (std::size_t p = 0; p < 2; ++p) {
    try {
      deflect_plane(tube, p, lv);
    } catch (const Error& e) {
      fail("'{}' deflected by {:.4g} degrees: {}", tube.planes[p]->name(), tube.planes[p]->deflection * kDegreesPerRadian,
           e.what());
    }
  }

  std::vector<int> cuts = tube.breaks;
  for (const int c : {0, tube.tips[0], tube.tips[1], last}) cuts.push_back(c);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
  const auto& split = lv.front().split;
  const int half_front = (split[1] - split[0]) / 2;
  const auto parts = ring_parts(split);
  std::vector<Block> blocks;
  for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
    const int a = cuts[c], b = cuts[c + 1];
    const int owner = b <= tube.tips[0] ? 0 : a >= tube.tips[1] ? 1 : -1;
    for (const RingPart& part : parts) {
      Block blk = ring_block(lv, RingOf::O, fmt::format("{}{}_{}", tube.tag, c, part.name), part.s0, part.cells, a, b);
      if (owner >= 0) add_whole_side_patch(blk, 2, tube.planes[static_cast<std::size_t>(owner)]->name());
      if (a == 0) add_whole_side_patch(blk, 4, root);
      if (b == last) add_whole_side_patch(blk, 5, root);
      blocks.push_back(std::move(blk));
    }
    if (owner >= 0) continue;
    // Between the tips: the cap's ring and core, the tips' faces at their ends.
    std::vector<Block> cap;
    for (const RingPart& part : parts)
      cap.push_back(ring_block(lv, RingOf::Cap, fmt::format("{}{}_cap_{}", tube.tag, c, part.name), part.s0,
                               part.cells, a, b));
    for (const bool plus : {false, true})
      cap.push_back(core_block(lv, fmt::format("{}{}_core{}", tube.tag, c, plus ? "p" : "m"), plus ? half_front : 0,
                               half_front, a, b));
    for (Block& blk : cap) {
      if (a == tube.tips[0]) add_whole_side_patch(blk, 4, tube.planes[0]->name());
      if (b == tube.tips[1]) add_whole_side_patch(blk, 5, tube.planes[1]->name());
      blocks.push_back(std::move(blk));
    }
  }
  // A deflection the tube has no room for folds cells whose volume may still be positive.
  if (tube.planes[0]->is_deflected() || tube.planes[1]->is_deflected())
    require_unfolded(measure_folds(blocks), "the deformed sail planes' tube");
  return blocks;
}

}  // namespace narwhal
