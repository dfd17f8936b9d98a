#include "mesh/appended_suboff.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
#include "mesh/appendage_box.hpp"
#include "mesh/generators.hpp"
#include "mesh/meridian.hpp"

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
std::vector<Block> make_box(const std::vector<Block>& sectors, const Layout& lay, const suboff::Appendage& a) {
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
  return make_appendage_box(box, a.name(), tag == tags.end() ? a.name() : tag->second);
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
Grid cut_around_boxes(const std::vector<Block>& blocks, const Layout& lay, const suboff::Configuration& config) {
  static constexpr const char* stretch[] = {"bow", "sail", "middle", "fin", "stern"};
  static constexpr const char* across[] = {"low", "mid", "high"};
  const int na = lay.spec.cells_around, w = lay.spec.box_half_width;
  const auto sail = box_stations(lay, true), fin = box_stations(lay, false);
  const std::vector<int> i_cuts{0, sail[0], sail[1], fin[0], fin[1], lay.nl};
  const std::vector<int> j_cuts{0, w, na - w, na};
  const std::vector<int> k_cuts{0, lay.spec.cells_span, lay.nk};
  auto boxed = [&](int sector, std::size_t a, std::size_t c) {
    for (const auto& ap : config.appendages) {
      const int q = plane_of(*ap);
      const std::size_t in_stretch = ap->name() == "sail" ? 1 : 3;
      if (a == in_stretch && ((sector == q && c == 2) || (sector == (q + 3) % 4 && c == 0))) return true;
    }
    return false;
  };
  Grid cut;
  for (const Block& b : blocks) {
    const bool square = b.name == "nose" || b.name == "tail";
    const std::vector<int> ic = square ? j_cuts : i_cuts;
    const int sector = square ? -1 : std::stoi(b.name.substr(b.name.find('_') + 1)) / 90;
    for (std::size_t a = 0; a + 1 < ic.size(); ++a)
      for (std::size_t c = 0; c + 1 < j_cuts.size(); ++c)
        for (std::size_t e = 0; e + 1 < k_cuts.size(); ++e) {
          if (!square && boxed(sector, a, c)) continue;
          // Boxes as wide as half a sector leave no middle piece.
          if (j_cuts[c + 1] == j_cuts[c] || (square && ic[a + 1] == ic[a])) continue;
          const std::string name = square ? fmt::format("{}_{}{}_{}", b.name, a, c, e == 0 ? "inner" : "outer")
                                          : fmt::format("{}_{}_{}_{}", b.name, stretch[a], across[c],
                                                        e == 0 ? "inner" : "outer");
          cut.blocks.push_back(
              extract_block(b, name, {ic[a], j_cuts[c], k_cuts[e]}, {ic[a + 1], j_cuts[c + 1], k_cuts[e + 1]}));
        }
  }
  return cut;
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
  std::vector<std::string> meshed;
  for (const auto& name : suboff::configuration_names())
    if (name != "full") meshed.push_back(name);
  return meshed;
}

Grid make_appended_suboff(const AppendedSuboffSpec& spec) {
  const int na = spec.cells_around;
  if (na < 2 || na % 2 != 0) fail("appended SUBOFF grid: cells_around ({}) must be even", na);
  if (spec.box_half_width < 1 || 2 * spec.box_half_width > na)
    fail("appended SUBOFF grid: box_half_width ({}) must lie between 1 and half of cells_around ({})",
         spec.box_half_width, na);
  if (spec.deflections.sail_planes != 0.0) fail("appended SUBOFF grid: the sail planes are not meshed yet");
  const auto meshed = appended_suboff_configurations();
  if (std::find(meshed.begin(), meshed.end(), spec.configuration) == meshed.end())
    fail("appended SUBOFF grid: configuration '{}' is not meshed (expected one of {})", spec.configuration,
         fmt::join(meshed, ", "));
  const suboff::Configuration config =
      suboff::make_configuration(spec.configuration, spec.deflections);

  const Layout layout(spec);
  std::vector<Block> blocks;
  for (int sector = 0; sector < 4; ++sector) blocks.push_back(make_sector_block(layout, sector));
  std::vector<Block> boxes;
  for (const auto& a : config.appendages)
    for (Block& b : make_box(blocks, layout, *a)) boxes.push_back(std::move(b));
  for (const bool tail : {false, true}) blocks.push_back(make_pole_block(layout, tail));
  Grid g = cut_around_boxes(blocks, layout, config);
  for (Block& b : boxes) g.blocks.push_back(std::move(b));
  return g;  // the free faces are connected by finalize_grid (mesh/setup.hpp)
}

}  // namespace narwhal
