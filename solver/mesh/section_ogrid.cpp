#include "mesh/section_ogrid.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/meridian.hpp"

namespace narwhal::ogrid {
namespace {

Real cross(const Point& a, const Point& b) { return a[0] * b[1] - a[1] * b[0]; }

// One side of the section tabulated by arc length from the leading edge, so that nodes
// can be placed by arc length and then evaluated exactly at their own u.
class Side {
 public:
  explicit Side(std::function<Point(Real)> f) : f_(std::move(f)) {
    // u = v^2 resolves the round leading edge, where w grows as sqrt(u).
    constexpr int n = 2000;
    u_.resize(n + 1);
    arc_.resize(n + 1);
    Point last = f_(0.0);
    for (int k = 0; k <= n; ++k) {
      const Real v = static_cast<Real>(k) / n;
      u_[k] = v * v;
      const Point p = f_(u_[k]);
      arc_[k] = k == 0 ? 0.0 : arc_[k - 1] + (p - last).norm();
      last = p;
    }
  }
  Point at(Real u) const { return f_(u); }
  Real arc_at(Real u) const { return interpolate(u_, arc_, u); }
  Real u_at(Real arc) const { return interpolate(arc_, u_, arc); }
  // The unit tangent at u, towards the trailing edge.
  Point tangent(Real u) const {
    const Real h = 1e-7;
    const Real a = std::max(0.0, u - h), b = std::min(1.0, u + h);
    return (f_(b) - f_(a)).normalized();
  }

 private:
  static Real interpolate(const std::vector<Real>& xs, const std::vector<Real>& ys, Real x) {
    const auto it = std::upper_bound(xs.begin(), xs.end(), x);
    if (it == xs.begin()) return ys.front();
    if (it == xs.end()) return ys.back();
    const std::size_t k = static_cast<std::size_t>(it - xs.begin());
    const Real f = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
    return ys[k - 1] + f * (ys[k] - ys[k - 1]);
  }
  std::function<Point(Real)> f_;
  std::vector<Real> u_, arc_;
};

// A two-sided distribution whose end spacings are reduced alike where they would not fit
// (a short arc in few cells: coarse grids).
std::vector<Real> fitted_nodes(Real a, Real b, int n, Real ds_a, Real ds_b) {
  if (n == 2) return {a, a + (b - a) * ds_a / (ds_a + ds_b), b};  // one free node: split as the spacings
  const Real room = 0.8 * (b - a) / n, mean = std::sqrt(ds_a * ds_b);
  const Real f = mean < room ? 1.0 : room / mean;
  return two_sided_nodes(a, b, n, f * ds_a, f * ds_b);
}

struct SectionNode {
  Point x, normal;
  Real u;
};

// Nodes along one side at the arc lengths `arcs` (the ends excluded when asked).
void append(std::vector<SectionNode>& out, const Side& side, bool upper, const std::vector<Real>& arcs, bool reverse,
            bool skip_first) {
  std::vector<Real> a = arcs;
  if (reverse) std::reverse(a.begin(), a.end());
  for (std::size_t k = skip_first ? 1 : 0; k < a.size(); ++k) {
    const Real u = side.u_at(a[k]);
    const Point t = side.tangent(u);
    const Point n = upper ? Point(-t[1], t[0]) : Point(t[1], -t[0]);
    out.push_back({side.at(u), n, u});
  }
}

std::vector<Point> box_ring(const Box& box) {
  const std::vector<Point>* sides[] = {&box.front, &box.top, &box.back, &box.bottom};
  std::vector<Point> ring;
  for (int q = 0; q < 4; ++q) {
    const auto& s = *sides[q];
    const auto& next = *sides[(q + 1) % 4];
    if (s.size() < 2) fail("section O-grid: a box side has fewer than two nodes");
    if ((s.back() - next.front()).norm() > 1e-12 * (1.0 + s.back().norm()))
      fail("section O-grid: box side {} does not end where side {} starts", q, (q + 1) % 4);
    ring.insert(ring.end(), s.begin(), s.end() - 1);
  }
  ring.push_back(ring.front());
  return ring;
}

}  // namespace

Real quad_area2(const Point& a, const Point& b, const Point& c, const Point& d) { return cross(c - a, d - b); }

namespace {

// The box's cells along each side.
struct BoxCounts {
  int front, upper, back, lower;
};
BoxCounts box_counts(const Box& box) {
  auto cells = [](const std::vector<Point>& side) { return static_cast<int>(side.size()) - 1; };
  return {cells(box.front), cells(box.top), cells(box.back), cells(box.bottom)};
}

// The box's node counts an O-grid needs: an even number of cells on its front and back
// (the edges are nodes) and two or more on its top and bottom.
void check_box_counts(const Box& box, const Spec& spec) {
  const auto [m_front, n_upper, m_back, n_lower] = box_counts(box);
  if (m_front < 2 || m_front % 2 != 0 || m_back < 2 || m_back % 2 != 0)
    fail("section O-grid: the box's front and back need an even number of cells (the edges are nodes), got {} and {}",
         m_front, m_back);
  if (n_upper < 2 || n_lower < 2) fail("section O-grid: the box's top and bottom need two or more cells");
  if (!(spec.leading_edge_arc > 0.0 && spec.leading_edge_arc < spec.trailing_edge_arc && spec.trailing_edge_arc < 1.0))
    fail("section O-grid: need 0 < leading_edge_arc < trailing_edge_arc < 1");
}

// The section's nodes, one per box node, from the lower leading-edge junction round by
// the leading edge, the upper side and the trailing edge; the edges' normals bisect the
// two sides' tangents (the leading edge's ahead of it, the trailing edge's along its
// bisector, downstream).
std::vector<SectionNode> section_nodes(const Section& section, const Box& box, const Spec& spec) {
  const auto [m_front, n_upper, m_back, n_lower] = box_counts(box);
  const Side up(section.upper), lo(section.lower);
  const Real ua = spec.leading_edge_arc, ub = spec.trailing_edge_arc;
  const int hf = m_front / 2, hb = m_back / 2;
  const Real up_a = up.arc_at(ua), up_b = up.arc_at(ub), up_end = up.arc_at(1.0);
  const Real lo_a = lo.arc_at(ua), lo_b = lo.arc_at(ub), lo_end = lo.arc_at(1.0);
  // The sides' nodes follow the box's: a node lies about where its box node is along the
  // chord (its line then leaves the section about square), and the box's nodes ahead of
  // and behind the section (its margins) crowd towards the junctions, keeping a fifth of
  // their share. Lines to box nodes far along the chord from their section node lean and
  // shear their cells (a box a chord long with the section's nodes spread evenly leaned
  // the lines by up to 80 degrees).
  auto side_arcs = [&](const Side& side, const std::vector<Point>& along, Real arc_a, Real arc_b) {
    const Real s0 = along.front()[0], length = along.back()[0] - s0;
    const Real fa = (side.at(ua)[0] - s0) / length, fb = (side.at(ub)[0] - s0) / length;
    constexpr Real keep = 0.2;
    std::vector<Real> arcs;
    for (const Point& p : along) {
      const Real f = (p[0] - s0) / length;
      const Real g = keep * f + (1.0 - keep) * std::clamp((f - fa) / (fb - fa), 0.0, 1.0);
      arcs.push_back(arc_a + (arc_b - arc_a) * g);
    }
    arcs.front() = arc_a;
    arcs.back() = arc_b;
    return arcs;
  };
  std::vector<Point> bottom_forward = box.bottom;
  std::reverse(bottom_forward.begin(), bottom_forward.end());
  const std::vector<Real> upper_arcs = side_arcs(up, box.top, up_a, up_b);
  const std::vector<Real> lower_arcs = side_arcs(lo, bottom_forward, lo_a, lo_b);
  const Real da_up = upper_arcs[1] - upper_arcs[0], db_up = upper_arcs.back() - upper_arcs[upper_arcs.size() - 2];
  const Real da_lo = lower_arcs[1] - lower_arcs[0], db_lo = lower_arcs.back() - lower_arcs[lower_arcs.size() - 2];
  const Real le = spec.leading_edge_spacing, te = spec.trailing_edge_spacing;

  std::vector<SectionNode> nodes;
  append(nodes, lo, false, fitted_nodes(0.0, lo_a, hf, le, da_lo), true, false);  // junction -> LE
  append(nodes, up, true, fitted_nodes(0.0, up_a, hf, le, da_up), false, true);   // LE -> junction
  append(nodes, up, true, upper_arcs, false, true);
  append(nodes, up, true, fitted_nodes(up_b, up_end, hb, db_up, te), false, true);  // -> TE
  append(nodes, lo, false, fitted_nodes(lo_b, lo_end, hb, db_lo, te), true, true);  // TE -> junction
  append(nodes, lo, false, lower_arcs, true, true);
  const int around = m_front + n_upper + m_back + n_lower;
  if (static_cast<int>(nodes.size()) != around + 1) fail("section O-grid: internal: {} ring nodes", nodes.size());
  SectionNode& lead = nodes[static_cast<std::size_t>(hf)];
  lead.normal = -(up.tangent(1e-9) + lo.tangent(1e-9)).normalized();
  const Real before_te = 1.0 - 1e-9;
  SectionNode& trail = nodes[static_cast<std::size_t>(m_front + n_upper + hb)];
  trail.normal = (up.tangent(before_te) + lo.tangent(before_te)).normalized();
  return nodes;
}

// The directions the lines leave the section in: the nodes' normals, except that at the
// sharp trailing edge (where they jump) they fan over the `fan` nodes either side.
std::vector<Point> leaving_directions(const std::vector<SectionNode>& nodes, int te_node, int fan) {
  std::vector<Point> normal;
  for (const auto& p : nodes) normal.push_back(p.normal);
  for (int k = -fan; k <= fan; ++k) {
    const std::size_t at = static_cast<std::size_t>(te_node + k);
    const Real f = static_cast<Real>(std::abs(k)) / (fan + 1);  // 0 at the edge, -> 1 away from it
    const Point side = nodes[static_cast<std::size_t>(te_node + (k < 0 ? -fan - 1 : fan + 1))].normal;
    normal[at] = ((1.0 - f) * nodes[static_cast<std::size_t>(te_node)].normal + f * side).normalized();
  }
  return normal;
}

// One line from a section node to its box node: along the leaving direction for `layer`
// (the boundary layer's cells are the section's offset curves: orthogonal, and no two
// lines meet on a convex section), then straight to the box; with a knot, the knot's
// distance along it.
struct Line {
  Real layer, rest, length, knot = 0.0;
  Point turn_at;
};

std::vector<Line> plan_lines(const std::vector<SectionNode>& nodes, const std::vector<Point>& direction,
                             const std::vector<Point>& outer, Real common_layer, const Spec& spec) {
  const int nn = spec.cells_normal;
  const std::size_t around = outer.size() - 1;
  std::vector<Line> lines(around);
  for (std::size_t s = 0; s < around; ++s) {
    const Point q = outer[s];
    // A line shorter than twice the layer (a box side close to an edge) leaves along the
    // normal for half its length only.
    Line& l = lines[s];
    l.layer = std::min(common_layer, 0.5 * (q - nodes[s].x).norm());
    l.turn_at = nodes[s].x + l.layer * direction[s];
    l.rest = (q - l.turn_at).norm();
    l.length = l.layer + l.rest;
    if (!(l.rest > 0.0) || !(l.length > 2.0 * nn * spec.first_spacing))
      fail("section O-grid: line {} from the section to the box is too short ({:.3g}) for {} cells from {:.3g}", s,
           l.length, nn, spec.first_spacing);
  }
  return lines;
}

// The knot ring's distance along each line: at |w| = knot_w on the sides' lines, and on
// the arcs' lines at the fraction of their length their junctions' lines have, blended.
void place_knots(std::vector<Line>& lines, const std::vector<Point>& outer, const std::array<int, 5>& split,
                 const Spec& spec) {
  const int around = static_cast<int>(lines.size());
  const int upper_end = split[2], lower_start = split[3];
  auto on_side = [&](int s) { return (s >= split[1] && s <= upper_end) || s >= lower_start || s == 0; };
  for (int s = 0; s < around; ++s) {
    if (!on_side(s)) continue;
    Line& l = lines[static_cast<std::size_t>(s)];
    const Real w_turn = l.turn_at[1], w_box = outer[static_cast<std::size_t>(s)][1];
    const Real target = (w_box > w_turn ? 1.0 : -1.0) * spec.knot_w;
    // Where the box is narrower than the knot's distance (near a hull that narrows the
    // box: levels away from the planes) the ring keeps to the lines' last tenth.
    const Real lambda = std::clamp((target - w_turn) / (w_box - w_turn), 0.1, 0.9);
    l.knot = l.layer + lambda * l.rest;
  }
  auto blend = [&](int from, int to) {
    const Line &a = lines[static_cast<std::size_t>(from % around)], &b = lines[static_cast<std::size_t>(to % around)];
    for (int s = from + 1; s < to; ++s) {
      const Real f = static_cast<Real>(s - from) / (to - from);
      Line& l = lines[static_cast<std::size_t>(s)];
      l.knot = ((1.0 - f) * a.knot / a.length + f * b.knot / b.length) * l.length;
    }
  };
  blend(0, split[1]);
  blend(upper_end, lower_start);
}

// The nodes' distances along line `s` from the section: `in_layer` cells in the layer,
// growing geometrically alike on every line (so the rings there are the section's offset
// curves), the rest from the layer to the box continuing the growth (through the knot,
// with one); a line whose layer was shortened is two-sided instead.
std::vector<Real> line_distances(const Line& l, int s, Real common_layer, int in_layer, bool knotted,
                                 const Spec& spec) {
  const int nn = spec.cells_normal;
  std::vector<Real> d;
  if (knotted) {
    if (!(l.layer == common_layer && in_layer >= 2 && l.knot > l.layer && l.knot < l.length))
      fail("section O-grid: line {}'s knot ({:.4g}) does not lie between its layer and the box", s, l.knot);
    d = geometric_nodes(0.0, l.layer, in_layer, spec.first_spacing);
    const std::size_t e = static_cast<std::size_t>(in_layer);
    const Real growth = (d[e] - d[e - 1]) / (d[e - 1] - d[e - 2]);
    const auto to_knot = fitted_nodes(l.layer, l.knot, spec.knot_ring - in_layer, growth * (d[e] - d[e - 1]),
                                      spec.knot_spacing);
    const auto beyond = fitted_nodes(l.knot, l.length, nn - spec.knot_ring, spec.knot_spacing,
                                     std::min(spec.outer_spacing, (l.length - l.knot) / (nn - spec.knot_ring)));
    d.insert(d.end(), to_knot.begin() + 1, to_knot.end());
    d.insert(d.end(), beyond.begin() + 1, beyond.end());
  } else if (l.layer == common_layer && in_layer >= 2) {
    d = geometric_nodes(0.0, l.layer, in_layer, spec.first_spacing);
    const std::size_t e = static_cast<std::size_t>(in_layer);
    const Real growth = (d[e] - d[e - 1]) / (d[e - 1] - d[e - 2]);
    const auto beyond = fitted_nodes(l.layer, l.length, nn - in_layer, growth * (d[e] - d[e - 1]),
                                     std::min(spec.outer_spacing, l.rest / (nn - in_layer)));
    d.insert(d.end(), beyond.begin() + 1, beyond.end());
  } else {
    d = two_sided_nodes(0.0, l.length, nn, spec.first_spacing, std::min(spec.outer_spacing, l.length / nn));
  }
  return d;
}

}  // namespace

OGrid make_section_ogrid(const Section& section, const Box& box, const Spec& spec) {
  check_box_counts(box, spec);
  const std::vector<Point> outer = box_ring(box);
  const auto [m_front, n_upper, m_back, n_lower] = box_counts(box);
  const int around = static_cast<int>(outer.size()) - 1;
  const std::vector<SectionNode> nodes = section_nodes(section, box, spec);
  const std::vector<Point> direction =
      leaving_directions(nodes, m_front + n_upper + m_back / 2, spec.trailing_edge_fan);

  OGrid o;
  o.split = {0, m_front, m_front + n_upper, m_front + n_upper + m_back, around};
  const int nn = spec.cells_normal;
  // The layer holds half the cells (or cells_layer): with large first spacings (far above
  // a tip) it thickens to keep them growing.
  const int in_layer = spec.cells_layer > 0 ? spec.cells_layer : nn / 2;
  const Real common_layer = std::max(spec.layer, 2.0 * in_layer * spec.first_spacing);
  const bool knotted = spec.knot_ring > 0;
  if (knotted && !(spec.knot_ring > in_layer && spec.knot_ring < nn && spec.knot_w > 0.0 && spec.knot_spacing > 0.0))
    fail("section O-grid: the knot ring ({}) must lie between the layer's {} cells and the box's {}, at a positive "
         "distance and spacing",
         spec.knot_ring, in_layer, nn);
  std::vector<Line> lines = plan_lines(nodes, direction, outer, common_layer, spec);
  if (knotted) place_knots(lines, outer, o.split, spec);

  o.ring.assign(static_cast<std::size_t>(nn + 1), std::vector<Point>(static_cast<std::size_t>(around + 1)));
  for (int s = 0; s < around; ++s) {
    const std::size_t us = static_cast<std::size_t>(s);
    const Line& l = lines[us];
    const std::vector<Real> d = line_distances(l, s, common_layer, in_layer, knotted, spec);
    for (int t = 0; t <= nn; ++t) {
      const Real dt = d[static_cast<std::size_t>(t)];
      o.ring[static_cast<std::size_t>(t)][us] =
          t == nn ? outer[us]
          : dt <= l.layer ? Point(nodes[us].x + dt * direction[us])
                          : Point(l.turn_at + (dt - l.layer) / l.rest * (outer[us] - l.turn_at));
    }
    o.u.push_back(nodes[us].u);
  }
  for (auto& r : o.ring) r.back() = r.front();
  o.u.push_back(o.u.front());
  return o;
}

SectionCap section_cap(const OGrid& o, const Section& section, int ring_cells) {
  const int m_front = o.split[1] - o.split[0], n_upper = o.split[2] - o.split[1];
  const int m_back = o.split[3] - o.split[2], n_lower = o.split[4] - o.split[3];
  if (n_upper != n_lower || m_front != m_back)
    fail("section cap: needs as many cells on the lower side as on the upper ({} and {}) and round the trailing "
         "edge as round the leading edge ({} and {})",
         n_lower, n_upper, m_back, m_front);
  if (ring_cells < 1) fail("section cap: the ring needs a cell or more");
  const auto& wall = o.ring.front();
  const int S = o.split[4];
  // The core's boundary, node for node with the section's: the sides at 3/4 of the way
  // from the lower side to the upper (and 1/4) at the same u; front and back straight
  // between the corners, spaced as the section's arcs.
  auto inner_side = [&](Real u, bool upper) {
    const Point a = section.upper(u), b = section.lower(u);
    return upper ? Point(0.75 * a + 0.25 * b) : Point(0.25 * a + 0.75 * b);
  };
  // The core's corners lie behind the front junctions and ahead of the back ones (u from
  // [ua, ub] mapped onto [2 ua, ub - (1 - ub) / 3]): at the junctions themselves the ring's
  // corner lines would run along the core's straight front and back, a straight angle; and
  // with the back ahead of every node of the trailing edge's arc, all their lines run
  // forward and none crosses another (behind the junction they crossed).
  const Real ua = o.u[static_cast<std::size_t>(o.split[1])], ub = o.u[static_cast<std::size_t>(o.split[2])];
  const Real ca = 2.0 * ua, cb = ub - (1.0 - ub) / 3.0;
  auto core_u = [&](Real u) { return ca + (u - ua) / (ub - ua) * (cb - ca); };
  const Point front_lower = inner_side(ca, false), front_upper = inner_side(ca, true);
  const Point back_upper = inner_side(cb, true), back_lower = inner_side(cb, false);
  std::vector<Point> boundary(static_cast<std::size_t>(S + 1));
  auto straight = [&](int s0, int cells, const Point& from, const Point& to) {
    Real total = 0.0;
    for (int q = 0; q < cells; ++q)
      total += (wall[static_cast<std::size_t>(s0 + q + 1)] - wall[static_cast<std::size_t>(s0 + q)]).norm();
    Real run = 0.0;
    for (int q = 0; q <= cells; ++q) {
      if (q > 0) run += (wall[static_cast<std::size_t>(s0 + q)] - wall[static_cast<std::size_t>(s0 + q - 1)]).norm();
      boundary[static_cast<std::size_t>(s0 + q)] = from + (run / total) * (to - from);
    }
  };
  straight(o.split[0], m_front, front_lower, front_upper);
  for (int s = o.split[1]; s <= o.split[2]; ++s)
    boundary[static_cast<std::size_t>(s)] = inner_side(core_u(o.u[static_cast<std::size_t>(s)]), true);
  straight(o.split[2], m_back, back_upper, back_lower);
  for (int s = o.split[3]; s <= S; ++s)
    boundary[static_cast<std::size_t>(s)] = inner_side(core_u(o.u[static_cast<std::size_t>(s)]), false);
  boundary[static_cast<std::size_t>(o.split[1])] = front_upper;
  boundary[static_cast<std::size_t>(o.split[2])] = back_upper;
  boundary[static_cast<std::size_t>(o.split[3])] = back_lower;
  boundary[0] = boundary[static_cast<std::size_t>(S)] = front_lower;

  SectionCap cap;
  cap.ring.assign(static_cast<std::size_t>(ring_cells + 1), std::vector<Point>(static_cast<std::size_t>(S + 1)));
  for (int t = 0; t <= ring_cells; ++t)
    for (int s = 0; s <= S; ++s) {
      const std::size_t us = static_cast<std::size_t>(s);
      const Real f = static_cast<Real>(t) / ring_cells;
      cap.ring[static_cast<std::size_t>(t)][us] = t == 0 ? wall[us] : t == ring_cells ? boundary[us] : Point((1.0 - f) * wall[us] + f * boundary[us]);
    }
  // The core: transfinite interpolation between its four sides, in their arc-length fractions.
  const int na = n_upper, nb = m_front;
  auto lower = [&](int a) { return boundary[static_cast<std::size_t>(S - a)]; };
  auto upper = [&](int a) { return boundary[static_cast<std::size_t>(o.split[1] + a)]; };
  auto front = [&](int b) { return boundary[static_cast<std::size_t>(b)]; };
  auto back = [&](int b) { return boundary[static_cast<std::size_t>(o.split[3] - b)]; };
  auto fractions = [](auto edge, int n) {
    std::vector<Real> f(static_cast<std::size_t>(n + 1), 0.0);
    for (int k = 1; k <= n; ++k)
      f[static_cast<std::size_t>(k)] = f[static_cast<std::size_t>(k - 1)] + (edge(k) - edge(k - 1)).norm();
    for (auto& v : f) v /= f.back();
    return f;
  };
  const auto fl = fractions(lower, na), fu = fractions(upper, na), ff = fractions(front, nb), fb = fractions(back, nb);
  cap.core.assign(static_cast<std::size_t>(na + 1), std::vector<Point>(static_cast<std::size_t>(nb + 1)));
  const Point c00 = lower(0), c10 = lower(na), c01 = upper(0), c11 = upper(na);
  for (int a = 0; a <= na; ++a)
    for (int b = 0; b <= nb; ++b) {
      const std::size_t ua_ = static_cast<std::size_t>(a), ub_ = static_cast<std::size_t>(b);
      const Real al = 0.5 * (fl[ua_] + fu[ua_]), be = 0.5 * (ff[ub_] + fb[ub_]);
      Point p = (1.0 - al) * front(b) + al * back(b) + (1.0 - be) * lower(a) + be * upper(a) -
                ((1.0 - al) * (1.0 - be) * c00 + al * (1.0 - be) * c10 + (1.0 - al) * be * c01 + al * be * c11);
      if (a == 0) p = front(b);
      if (a == na) p = back(b);
      if (b == 0) p = lower(a);
      if (b == nb) p = upper(a);
      cap.core[ua_][ub_] = p;
    }
  return cap;
}

}  // namespace narwhal::ogrid
