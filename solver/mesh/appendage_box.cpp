#include "mesh/appendage_box.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "mesh/grid_quality.hpp"
#include "mesh/level_stack.hpp"
#include "mesh/meridian.hpp"
#include "mesh/turned_fin.hpp"

namespace narwhal {
namespace {

constexpr int kCapRingCells = 8;

using ogrid::Point;
using revolution::kPi;

Real lerp_table(const std::vector<Real>& xs, const std::vector<Real>& ys, Real x) {
  const auto it = std::upper_bound(xs.begin(), xs.end(), x);
  if (it == xs.begin()) return ys.front();
  if (it == xs.end()) return ys.back();
  const std::size_t k = static_cast<std::size_t>(it - xs.begin());
  return ys[k - 1] + (x - xs[k - 1]) / (xs[k] - xs[k - 1]) * (ys[k] - ys[k - 1]);
}

// The angle out of its plane of the appendage's surface at axial position x and radius r
// (feet): the surface point at that radius has span s with s^2 + t(x, s)^2 = r^2.
// The span stays inside the tip: at the tip's radius the edge (s = r, t = 0) solves it
// too, and the level there (the fins' flat tip face, that radius's cylinder) may pass the
// tip's radius by round-off between stations; beyond it the tip section continues.
Real surface_angle(const suboff::Appendage& a, Real x, Real r) {
  const Real inside = a.tip(x) * (1.0 - 1e-12);
  Real s = std::min(r, inside), t = 0.0;
  for (int it = 0; it < 60; ++it) {
    t = a.half_thickness(x, s);
    const Real next = std::min(inside, std::sqrt(std::max(0.0, r * r - t * t)));
    if (std::abs(next - s) < 1e-15 * r) break;
    s = next;
  }
  return std::atan2(t, s);
}

// One level's chart along the station parameter: the arc length sigma of the level
// curve, and the appendage's chord fraction, tabulated (both increase along the box).
struct LevelChart {
  int k = 0;
  std::vector<Real> s, sigma;
  std::vector<Real> chord_s, chord;  // over the planform and a sample either side
  Real to_sigma(Real station) const { return lerp_table(s, sigma, station); }
  Real to_station(Real sig) const { return lerp_table(sigma, s, sig); }
  Real station_at_chord(Real u) const { return lerp_table(chord, chord_s, u); }
};

LevelChart make_chart(const AppendageBox& box, int k) {
  constexpr int kSub = 16;  // samples per station interval
  LevelChart c;
  c.k = k;
  const suboff::Appendage& a = *box.appendage;
  std::vector<Real> u;
  std::array<Real, 2> last{};
  for (std::size_t i = 0; i + 1 < box.stations.size(); ++i)
    for (int q = 0; q < kSub || (q == kSub && i + 2 == box.stations.size()); ++q) {
      const Real s = box.stations[i] + (box.stations[i + 1] - box.stations[i]) * q / kSub;
      const auto p = box.level(s, k);
      c.sigma.push_back(c.s.empty() ? 0.0 : c.sigma.back() + std::hypot(p[0] - last[0], p[1] - last[1]));
      c.s.push_back(s);
      const Real x = p[0] / box.feet, r = p[1] / box.feet;
      u.push_back((x - a.leading_edge(r)) / (a.trailing_edge(r) - a.leading_edge(r)));
      last = p;
    }
  if (k > box.tip_level) return c;
  // The chord fraction locates the section's nodes; it need only rise across the planform.
  const auto first_in = std::find_if(u.begin(), u.end(), [](Real v) { return v >= 0.0; });
  const auto first_out = std::find_if(first_in, u.end(), [](Real v) { return v > 1.0; });
  if (first_in == u.begin() || first_out == u.end())
    fail("appendage box '{}': the box does not reach past the appendage's edges at level {}", a.name(), k);
  const std::size_t i0 = static_cast<std::size_t>(first_in - u.begin()) - 1;
  const std::size_t i1 = static_cast<std::size_t>(first_out - u.begin());
  for (std::size_t i = i0; i <= i1; ++i) {
    if (i > i0 && !(u[i] > u[i - 1]))
      fail("appendage box '{}': the chord fraction does not increase across the planform at level {}", a.name(), k);
    c.chord_s.push_back(c.s[i]);
    c.chord.push_back(u[i]);
  }
  return c;
}

Real chord_fraction_at(const AppendageBox& box, Real station, int k) {
  const auto p = box.level(station, k);
  const suboff::Appendage& a = *box.appendage;
  const Real x = p[0] / box.feet, r = p[1] / box.feet;
  return (x - a.leading_edge(r)) / (a.trailing_edge(r) - a.leading_edge(r));
}

// The station where the level's chord fraction is u, exactly (the table's interpolation
// refined by secant steps): near the sharp trailing edge the table's error alone put
// section nodes past the edge, where the section has no thickness.
Real exact_station(const AppendageBox& box, const LevelChart& c, Real u) {
  Real s0 = c.station_at_chord(u), f0 = chord_fraction_at(box, s0, c.k) - u;
  if (f0 == 0.0) return s0;
  const Real ds = 1e-3 * (c.s.back() - c.s.front()) / static_cast<Real>(c.s.size());
  Real s1 = s0 - ds * (f0 > 0.0 ? 1.0 : -1.0), f1 = chord_fraction_at(box, s1, c.k) - u;
  for (int it = 0; it < 20 && f1 != 0.0 && f1 != f0; ++it) {
    const Real s2 = s1 - f1 * (s1 - s0) / (f1 - f0);
    s0 = s1, f0 = f1;
    s1 = s2, f1 = chord_fraction_at(box, s1, c.k) - u;
    if (std::abs(f1) < 1e-14) break;
  }
  return s1;
}

// A chart point back in space at level k. The chart is a level's (sigma along its curve,
// w = r (phi - plane) with that level's r); above the tip every level uses the tip's,
// so that a node keeps its station and azimuth from level to level and its lines follow
// the wall lines: there the levels lean far over the lines, and nodes drifting along a
// level between levels folded cells.
Vec3 to_space(const AppendageBox& box, const LevelChart& c, int k, const Point& p) {
  const Real station = c.to_station(p[0]);
  const Real phi = box.plane + p[1] / box.level(station, c.k)[1];
  const auto xr = box.level(station, k);
  return {xr[0], xr[1] * std::cos(phi), xr[1] * std::sin(phi)};
}

Point to_chart(const AppendageBox& box, const LevelChart& c, Real station, const Vec3& x) {
  const Real r = box.level(station, c.k)[1];
  return {c.to_sigma(station), r * std::remainder(std::atan2(x[2], x[1]) - box.plane, 2.0 * kPi)};
}

Level make_level(const AppendageBox& box, int k, const LevelChart& tip) {
  const suboff::Appendage& a = *box.appendage;
  const LevelChart chart = k >= tip.k ? tip : make_chart(box, k);
  const std::size_t uk = static_cast<std::size_t>(k);
  // The section: at and below the tip the appendage's own; above it the tip's, along
  // the same wall lines, widening and with growing first spacings as it rises.
  const Real rise = k <= box.tip_level ? 0.0 : [&] {
    const Real mid = 0.5 * (box.stations.front() + box.stations.back());
    const auto p = box.level(mid, k), q = box.level(mid, box.tip_level);
    return std::hypot(p[0] - q[0], p[1] - q[1]);
  }();
  const Real grown = box.cap_growth > 0.0 ? revolution::smoothstep(rise / box.cap_growth) : 0.0;
  auto side = [&](int sign) {
    return [&, sign](Real u) {
      const Real station = exact_station(box, chart, u);
      const auto xr = box.level(station, chart.k);
      const Real angle = surface_angle(a, xr[0] / box.feet, xr[1] / box.feet) * (1.0 + grown);
      return Point(chart.to_sigma(station), sign * xr[1] * angle);
    };
  };
  const ogrid::Section section{side(+1), side(-1)};
  // The box's sides in the chart: the top and bottom along the stations, the front and
  // back at the first and last.
  auto chart_side = [&](const std::vector<Vec3>& nodes, int fixed_station) {
    std::vector<Point> p;
    for (std::size_t q = 0; q < nodes.size(); ++q) {
      const Real station = fixed_station >= 0 ? box.stations[static_cast<std::size_t>(fixed_station)] : box.stations[q];
      p.push_back(to_chart(box, chart, station, nodes[q]));
    }
    return p;
  };
  const int last = static_cast<int>(box.stations.size()) - 1;
  ogrid::Box outline;
  outline.front = chart_side(box.front[uk], 0);
  outline.top = chart_side(box.top[uk], -1);
  outline.back = chart_side(box.back[uk], last);
  outline.bottom = chart_side(box.bottom[uk], -1);
  std::reverse(outline.bottom.begin(), outline.bottom.end());  // listed front to back, run back to front
  // Corners shared bit for bit between consecutive sides.
  outline.top.front() = outline.front.back();
  outline.back.front() = outline.top.back();
  outline.bottom.front() = outline.back.back();
  outline.bottom.back() = outline.front.front();

  ogrid::Spec spec = box.section_grid;
  const auto& chart_top = box.top[static_cast<std::size_t>(chart.k)];
  const Vec3& middle = chart_top[chart_top.size() / 2];
  spec.outer_spacing = std::hypot(middle[1], middle[2]) * box.outer_angle;
  if (box.knot_offset > 0.0) {
    // The chart's w is r times the azimuth from the plane: the offset's at this level's r.
    const Real r = box.level(0.5 * (box.stations.front() + box.stations.back()), chart.k)[1];
    spec.knot_w = r * std::asin(box.knot_offset / r);
  }
  // Far above the tip the lines from the widened outline may be shorter than the box's
  // spacing suggests: no more than a quarter of the mean spacing of the shortest.
  if (grown > 0.0) {
    Real shortest = std::min(section.upper(0.0)[0] - outline.front.front()[0],
                             outline.back.front()[0] - section.upper(1.0)[0]);
    for (const auto* edge : {&outline.top, &outline.bottom})
      for (const Point& p : *edge) shortest = std::min(shortest, std::abs(p[1]));
    const Real cap = 0.25 * std::min(spec.outer_spacing, shortest / spec.cells_normal);
    spec.first_spacing += grown * (std::max(cap, spec.first_spacing) - spec.first_spacing);
  }
  if (grown > 0.0 && spec.knot_ring > 0) {
    // Away above the tip the planes' ring keeps its place but not its clustering.
    spec.knot_spacing += grown * (std::max(0.25 * spec.outer_spacing, spec.knot_spacing) - spec.knot_spacing);
  }
  const ogrid::OGrid o = [&] {
    try {
      return ogrid::make_section_ogrid(section, outline, spec);
    } catch (const Error& e) {
      fail("appendage box '{}', level {}: {}", a.name(), k, e.what());
    }
  }();

  Level lv;
  lv.split = o.split;
  const int n = o.cells_normal(), around = o.cells_around();
  std::vector<Vec3> outer;
  for (const auto* s : {&box.front[uk], &box.top[uk], &box.back[uk]}) outer.insert(outer.end(), s->begin(), s->end() - 1);
  {
    std::vector<Vec3> bottom = box.bottom[uk];
    std::reverse(bottom.begin(), bottom.end());
    outer.insert(outer.end(), bottom.begin(), bottom.end());
  }
  if (static_cast<int>(outer.size()) != around + 1) fail("appendage box '{}': internal: box ring", a.name());
  lv.ring.assign(static_cast<std::size_t>(n + 1), std::vector<Vec3>(static_cast<std::size_t>(around + 1)));
  for (int t = 0; t <= n; ++t)
    for (int s = 0; s <= around; ++s) {
      const std::size_t ut = static_cast<std::size_t>(t), us = static_cast<std::size_t>(s);
      lv.ring[ut][us] = t == n ? outer[us] : to_space(box, chart, k, o.ring[ut][us]);
    }
  for (int t = 0; t < n; ++t) lv.ring[static_cast<std::size_t>(t)].back() = lv.ring[static_cast<std::size_t>(t)].front();
  if (k >= box.tip_level) {
    // Eight cells deep on every grid: three multigrid levels (8 -> 4 -> 2) on each member
    // of a grid family (AppendedSuboffSpec's scale), however few cells its O has.
    const ogrid::SectionCap cap = ogrid::section_cap(o, section, kCapRingCells);
    for (std::size_t t = 0; t < cap.ring.size(); ++t) {
      std::vector<Vec3> r;
      for (const auto& p : cap.ring[t]) r.push_back(to_space(box, chart, k, p));
      lv.cap_ring.push_back(std::move(r));
    }
    lv.cap_ring.front() = lv.ring.front();  // the section's nodes as the O's, bit for bit
    for (const auto& row : cap.core) {
      std::vector<Vec3> r;
      for (const auto& p : row) r.push_back(to_space(box, chart, k, p));
      lv.core.push_back(std::move(r));
    }
    tie_core_to_cap_ring(lv);
  }
  return lv;
}

// ---- A deflected control surface (mesh/DESIGN.md, "Deflected control surfaces") ----
// The box is generated about the undeflected surface, then deformed: every node turns
// about the stock by the deflection times a weight, so that the same map can move the
// surface during a manoeuvre. The weight is 1 on the section, through the O's wall layer
// (its first half, where the lines leave along the normal: the wall cells turn rigidly and
// stay orthogonal) and in the cap; it falls smoothly to 0 at the box, whose nodes (the
// surrounding grid's) stay bit for bit, and over cap_growth above the tip.
//
// Turning about a stock normal to a tapering hull lifts the root off the hull. Each
// section column therefore also slides along the turned surface (at its chord fraction)
// by the span shift that puts its root node back on the hull, fading to nothing at the
// tip; the rest of the root level is put back on the hull radially, that correction
// fading over the span too.

// The node weights: per level, the share of the turn (1 up to the tip level) and the height
// fraction (0 on the hull, 1 at and above the tip) over which the root's corrections fade;
// per O index t, the share of the turn.
struct DeflectionWeights {
  std::vector<Real> turn, height, ring;
};

DeflectionWeights deflection_weights(const AppendageBox& box, int levels, int cells_normal) {
  DeflectionWeights w;
  const Real mid = 0.5 * (box.stations.front() + box.stations.back());
  const auto hull = box.level(mid, 0), tip = box.level(mid, box.tip_level);
  const Real span = std::hypot(tip[0] - hull[0], tip[1] - hull[1]);
  for (int k = 0; k <= levels; ++k) {
    const auto p = box.level(mid, k);
    if (k <= box.tip_level) {
      w.turn.push_back(1.0);
      w.height.push_back(k == box.tip_level ? 1.0 : std::hypot(p[0] - hull[0], p[1] - hull[1]) / span);
    } else {
      const Real rise = std::hypot(p[0] - tip[0], p[1] - tip[1]);
      w.turn.push_back(1.0 - revolution::smoothstep(rise / box.cap_growth));
      w.height.push_back(1.0);
    }
  }
  const int layer = cells_normal / 2;
  for (int t = 0; t <= cells_normal; ++t)
    w.ring.push_back(t <= layer ? 1.0 : 1.0 - revolution::smoothstep(static_cast<Real>(t - layer) / (cells_normal - layer)));
  return w;
}

void deflect_levels(const AppendageBox& box, std::vector<Level>& lv) {
  const suboff::Appendage& a = *box.appendage;
  if (!a.is_deflected()) return;
  const auto* fin = dynamic_cast<const suboff::Fin*>(&a);
  if (fin == nullptr || fin->shape().on_sail)
    fail("appendage box '{}': only control surfaces standing on the hull can be deflected", a.name());
  if (!(box.cap_growth > 0.0))
    fail("appendage box '{}': a deflection needs cap_growth > 0 (the height over which the turn fades)", a.name());
  const Real feet = box.feet;
  // Off the hull: radially.
  const TurnedFin f{*fin, feet, [feet](const Vec3& node) {
                      return std::hypot(node[1], node[2]) - suboff::hull_radius(node[0] / feet) * feet;
                    }};
  const int levels = static_cast<int>(lv.size()) - 1;
  const int n = static_cast<int>(lv.front().ring.size()) - 1;
  const std::size_t around = lv.front().ring.front().size();
  const DeflectionWeights w = deflection_weights(box, levels, n);

  // Each section column's root shift along the turned surface, from its hull node.
  std::vector<Real> root_shift(around);
  auto wall_coordinates = [&](const Vec3& node) {
    const Vec3 c = f.plane(node);
    return std::array<Real, 3>{fin->chord_fraction(c[0], c[1]), c[1], c[2] >= 0.0 ? 1.0 : -1.0};
  };
  for (std::size_t s = 0; s < around; ++s) {
    const auto [xi, span, side] = wall_coordinates(lv.front().ring.front()[s]);
    root_shift[s] = root_span_shift(f, xi, span, static_cast<int>(side));
  }
  // The turn, and below the tip each column's slide along the surface.
  for (int k = 0; k <= levels; ++k) {
    Level& l = lv[static_cast<std::size_t>(k)];
    const Real fade = 1.0 - revolution::smoothstep(w.height[static_cast<std::size_t>(k)]);
    std::vector<Vec3> slide(around, Vec3::Zero());
    if (k < box.tip_level)
      for (std::size_t s = 0; s < around; ++s) {
        const auto [xi, span, side] = wall_coordinates(l.ring.front()[s]);
        slide[s] = f.surface(xi, span + fade * root_shift[s], static_cast<int>(side)) -
                   f.surface(xi, span, static_cast<int>(side));
      }
    for (int t = 0; t <= n; ++t) {
      const Real weight = w.ring[static_cast<std::size_t>(t)] * w.turn[static_cast<std::size_t>(k)];
      if (weight == 0.0) continue;
      for (std::size_t s = 0; s < around; ++s) {
        Vec3& node = l.ring[static_cast<std::size_t>(t)][s];
        node = f.turn(node, weight * a.deflection) + w.ring[static_cast<std::size_t>(t)] * slide[s];
      }
    }
    for (auto* nodes : {&l.cap_ring, &l.core})
      for (auto& row : *nodes)
        for (Vec3& node : row) node = f.turn(node, w.turn[static_cast<std::size_t>(k)] * a.deflection);
  }
  // The root level's nodes off the section back on the hull, radially; the same
  // correction fades over the span.
  for (int t = 1; t < n; ++t)
    for (std::size_t s = 0; s < around; ++s) {
      const Real miss = f.off_root(lv.front().ring[static_cast<std::size_t>(t)][s]);
      for (int k = 0; k < box.tip_level; ++k) {
        Vec3& node = lv[static_cast<std::size_t>(k)].ring[static_cast<std::size_t>(t)][s];
        const Real r = std::hypot(node[1], node[2]);
        const Real to = r - miss * (1.0 - revolution::smoothstep(w.height[static_cast<std::size_t>(k)]));
        node[1] *= to / r;
        node[2] *= to / r;
      }
    }
  // The nodes the rings and the cap share, bit for bit as make_level had them.
  for (Level& l : lv) {
    for (int t = 0; t < n; ++t) l.ring[static_cast<std::size_t>(t)].back() = l.ring[static_cast<std::size_t>(t)].front();
    if (l.cap_ring.empty()) continue;
    l.cap_ring.front() = l.ring.front();
    tie_core_to_cap_ring(l);
  }
}

std::vector<Block> assemble_box_blocks(const AppendageBox& box, const std::vector<Level>& lv, const std::string& name,
                                       const std::string& tag);

}  // namespace

std::vector<Block> make_appendage_box(const AppendageBox& box, const std::string& name, const std::string& tag,
                                      std::vector<Level>* levels_out) {
  const int levels = static_cast<int>(box.top.size()) - 1;
  if (box.appendage == nullptr || levels < 1 || box.tip_level < 1 || box.tip_level >= levels)
    fail("appendage box '{}': needs the appendage and a tip level inside the levels", name);
  if (box.front.size() != box.top.size() || box.back.size() != box.top.size() || box.bottom.size() != box.top.size())
    fail("appendage box '{}': its four sides need every level", name);
  if (box.top.front().size() != box.stations.size())
    fail("appendage box '{}': {} top nodes but {} stations", name, box.top.front().size(), box.stations.size());
  const LevelChart tip = make_chart(box, box.tip_level);
  std::vector<Level> lv;
  for (int k = 0; k <= levels; ++k) lv.push_back(make_level(box, k, tip));
  // The sail's cap: the tip face raised onto its crest (all but the section's own nodes,
  // which are the crest's foot), fading over three crest heights above it so that the
  // levels stay in order.
  if (box.crest) {
    const Level base = lv[static_cast<std::size_t>(box.tip_level)];
    auto crest_at = [&](const Vec3& p) {
      return box.crest(p[0], std::hypot(p[1], p[2]) * std::remainder(std::atan2(p[2], p[1]) - box.plane, 2.0 * kPi));
    };
    Real highest = 0.0;
    for (const auto& row : base.core)
      for (const Vec3& p : row) highest = std::max(highest, crest_at(p));
    auto lift = [&](const Vec3& p0, Vec3& p) {
      const Real r0 = std::hypot(p0[1], p0[2]), r = std::hypot(p[1], p[2]);
      const Real by = crest_at(p0) * (1.0 - revolution::smoothstep((r - r0) / (3.0 * highest)));
      p[1] *= (r + by) / r;
      p[2] *= (r + by) / r;
    };
    for (int k = box.tip_level; k <= levels && highest > 0.0; ++k) {
      Level& l = lv[static_cast<std::size_t>(k)];
      for (std::size_t t = 1; t < l.cap_ring.size(); ++t)
        for (std::size_t q = 0; q < l.cap_ring[t].size(); ++q) lift(base.cap_ring[t][q], l.cap_ring[t][q]);
      for (std::size_t a = 0; a < l.core.size(); ++a)
        for (std::size_t b = 0; b < l.core[a].size(); ++b) lift(base.core[a][b], l.core[a][b]);
    }
  }
  if (box.appendage->is_deflected()) {
    const std::string turned =
        fmt::format("appendage box '{}' deflected by {:.4g} degrees", name, box.appendage->deflection * kDegreesPerRadian);
    // A deflection the box has no room for folds blocks: say so, with the deflection.
    try {
      deflect_levels(box, lv);
      if (levels_out != nullptr) *levels_out = lv;
      return assemble_box_blocks(box, lv, name, tag);
    } catch (const Error& e) {
      fail("{}: {}", turned, e.what());
    }
  }
  if (levels_out != nullptr) *levels_out = lv;
  return assemble_box_blocks(box, lv, name, tag);
}

namespace {

// The box's blocks from its levels: the O's six parts from the hull to the tip and from the
// tip to the far field, the cap's ring in the same six parts and its core in two halves.
std::vector<Block> assemble_box_blocks(const AppendageBox& box, const std::vector<Level>& lv, const std::string& name,
                                       const std::string& tag) {
  const int levels = static_cast<int>(lv.size()) - 1;
  const auto& split = lv.front().split;
  const int half_front = (split[1] - split[0]) / 2;
  const auto parts = ring_parts(split);
  std::vector<Block> blocks;
  for (const RingPart& part : parts)
    for (const bool inner : {true, false}) {
      const int k0 = inner ? 0 : box.tip_level, k1 = inner ? box.tip_level : levels;
      Block b = ring_block(lv, RingOf::O, fmt::format("{}_{}_{}", tag, part.name, inner ? "inner" : "outer"), part.s0,
                           part.cells, k0, k1);
      if (inner) {
        add_whole_side_patch(b, 2, name);    // the appendage's side
        add_whole_side_patch(b, 4, "body");  // the hull
      } else {
        add_whole_side_patch(b, 5, "farfield");
      }
      blocks.push_back(std::move(b));
    }
  // The cap over the tip: its ring in the O's six parts, its core halved along the mean
  // line to meet the ring's halved front and back.
  for (const RingPart& part : parts) {
    Block b = ring_block(lv, RingOf::Cap, fmt::format("{}_cap_{}", tag, part.name), part.s0, part.cells, box.tip_level,
                         levels);
    add_whole_side_patch(b, 4, name);  // the tip
    add_whole_side_patch(b, 5, "farfield");
    blocks.push_back(std::move(b));
  }
  for (const bool plus : {false, true}) {
    Block b = core_block(lv, fmt::format("{}_cap_core{}", tag, plus ? "p" : "m"), plus ? half_front : 0,
                         half_front, box.tip_level, levels);
    add_whole_side_patch(b, 4, name);
    add_whole_side_patch(b, 5, "farfield");
    blocks.push_back(std::move(b));
  }
  // A deflection the box has no room for folds cells whose volume may still be positive:
  // the scaled corner Jacobian finds them.
  if (box.appendage->is_deflected()) require_unfolded(measure_folds(blocks), "the deformed box");
  return blocks;
}

}  // namespace

}  // namespace narwhal
