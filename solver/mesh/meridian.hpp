#pragma once
// The surface of a body of revolution as the grid generators see it: the meridian by arc
// length, surface points, the pole squares' diamonds, the azimuths of the sectors and the
// wall lines' extrusion. Shared by the plain body grids (body_of_revolution.hpp) and the
// appended SUBOFF grids (appended_suboff.hpp), so that both place the same nodes alike.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "mesh/block.hpp"
#include "mesh/body_of_revolution.hpp"
#include "mesh/generators.hpp"

namespace narwhal::revolution {

inline constexpr Real kPi = std::numbers::pi;

// The meridian by arc length s from the nose: (x, r) and the unit tangent
// (dx/ds, dr/ds), from a dense sampling in t with x = L (1 - cos pi t) / 2, which puts
// r ~ t at a blunt end so that the samples resolve the poles. The tangent comes from
// dx/dt (exact) and dr/dt (central differences, r continued oddly through the poles),
// so that at a blunt pole it is exactly along the radius and the wall line leaving
// the pole is exactly the axis.
class Meridian {
 public:
  explicit Meridian(const BodyProfile& p) {
    constexpr int n = 40000;
    const Real h = 1.0 / n;
    x_.resize(n + 1);
    r_.resize(n + 1);
    s_.resize(n + 1);
    tx_.resize(n + 1);
    tr_.resize(n + 1);
    for (int m = 0; m <= n; ++m) {
      x_[m] = 0.5 * p.length * (1.0 - std::cos(kPi * m * h));
      r_[m] = m == 0 || m == n ? 0.0 : p.radius(x_[m]);
      if (!(r_[m] >= 0.0) || !std::isfinite(r_[m]))
        fail("body profile '{}': radius {} at x = {} (expected finite and >= 0)", p.name, r_[m], x_[m]);
      s_[m] = m == 0 ? 0.0 : s_[m - 1] + std::hypot(x_[m] - x_[m - 1], r_[m] - r_[m - 1]);
    }
    for (int m = 0; m <= n; ++m) {
      const Real dx = 0.5 * p.length * kPi * std::sin(kPi * m * h);
      const Real before = m == 0 ? -r_[1] : r_[m - 1], after = m == n ? -r_[n - 1] : r_[m + 1];
      const Real dr = (after - before) / (2.0 * h);
      const Real norm = std::hypot(dx, dr);
      tx_[m] = m == 0 || m == n ? 0.0 : dx / norm;
      tr_[m] = dr / norm;
    }
    // N(s) = integral of the normal (-dr/ds, dx/ds) from the nose, by the trapezoidal rule.
    nx_int_.assign(n + 1, 0.0);
    nr_int_.assign(n + 1, 0.0);
    for (int m = 1; m <= n; ++m) {
      const Real ds = s_[m] - s_[m - 1];
      nx_int_[m] = nx_int_[m - 1] - 0.5 * ds * (tr_[m] + tr_[m - 1]);
      nr_int_[m] = nr_int_[m - 1] + 0.5 * ds * (tx_[m] + tx_[m - 1]);
    }
  }
  Real length() const { return s_.back(); }

  // The meridian's outward unit normal (n_x, n_r) averaged over arc lengths
  // [s - a, s + a], the meridian continued through each pole onto the opposite one
  // (n_r changes sign there, so the mean at a pole is along the axis).
  std::array<Real, 2> averaged_normal(Real s, Real a) const {
    if (a <= 0.0) {
      const auto [x, r, tx, tr] = at(s);
      return {-tr, tx};
    }
    const auto lo = normal_integral(s - a), hi = normal_integral(s + a);
    const Real nx = hi[0] - lo[0], nr = hi[1] - lo[1], norm = std::hypot(nx, nr);
    return {nx / norm, nr / norm};
  }

  // (x, r, dx/ds, dr/ds) at arc length s.
  std::array<Real, 4> at(Real s) const {
    const auto [m, w] = locate(s);
    auto mix = [&](const std::vector<Real>& v) { return v[m - 1] + w * (v[m] - v[m - 1]); };
    const Real tx = mix(tx_), tr = mix(tr_), norm = std::hypot(tx, tr);
    return {mix(x_), mix(r_), tx / norm, tr / norm};
  }

 private:
  // The sample interval [m - 1, m] holding s, and the weight of sample m.
  std::pair<std::size_t, Real> locate(Real s) const {
    s = std::clamp(s, 0.0, length());
    const auto it = std::upper_bound(s_.begin(), s_.end(), s);
    const std::size_t m = std::min<std::size_t>(std::max<std::ptrdiff_t>(it - s_.begin(), 1), s_.size() - 1);
    const Real ds = s_[m] - s_[m - 1];
    return {m, ds > 0.0 ? (s - s_[m - 1]) / ds : 0.0};
  }
  // N(s) for -S <= s <= 2 S: beyond a pole the opposite meridian, mirrored in r.
  std::array<Real, 2> normal_integral(Real s) const {
    const Real S = length();
    auto inside = [&](Real u) {
      const auto [m, w] = locate(u);
      return std::array<Real, 2>{nx_int_[m - 1] + w * (nx_int_[m] - nx_int_[m - 1]),
                                 nr_int_[m - 1] + w * (nr_int_[m] - nr_int_[m - 1])};
    };
    if (s < 0.0) {
      const auto f = inside(std::min(-s, S));
      return {-f[0], f[1]};
    }
    if (s > S) {
      const auto total = inside(S), back = inside(std::max(2.0 * S - s, 0.0));
      return {total[0] + (total[0] - back[0]), total[1] - (total[1] - back[1])};
    }
    return inside(s);
  }

  std::vector<Real> x_, r_, s_, tx_, tr_, nx_int_, nr_int_;
};

struct SurfacePoint {
  Vec3 x;                    // position
  Real s;                    // arc length from the nose
  std::array<Real, 2> dir;   // azimuth (cos phi, sin phi)
  Vec3 far;                  // the direction the wall line takes far out (polar angle pi s / S)
};

// The surface point at arc length s from the nose and azimuth (cos phi, sin phi).
inline SurfacePoint surface(const Meridian& m, Real s, const std::array<Real, 2>& dir) {
  const auto [x, r, tx, tr] = m.at(s);
  const auto [c, sn] = dir;
  const Real theta = kPi * std::clamp(s / m.length(), 0.0, 1.0);
  return {Vec3(x, r * c, r * sn), s, dir, Vec3(-std::cos(theta), std::sin(theta) * c, std::sin(theta) * sn)};
}

// The point of polar-projection coordinates (X, Y) around the nose (tail = false) or
// the tail, where s = |(X, Y)| is measured from that pole.
inline SurfacePoint near_pole(const Meridian& m, const std::array<Real, 2>& xy, bool tail) {
  const Real rho = std::hypot(xy[0], xy[1]);
  const std::array<Real, 2> dir = rho > 0.0 ? std::array<Real, 2>{xy[0] / rho, xy[1] / rho} : std::array<Real, 2>{1, 0};
  return surface(m, tail ? m.length() - rho : rho, dir);
}

// Azimuths are multiples of 90 / cells_around degrees: index m in [0, 4 na] (m and
// m + 4 na the same). Every block computes a shared node from the same integer, so
// that the blocks' common faces coincide to the bit; the sector boundaries (m a
// multiple of na) get exact cosines and sines.
struct Azimuth {
  int na;
  Real phi(int m) const { return (m % (4 * na)) * (0.5 * kPi / na); }
  std::array<Real, 2> unit(int m) const {
    m %= 4 * na;
    if (m % na == 0) {
      static constexpr std::array<std::array<Real, 2>, 4> axes{{{1, 0}, {0, 1}, {-1, 0}, {0, -1}}};
      return axes[static_cast<std::size_t>(m / na)];
    }
    return {std::cos(phi(m)), std::sin(phi(m))};
  }
};

// The point of the diamond |X| + |Y| = rho at azimuth index m, in (X, Y).
inline std::array<Real, 2> diamond(Real rho, const Azimuth& az, int m) {
  const auto [c, s] = az.unit(m);
  const Real re = rho / (std::abs(c) + std::abs(s));
  return {re * c, re * s};
}

// A pole square's node (ia, ib) in polar-projection coordinates: the transfinite
// interpolation of the diamond's edges. Corners c0..c3 at azimuths 0, 90, 180, 270
// degrees; square coordinates (a, b) with (0,0) = c3, (1,0) = c0, (1,1) = c1, (0,1) = c2;
// each edge's nodes where the sectors' meridians meet it (the same azimuth indices), and
// the edge nodes exactly as the sectors place them.
inline std::array<Real, 2> pole_square_point(Real rho, const Azimuth& az, int ia, int ib) {
  const int na = az.na;
  auto edge = [&](int ma) { return diamond(rho, az, ma); };
  const Real a = static_cast<Real>(ia) / na, c = static_cast<Real>(ib) / na;
  const auto b0 = edge(3 * na + ia), b1 = edge(2 * na - ia);  // c3 -> c0, c2 -> c1
  const auto a0 = edge(3 * na - ib), a1 = edge(ib);           // c3 -> c2, c0 -> c1
  const auto k3 = edge(3 * na), k0 = edge(0), k1 = edge(na), k2 = edge(2 * na);
  std::array<Real, 2> xy{};
  for (int d = 0; d < 2; ++d)
    xy[d] = (1 - c) * b0[d] + c * b1[d] + (1 - a) * a0[d] + a * a1[d] -
            ((1 - a) * (1 - c) * k3[d] + a * (1 - c) * k0[d] + a * c * k1[d] + (1 - a) * c * k2[d]);
  if (ib == 0) xy = b0;
  if (ib == na) xy = b1;
  if (ia == 0) xy = a0;
  if (ia == na) xy = a1;
  return xy;
}

// A pole square's block ("nose" or "tail"), node (ia, ib, k) = node(p, k) with p the
// surface point of square node (ia, ib). Right-handed with k outward: (i, j) = (b, a) at
// the nose, (a, b) at the tail.
template <class Node>
Block make_pole_square(const Meridian& m, const Azimuth& az, Real rho, int nk, bool tail, Node&& node) {
  const int na = az.na;
  Block b(tail ? "tail" : "nose", na, na, nk);
  for (int ia = 0; ia <= na; ++ia)
    for (int ib = 0; ib <= na; ++ib) {
      const SurfacePoint p = near_pole(m, pole_square_point(rho, az, ia, ib), tail);
      for (int k = 0; k <= nk; ++k) {
        if (tail)
          b.x(ia, ib, k) = node(p, k);
        else
          b.x(ib, ia, k) = node(p, k);
      }
    }
  return b;
}

// Smooth step 0 -> 1 over [0, 1].
inline Real smoothstep(Real t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

// The wall lines. At distance d from the wall a line's direction is the body normal
// averaged over the arc lengths within d of its foot, turned over half a body length
// towards the direction of polar angle pi s / S (s the arc length from the nose, S the
// meridian's): forward from the nose, radial at mid-length, aft from the tail.
// - At the wall the average is the normal itself: the lines leave orthogonally.
// - Exact normals cross at the radius of curvature of a concave stretch (SUBOFF's
//   afterbody before its cap, about 0.09 L); their average over a window growing with
//   d turns by at most half the stretch's total turning, so neighbours cannot meet.
// - Monotone along the meridian, so lines from a slender nose do not cross (rays
//   from the centre did: a 6:1 spheroid folded).
class Extrusion {
 public:
  Extrusion(const BodyGridSpec& s, const Meridian& m, Real length)
      : meridian_(m),
        blend_(0.5 * length),
        d_(geometric_nodes(0.0, s.far_field * length, s.cells_normal, s.first_spacing)) {}
  int cells() const { return static_cast<int>(d_.size()) - 1; }
  Vec3 node(const SurfacePoint& p, int k) const {
    const Real d = d_[static_cast<std::size_t>(k)];
    return p.x + d * direction(p, d);
  }
  // The unit direction of the wall line from p at distance d.
  Vec3 direction(const SurfacePoint& p, Real d) const {
    const Real w = smoothstep(d / blend_);
    const auto [nx, nr] = meridian_.averaged_normal(p.s, std::min(d, meridian_.length()));
    const Vec3 n(nx, nr * p.dir[0], nr * p.dir[1]);
    return ((1.0 - w) * n + w * p.far).normalized();
  }

 private:
  const Meridian& meridian_;
  Real blend_;
  std::vector<Real> d_;
};

}  // namespace narwhal::revolution
