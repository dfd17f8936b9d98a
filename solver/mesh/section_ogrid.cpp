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
    constexpr int n = 4000;
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

OGrid make_section_ogrid(const Section& section, const Box& box, const Spec& spec) {
  const int m_front = static_cast<int>(box.front.size()) - 1, n_upper = static_cast<int>(box.top.size()) - 1;
  const int m_back = static_cast<int>(box.back.size()) - 1, n_lower = static_cast<int>(box.bottom.size()) - 1;
  if (m_front < 2 || m_front % 2 != 0 || m_back < 2 || m_back % 2 != 0)
    fail("section O-grid: the box's front and back need an even number of cells (the edges are nodes), got {} and {}",
         m_front, m_back);
  if (n_upper < 2 || n_lower < 2) fail("section O-grid: the box's top and bottom need two or more cells");
  if (!(spec.leading_edge_arc > 0.0 && spec.leading_edge_arc < spec.trailing_edge_arc && spec.trailing_edge_arc < 1.0))
    fail("section O-grid: need 0 < leading_edge_arc < trailing_edge_arc < 1");
  const std::vector<Point> outer = box_ring(box);

  const Side up(section.upper), lo(section.lower);
  const Real ua = spec.leading_edge_arc, ub = spec.trailing_edge_arc;
  // Spacings at the junctions: the geometric mean of the two neighbouring blocks' mean
  // spacings along the section, so that neither side jumps.
  auto junction = [](Real len_a, int n_a, Real len_b, int n_b) { return std::sqrt(len_a / n_a * (len_b / n_b)); };
  const int hf = m_front / 2, hb = m_back / 2;
  const Real up_a = up.arc_at(ua), up_b = up.arc_at(ub), up_end = up.arc_at(1.0);
  const Real lo_a = lo.arc_at(ua), lo_b = lo.arc_at(ub), lo_end = lo.arc_at(1.0);
  const Real da_up = junction(up_a, hf, up_b - up_a, n_upper), db_up = junction(up_b - up_a, n_upper, up_end - up_b, hb);
  const Real da_lo = junction(lo_a, hf, lo_b - lo_a, n_lower), db_lo = junction(lo_b - lo_a, n_lower, lo_end - lo_b, hb);
  const Real le = spec.leading_edge_spacing, te = spec.trailing_edge_spacing;

  std::vector<SectionNode> nodes;
  append(nodes, lo, false, two_sided_nodes(0.0, lo_a, hf, le, da_lo), true, false);  // junction -> LE
  append(nodes, up, true, two_sided_nodes(0.0, up_a, hf, le, da_up), false, true);   // LE -> junction
  append(nodes, up, true, two_sided_nodes(up_a, up_b, n_upper, da_up, db_up), false, true);
  append(nodes, up, true, two_sided_nodes(up_b, up_end, hb, db_up, te), false, true);  // -> TE
  append(nodes, lo, false, two_sided_nodes(lo_b, lo_end, hb, db_lo, te), true, true);  // TE -> junction
  append(nodes, lo, false, two_sided_nodes(lo_a, lo_b, n_lower, da_lo, db_lo), true, true);
  const int around = m_front + n_upper + m_back + n_lower;
  if (static_cast<int>(nodes.size()) != around + 1) fail("section O-grid: internal: {} ring nodes", nodes.size());
  // The edges' normals bisect the two sides' tangents (the leading edge's ahead of it,
  // the trailing edge's along its bisector, downstream).
  SectionNode& lead = nodes[static_cast<std::size_t>(hf)];
  lead.normal = -(up.tangent(1e-9) + lo.tangent(1e-9)).normalized();
  const Real before_te = 1.0 - 1e-9;
  SectionNode& trail = nodes[static_cast<std::size_t>(m_front + n_upper + hb)];
  trail.normal = (up.tangent(before_te) + lo.tangent(before_te)).normalized();

  OGrid o;
  o.split = {0, m_front, m_front + n_upper, m_front + n_upper + m_back, around};
  const int nn = spec.cells_normal;
  o.ring.assign(static_cast<std::size_t>(nn + 1), std::vector<Point>(static_cast<std::size_t>(around + 1)));
  // Each line runs along its node's normal for `layer` (the boundary layer's cells are
  // the section's offset curves: orthogonal, and no two lines meet on a convex section),
  // then straight to its box node. At the sharp trailing edge the normals jump; they fan
  // over the `trailing_edge_fan` nodes either side instead.
  const int te_node = m_front + n_upper + hb;
  const int fan = spec.trailing_edge_fan;
  std::vector<Point> normal;
  for (const auto& p : nodes) normal.push_back(p.normal);
  for (int k = -fan; k <= fan; ++k) {
    const std::size_t at = static_cast<std::size_t>(te_node + k);
    const Real f = static_cast<Real>(std::abs(k)) / (fan + 1);  // 0 at the edge, -> 1 away from it
    const Point side = nodes[static_cast<std::size_t>(te_node + (k < 0 ? -fan - 1 : fan + 1))].normal;
    normal[at] = ((1.0 - f) * nodes[static_cast<std::size_t>(te_node)].normal + f * side).normalized();
  }
  for (int s = 0; s < around; ++s) {
    const std::size_t us = static_cast<std::size_t>(s);
    const SectionNode& p = nodes[us];
    const Point q = outer[us];
    const Point turn_at = p.x + spec.layer * normal[us];
    const Real rest = (q - turn_at).norm(), length = spec.layer + rest;
    if (!(rest > 0.0) || !(length > nn * spec.first_spacing))
      fail("section O-grid: line {} from the section to the box is too short ({:.3g}) for its {} cells and the "
           "layer {:.3g}",
           s, length, nn, spec.layer);
    const auto d = two_sided_nodes(0.0, length, nn, spec.first_spacing, std::min(spec.outer_spacing, length / nn));
    for (int t = 0; t <= nn; ++t) {
      const Real dt = d[static_cast<std::size_t>(t)];
      o.ring[static_cast<std::size_t>(t)][us] =
          t == nn ? q : dt <= spec.layer ? Point(p.x + dt * normal[us]) : Point(turn_at + (dt - spec.layer) / rest * (q - turn_at));
    }
    o.u.push_back(p.u);
  }
  for (auto& r : o.ring) r.back() = r.front();
  o.u.push_back(o.u.front());
  return o;
}

std::vector<std::vector<Point>> section_interior(const OGrid& o) {
  const int m_front = o.split[1] - o.split[0], n_upper = o.split[2] - o.split[1];
  const int m_back = o.split[3] - o.split[2], n_lower = o.split[4] - o.split[3];
  if (n_upper != n_lower || m_front != m_back)
    fail("section interior: needs as many cells on the lower side as on the upper ({} and {}) and round the trailing "
         "edge as round the leading edge ({} and {})",
         n_lower, n_upper, m_back, m_front);
  const auto& ring = o.ring.front();
  const int na = n_upper, nb = m_front, S = o.split[4];
  auto lower = [&](int a) { return ring[static_cast<std::size_t>(S - a)]; };
  auto upper = [&](int a) { return ring[static_cast<std::size_t>(o.split[1] + a)]; };
  auto front = [&](int b) { return ring[static_cast<std::size_t>(b)]; };
  auto back = [&](int b) { return ring[static_cast<std::size_t>(o.split[3] - b)]; };
  // Arc-length fractions along each edge, averaged over the opposite pair: transfinite
  // interpolation in them keeps the interior lines spaced as the edges' nodes.
  auto fractions = [](auto edge, int n) {
    std::vector<Real> f(static_cast<std::size_t>(n + 1), 0.0);
    for (int k = 1; k <= n; ++k) f[static_cast<std::size_t>(k)] = f[static_cast<std::size_t>(k - 1)] + (edge(k) - edge(k - 1)).norm();
    for (auto& v : f) v /= f.back();
    return f;
  };
  const auto fl = fractions(lower, na), fu = fractions(upper, na), ff = fractions(front, nb), fb = fractions(back, nb);
  std::vector<std::vector<Point>> x(static_cast<std::size_t>(na + 1), std::vector<Point>(static_cast<std::size_t>(nb + 1)));
  const Point c00 = lower(0), c10 = lower(na), c01 = upper(0), c11 = upper(na);
  for (int a = 0; a <= na; ++a)
    for (int b = 0; b <= nb; ++b) {
      const std::size_t ua = static_cast<std::size_t>(a), ub = static_cast<std::size_t>(b);
      const Real al = 0.5 * (fl[ua] + fu[ua]), be = 0.5 * (ff[ub] + fb[ub]);
      Point p = (1.0 - al) * front(b) + al * back(b) + (1.0 - be) * lower(a) + be * upper(a) -
                ((1.0 - al) * (1.0 - be) * c00 + al * (1.0 - be) * c10 + (1.0 - al) * be * c01 + al * be * c11);
      if (a == 0) p = front(b);
      if (a == na) p = back(b);
      if (b == 0) p = lower(a);
      if (b == nb) p = upper(a);
      x[ua][ub] = p;
    }
  return x;
}

}  // namespace narwhal::ogrid
