#include "mesh/appended_suboff.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "mesh/appendage_box.hpp"
#include "mesh/generators.hpp"
#include "mesh/meridian.hpp"
#include "mesh/sail_plane_tube.hpp"

namespace narwhal {
namespace {

using namespace revolution;

// The arc length from the nose of the hull's meridian point at axial position x.
Real arc_length_at(const Meridian& m, Real x) {
  Real lo = 0.0, hi = m.length();
  for (int it = 0; it < 100; ++it) {
    const Real mid = 0.5 * (lo + hi);
    (m.at(mid)[0] < x ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// A wall line leaving the hull at station i: along the appendages' direction u (in the
// meridional plane, fin_weight 1 in a window, fading outside) up to the tip level, then
// turning to the extrusion's direction over `release`.
struct WallLine {
  bool near_sail = false;  // the window it follows: the sail's or the stern appendages'
  Real fin_weight = 0.0;
  Real ux = 0.0, ur = 1.0;
  Real d_tip = 0.0;
  Real release = 1.0;
};

Vec3 line_node(const Extrusion& ex, const SurfacePoint& p, const WallLine& w, Real d) {
  const Vec3 e = ex.direction(p, d);
  if (w.fin_weight == 0.0) return p.x + d * e;
  const Real weight = w.fin_weight * (1.0 - smoothstep((d - w.d_tip) / w.release));
  const Vec3 u(w.ux, w.ur * p.dir[0], w.ur * p.dir[1]);
  return p.x + d * ((1.0 - weight) * e + weight * u).normalized();
}

// The stations along the sector boundaries' meridian (arc lengths), the index ranges of
// the two windows, and each station's wall line.
struct Stations {
  std::vector<Real> s;
  int sail_first = 0, sail_last = 0, fin_first = 0, fin_last = 0;
  std::vector<WallLine> lines;
};

std::vector<Real> joined(std::vector<Real> a, const std::vector<Real>& b) {
  a.insert(a.end(), b.begin() + 1, b.end());
  return a;
}

Stations make_stations(const AppendedSuboffSpec& spec, const Meridian& m, Real rho, Real ft) {
  const Real S = m.length();
  Stations st;
  // The sail's window: stations at x, lines straight up (its sections do not change with height).
  // At least 0.9 of the chord's mean spacing at the appendages' edges (here and for the
  // fins below): the stations carry the boxes' sides and margins, and a box front much
  // wider than deep (the margin's stations clustered at the edge) had concave cells.
  const Real sail_mean = (suboff::Sail::kTrailingEdge - suboff::Sail::kLeadingEdge) / spec.cells_sail;
  const std::vector<Real> x_sail = two_sided_nodes(suboff::Sail::kLeadingEdge, suboff::Sail::kTrailingEdge,
                                                   spec.cells_sail, std::max(spec.leading_edge_spacing / ft, 0.9 * sail_mean),
                                                   std::max(spec.trailing_edge_spacing / ft, 0.9 * sail_mean));
  std::vector<Real> s_sail;
  std::vector<WallLine> sail_lines;
  for (const Real x : x_sail) {
    s_sail.push_back(arc_length_at(m, x * ft));
    // The tip level at the top of the sail's uniform section; its cap is the cap block's.
    sail_lines.push_back({true, 1.0, 0.0, 1.0, (suboff::Sail::kUniformTop - suboff::hull_radius(x)) * ft, 0.0});
  }
  // The stern appendages' window: lines of constant chord fraction xi, x = x_te - c(r) (1 - xi).
  const auto fin = suboff::make_stern_appendage(suboff::SternAppendage::UpperRudder);
  const auto& shape = fin->shape();
  const Real mean_chord = fin->chord(0.5 * (0.4 + shape.tip_span));
  const std::vector<Real> xi = two_sided_nodes(0.0, 1.0, spec.cells_fin,
                                               std::max(spec.leading_edge_spacing / (ft * mean_chord), 0.9 / spec.cells_fin),
                                               std::max(spec.trailing_edge_spacing / (ft * mean_chord), 0.9 / spec.cells_fin));
  std::vector<Real> s_fin;
  std::vector<WallLine> fin_lines;
  for (const Real f : xi) {
    // The line's foot on the hull: x - x_te + c(R(x)) (1 - xi) = 0 (monotone in x).
    Real lo = shape.trailing_edge_x - 1.5, hi = shape.trailing_edge_x;
    for (int it = 0; it < 100; ++it) {
      const Real mid = 0.5 * (lo + hi);
      (mid - shape.trailing_edge_x + fin->chord(suboff::hull_radius(mid)) * (1.0 - f) < 0.0 ? lo : hi) = mid;
    }
    const Real x_root = 0.5 * (lo + hi);
    const Real slope = -shape.chord_slope * (1.0 - f);  // dx/dr along the line
    const Real norm = std::hypot(slope, 1.0);
    s_fin.push_back(arc_length_at(m, x_root * ft));
    fin_lines.push_back(
        {false, 1.0, slope / norm, 1.0 / norm, (shape.tip_span - suboff::hull_radius(x_root)) * ft * norm, 0.0});
  }
  if (!(s_sail.back() < s_fin.front())) fail("appended SUBOFF grid: the sail's window overlaps the stern's");

  // The stretches between the windows, their end spacings matched to the windows'.
  const Real pole_ds = spec.pole_spacing;
  const auto bow = two_sided_nodes(rho, s_sail.front(), spec.cells_bow, pole_ds, s_sail[1] - s_sail[0]);
  const auto middle = two_sided_nodes(s_sail.back(), s_fin.front(), spec.cells_middle,
                                      s_sail.back() - s_sail[s_sail.size() - 2], s_fin[1] - s_fin[0]);
  const auto stern = two_sided_nodes(s_fin.back(), S - rho, spec.cells_stern, s_fin.back() - s_fin[s_fin.size() - 2],
                                     pole_ds);
  st.s = joined(joined(joined(joined(bow, s_sail), middle), s_fin), stern);
  st.sail_first = spec.cells_bow;
  st.sail_last = st.sail_first + spec.cells_sail;
  st.fin_first = st.sail_last + spec.cells_middle;
  st.fin_last = st.fin_first + spec.cells_fin;

  // Each station's line. Outside the windows the appendages' direction fades over one
  // chord, and the tip level follows the nearer window's (blended across the middle).
  const int nl = static_cast<int>(st.s.size()) - 1;
  st.lines.resize(st.s.size());
  const Real sail_reach = (suboff::Sail::kTrailingEdge - suboff::Sail::kLeadingEdge) * ft;
  const Real fin_reach = 0.4 * ft;  // clear of the tail's pole stretch (pole_shift)
  for (int i = 0; i <= nl; ++i) {
    const Real s = st.s[static_cast<std::size_t>(i)];
    WallLine w;
    if (i >= st.sail_first && i <= st.sail_last) {
      w = sail_lines[static_cast<std::size_t>(i - st.sail_first)];
    } else if (i >= st.fin_first && i <= st.fin_last) {
      w = fin_lines[static_cast<std::size_t>(i - st.fin_first)];
    } else if (i < st.sail_first) {
      w = sail_lines.front();
      w.fin_weight = 1.0 - smoothstep((s_sail.front() - s) / sail_reach);
    } else if (i > st.fin_last) {
      w = fin_lines.back();
      w.fin_weight = 1.0 - smoothstep((s - s_fin.back()) / fin_reach);
    } else {
      const Real after_sail = s - s_sail.back(), before_fin = s_fin.front() - s;
      w = after_sail < before_fin ? sail_lines.back() : fin_lines.front();
      w.fin_weight = 1.0 - smoothstep(std::min(after_sail / sail_reach, before_fin / fin_reach));
      const Real blend = smoothstep(after_sail / (after_sail + before_fin));
      w.d_tip = (1.0 - blend) * sail_lines.back().d_tip + blend * fin_lines.front().d_tip;
    }
    w.release = w.d_tip;
    st.lines[static_cast<std::size_t>(i)] = w;
  }
  return st;
}

// Distances along a wall line: clustered at the hull and at the tip level (k = cells_span).
std::vector<Real> line_distances(const AppendedSuboffSpec& spec, Real d_tip) {
  return joined(two_sided_nodes(0.0, d_tip, spec.cells_span, spec.first_spacing, spec.tip_spacing),
                geometric_nodes(d_tip, spec.far_field * spec.length, spec.cells_outer, spec.tip_spacing));
}

void add_hull_patches(Block& b) {
  for (const int side : {4, 5}) {
    Patch p;
    p.side = side;
    p.lo = {0, 0, 0};
    p.hi = b.dims();
    p.label = side == 5 ? "farfield" : "body";
    b.patches.push_back(p);
  }
}

// Everything the blocks are built from: the hull's meridian, the stations and their
// wall lines, the azimuths, and each line's distances. Built once, in place (the
// extrusion keeps a reference to the meridian).
struct Layout {
  const AppendedSuboffSpec& spec;
  Real ft;
  Meridian meridian;
  Real S, rho;  // the meridian's length; the pole squares' half-diagonal
  Stations st;
  int nl, nk;
  Azimuth az;
  Extrusion extrusion;
  std::vector<std::vector<Real>> distances;  // per station, along its wall line

  explicit Layout(const AppendedSuboffSpec& s);
  // Near the poles the stations of an off-boundary meridian shift with its square edge
  // (re, not rho), as in body_of_revolution.cpp; elsewhere every meridian has the boundary's.
  Real pole_shift(Real arc) const {
    const Real f = (arc - rho) / (S - 2.0 * rho), reach = 0.03;
    if (f < reach) return std::pow(1.0 - f / reach, 2);
    if (f > 1.0 - reach) return -std::pow(1.0 - (1.0 - f) / reach, 2);
    return 0.0;
  }
  Vec3 node(const SurfacePoint& p, std::size_t i, int k) const {
    return line_node(extrusion, p, st.lines[i], distances[i][static_cast<std::size_t>(k)]);
  }
  // The wall lines as a continuous family between the stations (each line's parameters
  // and distances interpolated in its foot's arc length): (x, r) of the line from `arc`
  // at level k, the station's node at a station and a hull point at level 0. The
  // appendages' boxes build their O-grids on these levels.
  std::array<Real, 2> level(Real arc, int k) const {
    const auto it = std::upper_bound(st.s.begin(), st.s.end(), arc);
    const std::size_t i = std::clamp<std::size_t>(static_cast<std::size_t>(it - st.s.begin()), 1, st.s.size() - 1) - 1;
    const Real f = (arc - st.s[i]) / (st.s[i + 1] - st.s[i]);
    const WallLine &a = st.lines[i], &b = st.lines[i + 1];
    auto mix = [f](Real u, Real v) { return f == 0.0 ? u : (1.0 - f) * u + f * v; };
    const WallLine w{a.near_sail, mix(a.fin_weight, b.fin_weight), mix(a.ux, b.ux), mix(a.ur, b.ur),
                     mix(a.d_tip, b.d_tip), mix(a.release, b.release)};
    const std::size_t uk = static_cast<std::size_t>(k);
    const Vec3 x = line_node(extrusion, surface(meridian, arc, {1.0, 0.0}), w, mix(distances[i][uk], distances[i + 1][uk]));
    return {x[0], std::hypot(x[1], x[2])};
  }
};

BodyGridSpec far_field_extrusion(const AppendedSuboffSpec& spec) {
  BodyGridSpec es;
  es.far_field = spec.far_field;
  es.cells_normal = 1;
  es.first_spacing = spec.far_field * spec.length;
  return es;
}

// Azimuths uniform, as the bare grids': the appendages' clustering is their boxes'.
Layout::Layout(const AppendedSuboffSpec& s)
    : spec(s),
      ft(s.length / suboff::kOverallLength),
      meridian(suboff_profile(s.length)),
      S(meridian.length()),
      rho(s.cells_around * s.pole_spacing / std::sqrt(2.0)),
      st(make_stations(s, meridian, rho, ft)),
      nl(static_cast<int>(st.s.size()) - 1),
      nk(s.cells_span + s.cells_outer),
      az{s.cells_around},
      extrusion(far_field_extrusion(s), meridian, s.length) {
  for (std::size_t i = 0; i < st.s.size(); ++i)
    if (pole_shift(st.s[i]) != 0.0 && st.lines[i].fin_weight != 0.0)
      fail("appended SUBOFF grid: station {} follows an appendage inside a pole stretch; use a smaller pole spacing", i);
  for (const auto& w : st.lines) distances.push_back(line_distances(spec, w.d_tip));
}

// One sector's block, 90 degrees from sector * 90 (j = 0 at the larger azimuth), no
// appendage yet.
Block make_sector_block(const Layout& lay, int sector) {
  const int na = lay.spec.cells_around;
  Block b(fmt::format("sector_{}", sector * 90), lay.nl, na, lay.nk);
  for (int i = 0; i <= lay.nl; ++i) {
    const std::size_t ui = static_cast<std::size_t>(i);
    const Real arc = lay.st.s[ui];
    if (i == 0 || i == lay.nl || lay.pole_shift(arc) != 0.0) {
      // Near the poles: each meridian's own stations, uniform azimuths, as the squares.
      for (int j = 0; j <= na; ++j) {
        const int ma = (sector + 1) * na - j;
        const auto end = diamond(lay.rho, lay.az, ma);
        const Real re = std::hypot(end[0], end[1]);
        const SurfacePoint p = i == 0 || i == lay.nl
                                   ? near_pole(lay.meridian, end, i == lay.nl)
                                   : surface(lay.meridian, arc + (re - lay.rho) * lay.pole_shift(arc), lay.az.unit(ma));
        for (int k = 0; k <= lay.nk; ++k) b.x(i, j, k) = lay.node(p, ui, k);
      }
      continue;
    }
    // Elsewhere every meridian has the same line: place its nodes at each one's azimuth.
    const SurfacePoint p = surface(lay.meridian, arc, {1.0, 0.0});
    for (int k = 0; k <= lay.nk; ++k) {
      const Vec3 xr = lay.node(p, ui, k);
      for (int j = 0; j <= na; ++j) {
        // Exact axes at the boundaries: shared bit for bit with the neighbour.
        const auto [c, sn] = lay.az.unit((sector + 1) * na - j);
        b.x(i, j, k) = Vec3(xr[0], xr[1] * c, xr[1] * sn);
      }
    }
  }
  add_hull_patches(b);
  return b;
}

bool is_sail_plane(const suboff::Appendage& a) {
  const auto* fin = dynamic_cast<const suboff::Fin*>(&a);
  return fin != nullptr && fin->shape().on_sail;
}

// The plane an appendage stands in: the sector boundary at q * 90 degrees.
int plane_of(const suboff::Appendage& a) {
  const Vec3 span = suboff::to_grid_axes(a.span_direction);
  return (static_cast<int>(std::lround(std::atan2(span[2], span[1]) / (0.5 * kPi))) + 4) % 4;
}

// The stations an appendage's box spans: its chord's window and cells_margin either side.
std::array<int, 2> box_stations(const Layout& lay, bool sail) {
  const int m = lay.spec.cells_margin;
  return sail ? std::array<int, 2>{lay.st.sail_first - m, lay.st.sail_last + m}
              : std::array<int, 2>{lay.st.fin_first - m, lay.st.fin_last + m};
}

// An appendage's box: box_half_width sector cells either side of its plane over its
// stations, all levels (mesh/appendage_box.hpp). Sector q has the plane at j = na (its
// columns na - w .. na are the +w side), sector q - 1 at j = 0.
// The sail's O with the sail planes (`full`): beyond its wall layer (cells_section / 2
// cells, as without them) as many cells again up to the ring at the planes' tips, clustered
// there at the tip spacing, and cells_section more out to the box; counts that keep the
// tube's pieces in fours.
struct SailPlaneRings {
  int cells_normal = 0, cells_layer = 0, knot_ring = 0;
};
SailPlaneRings sail_plane_rings(int cells_section) {
  SailPlaneRings r;
  r.cells_layer = cells_section / 2;
  int to_knot = cells_section;
  while ((r.cells_layer + to_knot) % 4 != 0) ++to_knot;
  r.knot_ring = r.cells_layer + to_knot;
  r.cells_normal = r.knot_ring + cells_section;
  return r;
}

std::vector<Block> make_box(const std::vector<Block>& sectors, const Layout& lay, const suboff::Appendage& a,
                            std::vector<Level>* levels = nullptr, bool sail_planes = false) {
  const int na = lay.spec.cells_around, w = lay.spec.box_half_width, q = plane_of(a);
  const Block& plus = sectors[static_cast<std::size_t>(q)];
  const Block& minus = sectors[static_cast<std::size_t>((q + 3) % 4)];
  const auto [first, last] = box_stations(lay, a.name() == "sail");
  AppendageBox box;
  box.appendage = &a;
  box.feet = lay.ft;
  box.plane = q * 0.5 * kPi;
  box.outer_angle = 0.5 * kPi / na;
  for (int k = 0; k <= lay.nk; ++k) {
    std::vector<Vec3> front, top, back, bottom;
    for (int j = w; j >= 0; --j) front.push_back(minus.x(first, j, k));
    for (int j = na - 1; j >= na - w; --j) front.push_back(plus.x(first, j, k));
    for (int i = first; i <= last; ++i) top.push_back(plus.x(i, na - w, k));
    for (int j = na - w; j <= na; ++j) back.push_back(plus.x(last, j, k));
    for (int j = 1; j <= w; ++j) back.push_back(minus.x(last, j, k));
    for (int i = first; i <= last; ++i) bottom.push_back(minus.x(i, w, k));
    box.front.push_back(std::move(front));
    box.top.push_back(std::move(top));
    box.back.push_back(std::move(back));
    box.bottom.push_back(std::move(bottom));
  }
  box.stations.assign(lay.st.s.begin() + first, lay.st.s.begin() + last + 1);
  box.level = [&lay](Real arc, int k) { return lay.level(arc, k); };
  box.tip_level = lay.spec.cells_span;
  box.section_grid.cells_normal = lay.spec.cells_section;
  box.section_grid.first_spacing = lay.spec.fin_spacing;
  box.section_grid.layer = lay.spec.section_layer;
  box.section_grid.leading_edge_spacing = lay.spec.section_edge_spacing;
  box.section_grid.trailing_edge_spacing = lay.spec.section_edge_spacing;
  box.cap_growth = lay.spec.cap_growth;
  if (sail_planes) {
    const SailPlaneRings rings = sail_plane_rings(lay.spec.cells_section);
    box.section_grid.cells_normal = rings.cells_normal;
    box.section_grid.cells_layer = rings.cells_layer;
    box.section_grid.knot_ring = rings.knot_ring;
    box.section_grid.knot_spacing = lay.spec.tip_spacing;
    box.knot_offset = suboff::SailPlaneDesign::kTipSpan * lay.ft;
  }
  if (a.name() == "sail") {
    // The report's cap over the uniform section (§3): 2 (y - top) = sqrt(Z1^2 - z^2).
    const Real ft = lay.ft;
    box.crest = [ft](Real x, Real w_off) {
      const Real z1 = suboff::Sail::section_half_thickness(x / ft), z = w_off / ft;
      return std::abs(z) >= z1 ? 0.0 : 0.5 * std::sqrt(z1 * z1 - z * z) * ft;
    };
  }
  // Short tags for the blocks' names (CGNS zone names have at most 32 characters).
  static const std::map<std::string, std::string> tags{{"sail", "sail"},
                                                       {"upper_rudder", "rud_up"},
                                                       {"lower_rudder", "rud_lo"},
                                                       {"starboard_stern_plane", "plane_sb"},
                                                       {"port_stern_plane", "plane_pt"}};
  const auto tag = tags.find(a.name());
  return make_appendage_box(box, a.name(), tag == tags.end() ? a.name() : tag->second, levels);
}

// The pole squares, as in body_of_revolution.cpp, with their meridians' lines.
Block make_pole_block(const Layout& lay, bool tail) {
  const std::size_t line = tail ? static_cast<std::size_t>(lay.nl) : 0;
  Block b = make_pole_square(lay.meridian, lay.az, lay.rho, lay.nk, tail,
                             [&](const SurfacePoint& p, int k) { return lay.node(p, line, k); });
  add_hull_patches(b);
  return b;
}

// Cut the sectors at the boxes' edges (along the hull and across each sector, so that
// every face is whole) and at the tip level, the squares with them, and leave out the
// pieces a box replaces.
// The sail planes' tube (the `full` configuration): its stations and levels, which every
// sector piece is cut at too, and which pieces it replaces.
struct TubeCuts {
  int station_first = 0, station_last = 0, level_low = 0, level_mid = 0, level_high = 0;
  bool active() const { return station_last > station_first; }
};

Grid cut_around_boxes(const std::vector<Block>& blocks, const Layout& lay, const suboff::Configuration& config,
                      const TubeCuts& tube = {}) {
  static constexpr const char* stretch[] = {"bow", "sail", "middle", "fin", "stern"};
  static constexpr const char* across[] = {"low", "mid", "high"};
  const int na = lay.spec.cells_around, w = lay.spec.box_half_width;
  const auto sail = box_stations(lay, true), fin = box_stations(lay, false);
  std::vector<int> i_cuts{0, sail[0], sail[1], fin[0], fin[1], lay.nl};
  const std::vector<int> j_cuts{0, w, na - w, na};
  std::vector<int> k_cuts{0, lay.spec.cells_span, lay.nk};
  if (tube.active()) {
    // Named by index beyond the stretches' names: the other configurations keep theirs.
    i_cuts = {0, sail[0], tube.station_first, tube.station_last, sail[1], fin[0], fin[1], lay.nl};
    k_cuts = {0, tube.level_low, tube.level_mid, tube.level_high, lay.spec.cells_span, lay.nk};
  }
  auto boxed = [&](int sector, std::size_t a, std::size_t c) {
    for (const auto& ap : config.appendages) {
      if (is_sail_plane(*ap)) continue;  // in the tube, not a box
      const int q = plane_of(*ap);
      const std::size_t in_stretch = ap->name() == "sail" ? 1 : 3;
      if (a == in_stretch && ((sector == q && c == 2) || (sector == (q + 3) % 4 && c == 0))) return true;
    }
    return false;
  };
  // The stretch of an i piece, in the five stretches' numbering (the tube's pieces of the
  // sail's stretch count as the sail's).
  auto stretch_of = [&](std::size_t a) -> std::size_t {
    if (!tube.active()) return a;
    return a <= 0 ? 0 : a <= 3 ? 1 : a - 2;
  };
  auto in_tube = [&](std::size_t a, std::size_t e) {
    return tube.active() && (a == 2) && (e == 1 || e == 2);
  };
  Grid cut;
  for (const Block& b : blocks) {
    const bool square = b.name == "nose" || b.name == "tail";
    const std::vector<int> ic = square ? j_cuts : i_cuts;
    const int sector = square ? -1 : std::stoi(b.name.substr(b.name.find('_') + 1)) / 90;
    for (std::size_t a = 0; a + 1 < ic.size(); ++a)
      for (std::size_t c = 0; c + 1 < j_cuts.size(); ++c)
        for (std::size_t e = 0; e + 1 < k_cuts.size(); ++e) {
          if (!square && boxed(sector, stretch_of(a), c)) continue;
          if (!square && in_tube(a, e)) continue;
          // Boxes as wide as half a sector leave no middle piece.
          if (j_cuts[c + 1] == j_cuts[c] || (square && ic[a + 1] == ic[a])) continue;
          const std::string level = tube.active() ? fmt::format("k{}", e) : e == 0 ? "inner" : "outer";
          const std::string along = tube.active() && !square ? fmt::format("{}{}", stretch[stretch_of(a)], a)
                                                            : std::string(square ? "" : stretch[a]);
          const std::string name = square ? fmt::format("{}_{}{}_{}", b.name, a, c, level)
                                          : fmt::format("{}_{}_{}_{}", b.name, along, across[c], level);
          cut.blocks.push_back(
              extract_block(b, name, {ic[a], j_cuts[c], k_cuts[e]}, {ic[a + 1], j_cuts[c + 1], k_cuts[e + 1]}));
        }
  }
  return cut;
}

// ---- The sail planes' tube (mesh/sail_plane_tube.hpp; mesh/DESIGN.md, "Sail planes") ----

// The pieces of a block between consecutive index planes in each direction (each list
// from 0 to the block's size), but those `drop` says the tube replaces; one piece keeps
// the block's name.
void cut_block(const Block& b, std::vector<int> ic, std::vector<int> jc, std::vector<int> kc,
               const std::function<bool(const Index3& lo, const Index3& hi)>& drop, Grid& out) {
  for (auto* c : {&ic, &jc, &kc}) {
    std::sort(c->begin(), c->end());
    c->erase(std::unique(c->begin(), c->end()), c->end());
  }
  const bool whole = ic.size() == 2 && jc.size() == 2 && kc.size() == 2;
  for (std::size_t a = 0; a + 1 < ic.size(); ++a)
    for (std::size_t c = 0; c + 1 < jc.size(); ++c)
      for (std::size_t e = 0; e + 1 < kc.size(); ++e) {
        const Index3 lo{ic[a], jc[c], kc[e]}, hi{ic[a + 1], jc[c + 1], kc[e + 1]};
        if (drop(lo, hi)) continue;
        out.blocks.push_back(extract_block(b, whole ? b.name : fmt::format("{}_{}{}{}", b.name, a, c, e), lo, hi));
      }
}

// The i index of a block's node equal to p at (j, k) (the blocks of an O may run either way
// along the ring).
int local_i(const Block& b, int j, int k, const Vec3& p) {
  for (int i = 0; i <= b.ni; ++i)
    if (b.x(i, j, k) == p) return i;
  fail("appended SUBOFF grid: internal: block '{}' has no node at the sail planes' tube", b.name);
}

// The hull's four sectors and the appendages' boxes; with the sail planes, the sail's box
// carries the planes' rings (sail_plane_rings) and keeps its levels for the tube, and the
// planes themselves go to the tube, not to boxes.
struct HullAndBoxes {
  std::vector<Block> sectors, boxes;
  std::vector<Level> sail_levels;              // the sail box's levels (sail planes only)
  std::array<const suboff::Fin*, 2> planes{};  // starboard, port (sail planes only)
};

HullAndBoxes make_hull_and_boxes(const Layout& lay, const suboff::Configuration& config, bool sail_planes) {
  HullAndBoxes h;
  for (int sector = 0; sector < 4; ++sector) h.sectors.push_back(make_sector_block(lay, sector));
  bool has_sail = false;
  for (const auto& a : config.appendages) {
    if (is_sail_plane(*a)) {
      h.planes[a->name() == "starboard_sail_plane" ? 0 : 1] = static_cast<const suboff::Fin*>(a.get());
      continue;
    }
    const bool tube_host = sail_planes && a->name() == "sail";
    has_sail = has_sail || a->name() == "sail";
    for (Block& b : make_box(h.sectors, lay, *a, tube_host ? &h.sail_levels : nullptr, tube_host))
      h.boxes.push_back(std::move(b));
  }
  if (sail_planes && (!has_sail || h.planes[0] == nullptr || h.planes[1] == nullptr))
    fail("appended SUBOFF grid: the sail planes need the sail");
  return h;
}

// Where the tube lies: its cross-section's stations and levels (TubeCuts) and the station
// and level at the planes' middle.
struct TubePlace {
  TubeCuts cuts;
  int station_mid = 0;
};

// The tube's cross-section: the stations half a root chord ahead of and behind the
// planes, the levels about their height, as many above as below.
TubePlace place_tube(const Layout& lay, const suboff::Fin& starboard) {
  const int tip = lay.spec.cells_span;
  const auto [first, last] = box_stations(lay, true);
  const Real root_span = suboff::Sail::kMaxHalfThickness, root_chord = starboard.chord(root_span);
  const Real x_front = (starboard.leading_edge(root_span) - 0.5 * root_chord) * lay.ft;
  const Real x_back = (starboard.trailing_edge(root_span) + 0.5 * root_chord) * lay.ft;
  auto station_x = [&](int i) { return lay.level(lay.st.s[static_cast<std::size_t>(i)], 0)[0]; };
  int ia = first + 1, ib = last - 1;
  while (ia + 1 < last && station_x(ia + 1) <= x_front) ++ia;
  while (ib - 1 > first && station_x(ib - 1) >= x_back) --ib;
  if (!(ia < ib) || station_x(ia) > x_front || station_x(ib) < x_back)
    fail("appended SUBOFF grid: the sail's box has no room ahead of or behind the sail planes (stations {}..{})", first,
         last);
  const int i_mid = (ia + ib) / 2;
  const Real s_mid = lay.st.s[static_cast<std::size_t>(i_mid)];
  const Real height = suboff::SailPlaneDesign::kHeight * lay.ft;
  int km = 1;
  for (int k = 1; k < tip; ++k)
    if (std::abs(lay.level(s_mid, k)[1] - height) < std::abs(lay.level(s_mid, km)[1] - height)) km = k;
  int h = 2;
  while (km - h > 1 && km + h < tip - 1 &&
         std::min(lay.level(s_mid, km + h)[1] - lay.level(s_mid, km)[1],
                  lay.level(s_mid, km)[1] - lay.level(s_mid, km - h)[1]) < 0.6 * root_chord * lay.ft)
    h += 2;
  if (km - h < 1 || km + h > tip - 1)
    fail("appended SUBOFF grid: no room between the hull and the sail's tip for the sail planes' tube");
  return {TubeCuts{ia, ib, km - h, km, km + h}, i_mid};
}

// The position along the sail box's O rings of a station on the sail's port or starboard
// side (the rings run round the section from the first level's split points).
int ring_position(const std::vector<Level>& sail_levels, int first_station, bool port, int station) {
  const auto& split = sail_levels.front().split;
  return port ? split[1] + (station - first_station) : split[4] - (station - first_station);
}

// The tube's level on the sail box's O layer t, port or starboard: its nodes the layer's,
// its azimuth exact on the sail's side (t = 0), beyond that interpolated from the layer's
// nodes (patch_azimuth), following the side through the wall layer and lying across the
// plane at the tips' ring.
TubeLevel sail_layer(const Layout& lay, const std::vector<Level>& sail_levels, const TubeCuts& cuts, bool port,
                     int t) {
  const int first = box_stations(lay, true)[0];
  const SailPlaneRings rings = sail_plane_rings(lay.spec.cells_section);
  const Real plane_angle = 1.5 * kPi;  // the sail's plane, 270 degrees
  const Real ft = lay.ft;
  TubeLevel l;
  l.node = [&sail_levels, t, port, first](int station, int k) {
    return sail_levels[static_cast<std::size_t>(k)].ring[static_cast<std::size_t>(t)][static_cast<std::size_t>(
        ring_position(sail_levels, first, port, station))];
  };
  // The sail's side: its half-thickness across the plane, exactly.
  const Real sign = port ? 1.0 : -1.0;
  if (t == 0) {
    l.azimuth = [sign, plane_angle, ft](Real x, Real r) {
      return plane_angle + sign * std::asin(suboff::Sail::section_half_thickness(x / ft) * ft / r);
    };
    return l;
  }
  std::vector<std::vector<Vec3>> patch;
  for (int i = cuts.station_first; i <= cuts.station_last; ++i) {
    std::vector<Vec3> column;
    for (int k = cuts.level_low; k <= cuts.level_high; ++k) column.push_back(l.node(i, k));
    patch.push_back(std::move(column));
  }
  // Between the wall layer and the knot a blend over the first half of the way, where the
  // rings stand far apart: clustered round the knot, rings 1e-6 L apart interpolated alike
  // (a blend there crossed them).
  const Real follow =
      1.0 - smoothstep(2.0 * static_cast<Real>(t - rings.cells_layer) / (rings.knot_ring - rings.cells_layer));
  l.azimuth = patch_azimuth(
      std::move(patch), [ft](Real x) { return suboff::Sail::section_half_thickness(x / ft) * ft; }, follow,
      plane_angle, sign);
  return l;
}

// The tube's level on a sector's meridional half-plane j.
TubeLevel sector_layer(const Block& sector, int station, int j) {
  TubeLevel l;
  l.node = [b = &sector, j](int i, int k) { return b->x(i, j, k); };
  const Vec3 p = sector.x(station, j, 0);
  const Real phi = std::atan2(p[2], p[1]);
  l.azimuth = [phi](Real, Real) { return phi; };
  return l;
}

// The tube's levels: the sail box's starboard O layers outwards, the sectors' azimuthal
// planes round under the hull, the port O layers inwards; its blocks break where the
// host's blocks do, and its tips lie on the sail's O ring clustered at their span.
SailPlaneTube describe_tube(const Layout& lay, const HullAndBoxes& h, const TubePlace& place) {
  const AppendedSuboffSpec& spec = lay.spec;
  const int na = spec.cells_around, w = spec.box_half_width;
  const TubeCuts& cuts = place.cuts;
  const int n = static_cast<int>(h.sail_levels.front().ring.size()) - 1;
  SailPlaneTube tube;
  tube.planes = h.planes;
  tube.feet = lay.ft;
  tube.station_first = cuts.station_first, tube.station_last = cuts.station_last;
  tube.level_low = cuts.level_low, tube.level_mid = cuts.level_mid, tube.level_high = cuts.level_high;
  for (int t = 0; t <= n; ++t) tube.levels.push_back(sail_layer(lay, h.sail_levels, cuts, false, t));
  tube.breaks.push_back(n);
  auto sector_run = [&](int q, int j0, int j1) {
    for (int j = j0 + 1; j <= j1; ++j) {
      tube.levels.push_back(sector_layer(h.sectors[static_cast<std::size_t>(q)], cuts.station_first, j));
      if (j == w || j == na - w || j == j1) tube.breaks.push_back(static_cast<int>(tube.levels.size()) - 1);
    }
  };
  sector_run(2, w, na);
  sector_run(1, 0, na);
  sector_run(0, 0, na);
  sector_run(3, 0, na - w);
  for (int t = n - 1; t >= 0; --t) tube.levels.push_back(sail_layer(lay, h.sail_levels, cuts, true, t));
  const int last_level = static_cast<int>(tube.levels.size()) - 1;
  // A box too narrow for the knot keeps that ring short of the span (ogrid::Spec's knot),
  // which is refused here.
  const int t_tip = sail_plane_rings(spec.cells_section).knot_ring;
  tube.tips = {t_tip, last_level - t_tip};
  for (const int l : tube.tips) {
    const suboff::Fin& plane = *h.planes[l == t_tip ? 0 : 1];
    const Vec3 p = tube.levels[static_cast<std::size_t>(l)].node(place.station_mid, cuts.level_mid);
    const Real span = plane.plane_coordinates(suboff::from_grid_axes(p / lay.ft))[1];
    if (std::abs(span - plane.shape().tip_span) > 1e-6)
      fail("appended SUBOFF grid: the sail's box reaches {:.3f} ft from the sail's plane at the sail planes' height, "
           "short of their {:.3f} ft span (widen grid.box_half_width)",
           span, plane.shape().tip_span);
  }
  tube.section_grid.cells_normal = spec.cells_section;
  tube.section_grid.first_spacing = spec.fin_spacing;
  tube.section_grid.layer = spec.section_layer;
  tube.section_grid.leading_edge_spacing = spec.section_edge_spacing;
  tube.section_grid.trailing_edge_spacing = spec.section_edge_spacing;
  tube.cap_growth = spec.cap_growth;
  return tube;
}

// The boxes cut where the tube meets them: the sail's O blocks at the tips' layer, its
// sides and what lies on them at the tube's stations, its inner blocks at the tube's
// levels, less the pieces the tube replaces; the stern appendages' inner blocks at the
// tube's levels (they meet the sectors' pieces there).
void cut_boxes_round_tube(const std::vector<Block>& boxes, const Layout& lay, const std::vector<Level>& sail_levels,
                          const TubeCuts& cuts, Grid& g) {
  const int first = box_stations(lay, true)[0], tip = lay.spec.cells_span;
  const int t_tip = sail_plane_rings(lay.spec.cells_section).knot_ring;
  const int ia = cuts.station_first, ib = cuts.station_last;
  auto ends_with = [](const std::string& s, const std::string& end) {
    return s.size() > end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
  };
  for (const Block& b : boxes) {
    const bool sail_box = b.name.rfind("sail_", 0) == 0;
    const bool inner = ends_with(b.name, "_inner"), outer = ends_with(b.name, "_outer");
    std::vector<int> ic{0, b.ni}, jc{0, b.nj}, kc{0, b.nk};
    if (inner)
      for (const int k : {cuts.level_low, cuts.level_mid, cuts.level_high}) kc.push_back(k);
    if (!sail_box) {
      cut_block(b, ic, jc, kc, [](const Index3&, const Index3&) { return false; }, g);
      continue;
    }
    if (inner || outer) jc.push_back(t_tip);
    const bool side = b.name == "sail_up_inner" || b.name == "sail_lo_inner" || b.name == "sail_up_outer" ||
                      b.name == "sail_lo_outer" || b.name == "sail_cap_up" || b.name == "sail_cap_lo";
    const bool port = b.name.find("_up") != std::string::npos;
    int i0 = -1, i1 = -1;
    if (side) {
      const auto& ring = sail_levels[static_cast<std::size_t>(inner ? 0 : tip)].ring.front();
      i0 = local_i(b, 0, 0, ring[static_cast<std::size_t>(ring_position(sail_levels, first, port, ia))]);
      i1 = local_i(b, 0, 0, ring[static_cast<std::size_t>(ring_position(sail_levels, first, port, ib))]);
      if (i0 > i1) std::swap(i0, i1);
      ic.push_back(i0);
      ic.push_back(i1);
    } else if (b.name == "sail_cap_corem" || b.name == "sail_cap_corep") {
      ic.push_back(ia - first);
      ic.push_back(ib - first);
    }
    const bool replaced = side && inner;
    cut_block(b, ic, jc, kc,
              [&](const Index3& lo, const Index3& hi) {
                return replaced && lo[0] >= i0 && hi[0] <= i1 && lo[2] >= cuts.level_low && hi[2] <= cuts.level_high;
              },
              g);
  }
}

}  // namespace

AppendedSuboffSpec scaled(const AppendedSuboffSpec& spec, Real scale) {
  if (!(scale > 0.0)) fail("appended SUBOFF grid: the scale must be positive, got {}", scale);
  AppendedSuboffSpec s = spec;
  const auto count = [scale](int n) { return std::max(4, 4 * static_cast<int>(std::lround(n * scale / 4.0))); };
  for (int* n : {&s.cells_bow, &s.cells_sail, &s.cells_middle, &s.cells_fin, &s.cells_stern, &s.cells_around,
                 &s.cells_span, &s.cells_outer, &s.box_half_width, &s.cells_margin, &s.cells_section})
    *n = count(*n);
  // The boxes span the reference's fraction of a sector on every member (rounded to whole
  // cells, not fours: at scale 0.375 fours made them a third of a sector where the others
  // have half, too narrow for a deflected fin), so that the members stay alike.
  s.box_half_width = std::clamp(static_cast<int>(std::lround(static_cast<Real>(s.cells_around) * spec.box_half_width /
                                                             spec.cells_around)),
                                1, s.cells_around / 2);
  // An O of 8 cells (4 in its outer half) diverged on the quarter of the 9.4 M grid where
  // 12 ran (mesh/DESIGN.md, "Appendage boxes").
  s.cells_section = std::max(s.cells_section, std::min(spec.cells_section, 12));
  for (Real* h : {&s.first_spacing, &s.fin_spacing, &s.tip_spacing, &s.leading_edge_spacing, &s.trailing_edge_spacing,
                  &s.pole_spacing, &s.section_edge_spacing})
    *h /= scale;
  return s;
}

std::vector<std::string> appended_suboff_configurations() {
  return suboff::configuration_names();
}

Grid make_appended_suboff(const AppendedSuboffSpec& spec) {
  const int na = spec.cells_around;
  if (na < 2 || na % 2 != 0) fail("appended SUBOFF grid: cells_around ({}) must be even", na);
  if (spec.box_half_width < 1 || 2 * spec.box_half_width > na)
    fail("appended SUBOFF grid: box_half_width ({}) must lie between 1 and half of cells_around ({})",
         spec.box_half_width, na);
  const auto meshed = appended_suboff_configurations();
  if (std::find(meshed.begin(), meshed.end(), spec.configuration) == meshed.end())
    fail("appended SUBOFF grid: configuration '{}' is not meshed (expected one of {})", spec.configuration,
         fmt::join(meshed, ", "));
  const suboff::Configuration config = suboff::make_configuration(spec.configuration, spec.deflections);

  const Layout layout(spec);
  const bool sail_planes = spec.configuration == "full";
  HullAndBoxes h = make_hull_and_boxes(layout, config, sail_planes);
  std::vector<Block> tube_blocks;
  TubeCuts cuts;
  if (sail_planes) {
    const TubePlace place = place_tube(layout, *h.planes[0]);
    cuts = place.cuts;
    tube_blocks = make_sail_plane_tube(describe_tube(layout, h, place), "sail");
  }
  for (const bool tail : {false, true}) h.sectors.push_back(make_pole_block(layout, tail));
  Grid g = cut_around_boxes(h.sectors, layout, config, cuts);
  if (sail_planes)
    cut_boxes_round_tube(h.boxes, layout, h.sail_levels, cuts, g);
  else
    for (Block& b : h.boxes) g.blocks.push_back(std::move(b));
  for (Block& b : tube_blocks) g.blocks.push_back(std::move(b));
  return g;  // the free faces are connected by finalize_grid (mesh/setup.hpp)
}

}  // namespace narwhal
