#include "mesh/appended_suboff.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/error.hpp"
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
  const suboff::Sail sail(spec.sail_crest_slope);
  const std::vector<Real> x_sail = two_sided_nodes(suboff::Sail::kLeadingEdge, suboff::Sail::kTrailingEdge,
                                                   spec.cells_sail, spec.leading_edge_spacing / ft,
                                                   spec.trailing_edge_spacing / ft);
  std::vector<Real> s_sail;
  std::vector<WallLine> sail_lines;
  for (const Real x : x_sail) {
    s_sail.push_back(arc_length_at(m, x * ft));
    sail_lines.push_back({true, 1.0, 0.0, 1.0, (sail.tip(x) - suboff::hull_radius(x)) * ft, 0.0});
  }
  // The stern appendages' window: lines of constant chord fraction xi, x = x_te - c(r) (1 - xi).
  const auto fin = suboff::make_stern_appendage(suboff::SternAppendage::UpperRudder);
  const auto& shape = fin->shape();
  const Real mean_chord = fin->chord(0.5 * (0.4 + shape.tip_span));
  const std::vector<Real> xi = two_sided_nodes(0.0, 1.0, spec.cells_fin, spec.leading_edge_spacing / (ft * mean_chord),
                                               spec.trailing_edge_spacing / (ft * mean_chord));
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

// The azimuths within a sector as a blend of four distributions from its j = 0 boundary:
// uniform, clustered at j = 0, at j = na, or at both (first spacing `first`), weighted
// bilinearly by how strongly each end clusters. A blend with non-negative weights of
// increasing sequences increases: no fold, whatever the weights.
class AzimuthBlend {
 public:
  AzimuthBlend(int na, Real first) : uniform_(uniform_nodes(0.0, 0.5 * kPi, na)) {
    const Real quarter = 0.5 * kPi, mean = quarter / na;
    both_ = two_sided_nodes(0.0, quarter, na, first, first);
    low_ = two_sided_nodes(0.0, quarter, na, first, mean);
    high_.resize(low_.size());
    for (std::size_t j = 0; j < low_.size(); ++j) high_[j] = quarter - low_[low_.size() - 1 - j];
  }
  // The azimuth of node j from the sector's j = 0 boundary, clustering c0 at j = 0 and cn
  // at j = na.
  Real at(int j, Real c0, Real cn) const {
    const std::size_t u = static_cast<std::size_t>(j);
    return (1.0 - c0) * (1.0 - cn) * uniform_[u] + c0 * (1.0 - cn) * low_[u] + (1.0 - c0) * cn * high_[u] +
           c0 * cn * both_[u];
  }

 private:
  std::vector<Real> uniform_, both_, low_, high_;
};

// Distances along a wall line: clustered at the hull and at the tip level (k = cells_span).
std::vector<Real> line_distances(const AppendedSuboffSpec& spec, Real d_tip) {
  return joined(two_sided_nodes(0.0, d_tip, spec.cells_span, spec.first_spacing, spec.tip_spacing),
                geometric_nodes(d_tip, spec.far_field * spec.length, spec.cells_outer, spec.tip_spacing));
}

// Wraps a sector's boundary plane at azimuth phi0 around an appendage: each node of the
// window turned about the hull axis by the angle that puts the boundary node on the
// appendage's surface at its own radius (hull nodes stay on the hull), the turn fading
// with the angular distance from the plane.
void wrap_appendage(Block& b, int sector, bool boundary_at_j0, const suboff::Appendage& a, int i_first, int i_last,
                    int k_tip, Real ft) {
  const int na = b.nj;
  const int jb = boundary_at_j0 ? 0 : na;
  const Real turn_sign = boundary_at_j0 ? -1.0 : 1.0;  // into the sector
  const Real phi0 = (boundary_at_j0 ? sector + 1 : sector) * 0.5 * kPi;
  for (int i = i_first + 1; i < i_last; ++i)
    for (int k = 0; k < k_tip; ++k) {
      const Vec3 on_plane = b.x(i, jb, k);
      const Real x = on_plane[0] / ft, r = std::hypot(on_plane[1], on_plane[2]) / ft;
      // The span coordinate s of the surface point at radius r: s^2 + t(x, s)^2 = r^2.
      Real s = r, t = 0.0;
      for (int it = 0; it < 60; ++it) {
        t = a.half_thickness(x, s);
        const Real next = std::sqrt(std::max(0.0, r * r - t * t));
        if (std::abs(next - s) < 1e-15 * r) break;
        s = next;
      }
      const Real angle = turn_sign * std::atan2(t, s);
      if (angle == 0.0) continue;
      // The turn fades over four times its own angle (at most the sector): the map
      // phi -> phi + angle w(phi / reach) stays monotone (|w'| <= 1.5), and where the
      // thickness falls to zero (edges, the tip's crest) only the nodes near the plane turn,
      // so the nodes further out do not shear against the untouched ones beyond the edge.
      const Real reach = std::min(0.5 * kPi, 4.0 * std::abs(angle));
      for (int j = 0; j <= na; ++j) {
        Vec3& p = b.x(i, j, k);
        const Real apart = std::abs(std::remainder(std::atan2(p[2], p[1]) - phi0, 2.0 * kPi));
        const Real w = 1.0 - smoothstep(apart / reach);
        if (w == 0.0) continue;
        const Real c = std::cos(angle * w), sn = std::sin(angle * w);
        const Real y = p[1], z = p[2];
        p[1] = c * y - sn * z;
        p[2] = sn * y + c * z;
      }
    }
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
  AzimuthBlend azimuths;
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
  // How strongly the azimuths cluster at boundary q at station i, level k: the window's
  // weight, fading above the tip level over three spans (over one, the grid coarsened
  // twice, a multigrid level, had folded cells above the sail's tip). The sail stands at
  // 270 degrees only.
  Real clustering(int q, std::size_t i, int k) const {
    const WallLine& w = st.lines[i];
    if (w.near_sail && q != 3) return 0.0;
    const Real above_tip = distances[i][static_cast<std::size_t>(k)] - w.d_tip;
    return w.fin_weight * (1.0 - smoothstep(above_tip / (3.0 * w.d_tip)));
  }
  Vec3 node(const SurfacePoint& p, std::size_t i, int k) const {
    return line_node(extrusion, p, st.lines[i], distances[i][static_cast<std::size_t>(k)]);
  }
};

BodyGridSpec far_field_extrusion(const AppendedSuboffSpec& spec) {
  BodyGridSpec es;
  es.far_field = spec.far_field;
  es.cells_normal = 1;
  es.first_spacing = spec.far_field * spec.length;
  return es;
}

// Azimuths: uniform (as the bare grids) at the poles and away from the appendages;
// clustered at a sector boundary where an appendage may stand there (whatever the
// configuration, so that all share the grid), with the first spacing fin_spacing at the
// largest radius an appendage reaches (the sail's crest).
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
      azimuths(s.cells_around, s.fin_spacing / (suboff::Sail(s.sail_crest_slope).tip(3.45) * ft)),
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
      const Real at_j0 = lay.clustering((sector + 1) % 4, ui, k), at_jn = lay.clustering(sector, ui, k);
      for (int j = 0; j <= na; ++j) {
        // j = 0 and j = na are the boundaries: exact axes, shared bit for bit with the neighbour.
        const Real phi = (sector + 1) * 0.5 * kPi - lay.azimuths.at(j, at_j0, at_jn);
        const auto [c, sn] = j == 0    ? lay.az.unit((sector + 1) * na)
                             : j == na ? lay.az.unit(sector * na)
                                       : std::array<Real, 2>{std::cos(phi), std::sin(phi)};
        b.x(i, j, k) = Vec3(xr[0], xr[1] * c, xr[1] * sn);
      }
    }
  }
  add_hull_patches(b);
  return b;
}

// Each appendage in the boundary plane its span direction points to: the plane wrapped
// round it in the two sectors that share the plane, and its sides as wall patches.
void attach_appendages(std::vector<Block>& sectors, const Layout& lay, const suboff::Configuration& config) {
  const int na = lay.spec.cells_around;
  for (const auto& a : config.appendages) {
    const Vec3 span = suboff::to_grid_axes(a->span_direction);
    const Real phi0 = std::atan2(span[2], span[1]);
    const int q = (static_cast<int>(std::lround(phi0 / (0.5 * kPi))) + 4) % 4;
    const bool is_sail = a->name() == "sail";
    const int i_first = is_sail ? lay.st.sail_first : lay.st.fin_first;
    const int i_last = is_sail ? lay.st.sail_last : lay.st.fin_last;
    // Sector q has the boundary at j = na, sector q - 1 at j = 0.
    for (const int sector : {q, (q + 3) % 4}) {
      const bool at_j0 = sector != q;
      Block& b = sectors[static_cast<std::size_t>(sector)];
      wrap_appendage(b, sector, at_j0, *a, i_first, i_last, lay.spec.cells_span, lay.ft);
      Patch p;
      p.side = at_j0 ? 2 : 3;
      p.lo = {i_first, 0, 0};
      p.hi = {i_last, na, lay.spec.cells_span};
      p.label = a->name();
      b.patches.push_back(p);
    }
  }
}

// The pole squares, as in body_of_revolution.cpp, with their meridians' lines.
Block make_pole_block(const Layout& lay, bool tail) {
  const std::size_t line = tail ? static_cast<std::size_t>(lay.nl) : 0;
  Block b = make_pole_square(lay.meridian, lay.az, lay.rho, lay.nk, tail,
                             [&](const SurfacePoint& p, int k) { return lay.node(p, line, k); });
  add_hull_patches(b);
  return b;
}

// Cut the blocks where the appendages' faces end, so that every face is either a whole
// wall or a whole interface.
Grid cut_at_appendage_edges(const std::vector<Block>& blocks, const Layout& lay) {
  static constexpr const char* stretch[] = {"bow", "sail", "middle", "fin", "stern"};
  const std::vector<int> i_cuts{0, lay.st.sail_first, lay.st.sail_last, lay.st.fin_first, lay.st.fin_last, lay.nl};
  const std::vector<int> k_cuts{0, lay.spec.cells_span, lay.nk};
  Grid cut;
  for (const Block& b : blocks) {
    const bool square = b.name == "nose" || b.name == "tail";
    const std::vector<int> ic = square ? std::vector<int>{0, b.ni} : i_cuts;
    for (std::size_t a = 0; a + 1 < ic.size(); ++a)
      for (std::size_t c = 0; c + 1 < k_cuts.size(); ++c) {
        const std::string name = square ? fmt::format("{}_{}", b.name, c == 0 ? "inner" : "outer")
                                        : fmt::format("{}_{}_{}", b.name, stretch[a], c == 0 ? "inner" : "outer");
        cut.blocks.push_back(extract_block(b, name, {ic[a], 0, k_cuts[c]}, {ic[a + 1], b.nj, k_cuts[c + 1]}));
      }
  }
  return cut;
}

}  // namespace

std::vector<std::string> appended_suboff_configurations() {
  std::vector<std::string> meshed;
  for (const auto& name : suboff::configuration_names())
    if (name != "full") meshed.push_back(name);
  return meshed;
}

Grid make_appended_suboff(const AppendedSuboffSpec& spec) {
  const int na = spec.cells_around;
  if (na < 2 || na % 2 != 0) fail("appended SUBOFF grid: cells_around ({}) must be even", na);
  if (spec.deflections.rudder != 0.0 || spec.deflections.stern_planes != 0.0 || spec.deflections.sail_planes != 0.0)
    fail("appended SUBOFF grid: deflected control surfaces are not meshed yet");
  const auto meshed = appended_suboff_configurations();
  if (std::find(meshed.begin(), meshed.end(), spec.configuration) == meshed.end())
    fail("appended SUBOFF grid: configuration '{}' is not meshed (expected one of {})", spec.configuration,
         fmt::join(meshed, ", "));
  const suboff::Configuration config =
      suboff::make_configuration(spec.configuration, spec.deflections, spec.sail_crest_slope);

  const Layout layout(spec);
  std::vector<Block> blocks;
  for (int sector = 0; sector < 4; ++sector) blocks.push_back(make_sector_block(layout, sector));
  attach_appendages(blocks, layout, config);
  for (const bool tail : {false, true}) blocks.push_back(make_pole_block(layout, tail));
  return cut_at_appendage_edges(blocks, layout);  // the free faces are connected by finalize_grid (mesh/setup.hpp)
}

}  // namespace narwhal
