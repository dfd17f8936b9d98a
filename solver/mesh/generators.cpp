#include "mesh/generators.hpp"

#include <cmath>
#include <random>

#include "core/error.hpp"

namespace narwhal {

std::vector<Real> uniform_nodes(Real a, Real b, int n) {
  std::vector<Real> x(n + 1);
  for (int i = 0; i <= n; ++i) x[i] = a + (b - a) * i / n;
  return x;
}

namespace {
// Growth ratio r with ds (r^n - 1)/(r - 1) = L, by bisection (monotone in r).
Real growth_ratio(Real L, int n, Real ds) {
  if (ds * n > L * (1 + 1e-12)) fail("geometric spacing: first spacing {} too large for length {} with {} cells", ds, L, n);
  if (std::abs(ds * n - L) < 1e-14 * L) return 1.0;
  Real lo = 1.0 + 1e-12, hi = 2.0;
  auto total = [&](Real r) { return ds * (std::pow(r, n) - 1.0) / (r - 1.0); };
  while (total(hi) < L) hi *= 2.0;
  for (int it = 0; it < 200; ++it) {
    const Real mid = 0.5 * (lo + hi);
    (total(mid) < L ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
}  // namespace

std::vector<Real> geometric_nodes(Real a, Real b, int n, Real ds) {
  const Real r = growth_ratio(b - a, n, ds);
  std::vector<Real> x(n + 1);
  x[0] = a;
  Real h = ds;
  for (int i = 1; i <= n; ++i) {
    x[i] = x[i - 1] + h;
    h *= r;
  }
  x[n] = b;
  return x;
}

std::vector<Real> geometric_nodes_to_end(Real a, Real b, int n, Real ds_last) {
  auto y = geometric_nodes(0.0, b - a, n, ds_last);
  std::vector<Real> x(n + 1);
  for (int i = 0; i <= n; ++i) x[i] = b - y[n - i];
  x[0] = a;
  return x;
}

namespace {

// The nodes of [a, b] from those of its first half [a, (a + b) / 2] and their mirror image
// about the middle.
std::vector<Real> mirrored_about_middle(const std::vector<Real>& first_half, Real a, Real b) {
  const int h = static_cast<int>(first_half.size()) - 1, n = 2 * h;
  std::vector<Real> x(static_cast<std::size_t>(n + 1));
  for (int i = 0; i <= h; ++i) {
    x[static_cast<std::size_t>(i)] = first_half[static_cast<std::size_t>(i)];
    x[static_cast<std::size_t>(n - i)] = a + b - first_half[static_cast<std::size_t>(i)];
  }
  x[static_cast<std::size_t>(h)] = 0.5 * (a + b);
  return x;
}

}  // namespace

std::vector<Real> geometric_nodes_both_ends(Real a, Real b, int n, Real ds) {
  if (n % 2 != 0) fail("geometric_nodes_both_ends: the cell count {} must be even", n);
  return mirrored_about_middle(geometric_nodes(a, 0.5 * (a + b), n / 2, ds), a, b);
}

std::vector<Real> geometric_nodes_from_middle(Real a, Real b, int n, Real ds) {
  if (n % 2 != 0) fail("geometric_nodes_from_middle: the cell count {} must be even", n);
  // The first half grows from the middle back to a.
  std::vector<Real> x = mirrored_about_middle(geometric_nodes_to_end(a, 0.5 * (a + b), n / 2, ds), a, b);
  x.back() = b;  // a + b - a need not be b in floating point
  return x;
}

namespace {

// u(t) = (1 + tanh(delta (t - 1/2)) / tanh(delta / 2)) / 2 clusters both ends alike,
// u'(0) = u'(1) = delta / sinh(delta); s = u / (A + (1 - A) u) moves nodes towards one end
// (s'(0) = u'(0) / A, s'(1) = A u'(1)).
Real stretched(Real t, Real delta, Real a) {
  const Real u = 0.5 * (1.0 + std::tanh(delta * (t - 0.5)) / std::tanh(0.5 * delta));
  return u / (a + (1.0 - a) * u);
}

}  // namespace

std::vector<Real> two_sided_nodes(Real a, Real b, int n, Real ds_a, Real ds_b) {
  const Real span = b - a;
  if (n < 2 || !(span > 0.0) || !(ds_a > 0.0) || !(ds_b > 0.0))
    fail("two_sided_nodes: need n >= 2, b > a and positive spacings (n = {}, [{}, {}], {}, {})", n, a, b, ds_a, ds_b);
  const Real s0 = ds_a / span, s1 = ds_b / span;
  if (!(std::sqrt(s0 * s1) * n < 1.0))
    fail("two_sided_nodes: end spacings {} and {} are not smaller than the mean spacing {} of [{}, {}] in {} cells",
         ds_a, ds_b, span / n, a, b, n);
  // Start: delta / sinh(delta) = n sqrt(s0 s1) (the ends' mean), A = sqrt(s1 / s0).
  const Real target = n * std::sqrt(s0 * s1);
  Real lo = 1e-8, hi = 1.0;
  while (hi / std::sinh(hi) > target) hi *= 2.0;
  for (int it = 0; it < 200; ++it) {
    const Real mid = 0.5 * (lo + hi);
    (mid / std::sinh(mid) > target ? lo : hi) = mid;
  }
  // Newton on (log delta, log A) for the exact discrete end spacings.
  Real x[2] = {std::log(0.5 * (lo + hi)), 0.5 * std::log(s1 / s0)};
  auto residual = [&](const Real* v, Real* f) {
    const Real delta = std::exp(v[0]), aa = std::exp(v[1]);
    f[0] = std::log(stretched(1.0 / n, delta, aa) / s0);
    f[1] = std::log((1.0 - stretched(1.0 - 1.0 / n, delta, aa)) / s1);
  };
  for (int it = 0; it < 50; ++it) {
    Real f[2], jac[2][2];
    residual(x, f);
    if (std::abs(f[0]) + std::abs(f[1]) < 1e-13) break;
    for (int c = 0; c < 2; ++c) {
      Real y[2] = {x[0], x[1]}, g[2];
      const Real h = 1e-7;
      y[c] += h;
      residual(y, g);
      jac[0][c] = (g[0] - f[0]) / h;
      jac[1][c] = (g[1] - f[1]) / h;
    }
    const Real det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
    if (det == 0.0) break;
    x[0] -= (jac[1][1] * f[0] - jac[0][1] * f[1]) / det;
    x[1] -= (-jac[1][0] * f[0] + jac[0][0] * f[1]) / det;
  }
  std::vector<Real> nodes(n + 1);
  const Real delta = std::exp(x[0]), aa = std::exp(x[1]);
  for (int i = 0; i <= n; ++i) nodes[i] = a + span * stretched(static_cast<Real>(i) / n, delta, aa);
  nodes[0] = a;
  nodes[n] = b;
  Real f[2];
  residual(x, f);
  if (!(std::abs(f[0]) < 1e-8 && std::abs(f[1]) < 1e-8))
    fail("two_sided_nodes: no stretching of [{}, {}] in {} cells has end spacings {} and {}", a, b, n, ds_a, ds_b);
  return nodes;
}

Block make_box(const std::string& name, const std::vector<Real>& xs, const std::vector<Real>& ys,
               const std::vector<Real>& zs) {
  Block b(name, static_cast<int>(xs.size()) - 1, static_cast<int>(ys.size()) - 1, static_cast<int>(zs.size()) - 1);
  for (int k = 0; k <= b.nk; ++k)
    for (int j = 0; j <= b.nj; ++j)
      for (int i = 0; i <= b.ni; ++i) b.x(i, j, k) = Vec3(xs[i], ys[j], zs[k]);
  for (int s = 0; s < 6; ++s) {
    Patch p;
    p.side = s;
    p.lo = {0, 0, 0};
    p.hi = b.dims();
    p.label = side_name(s);
    b.patches.push_back(p);
  }
  return b;
}

Grid make_flat_plate(const FlatPlateSpec& s) {
  if (s.n_runup < 1 || s.n_plate < 1 || s.n_normal < 1) fail("flat plate grid: cell counts must be >= 1");
  auto xr = geometric_nodes_to_end(-s.x_runup, 0.0, s.n_runup, s.dx_le);
  std::vector<Real> xp;
  if (s.dx_te > 0.0) {
    // Two-sided: geometric from both ends meeting in the middle of the plate.
    const int n1 = s.n_plate / 2;
    auto a = geometric_nodes(0.0, 0.5 * s.length, n1, s.dx_le);
    auto b = geometric_nodes_to_end(0.5 * s.length, s.length, s.n_plate - n1, s.dx_te);
    xp = a;
    xp.insert(xp.end(), b.begin() + 1, b.end());
  } else {
    xp = geometric_nodes(0.0, s.length, s.n_plate, s.dx_le);
  }
  std::vector<Real> xs = xr;
  xs.insert(xs.end(), xp.begin() + 1, xp.end());
  auto ys = geometric_nodes(0.0, s.height, s.n_normal, s.dy_wall);
  auto zs = uniform_nodes(0.0, s.width, 1);
  Block b = make_box("plate", xs, ys, zs);
  // Split the jmin side at the leading edge.
  std::vector<Patch> patches;
  for (auto p : b.patches) {
    if (p.side == 2) {
      Patch runup = p, plate = p;
      runup.hi[0] = s.n_runup;
      runup.label = "runup";
      plate.lo[0] = s.n_runup;
      plate.label = "plate";
      patches.push_back(runup);
      patches.push_back(plate);
      continue;
    }
    static const char* labels[6] = {"inlet", "outlet", "", "top", "side_lo", "side_hi"};
    p.label = labels[p.side];
    patches.push_back(p);
  }
  b.patches = patches;
  Grid g;
  g.blocks.push_back(std::move(b));
  return g;
}

Block make_perturbed_box(const std::string& name, int n, Real amplitude) {
  auto u = uniform_nodes(0.0, 1.0, n);
  Block b = make_box(name, u, u, u);
  const Real tp = 2.0 * M_PI;
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const Real X = u[i], Y = u[j], Z = u[k];
        const Real s = std::sin(tp * X) * std::sin(tp * Y) * std::sin(tp * Z);
        // Different shapes per component so that no direction stays Cartesian.
        const Real s2 = std::sin(M_PI * X) * std::sin(tp * Y) * std::sin(M_PI * Z);
        b.x(i, j, k) = Vec3(X + amplitude * s, Y + amplitude * (0.8 * s + 0.5 * s2), Z + amplitude * 0.6 * s2);
      }
  return b;
}

void randomly_perturb(Block& b, Real fraction, std::uint64_t seed, bool move_boundary) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> U(-1.0, 1.0);
  for (int k = 0; k <= b.nk; ++k)
    for (int j = 0; j <= b.nj; ++j)
      for (int i = 0; i <= b.ni; ++i) {
        const bool boundary = i == 0 || j == 0 || k == 0 || i == b.ni || j == b.nj || k == b.nk;
        if (boundary && !move_boundary) continue;
        // Local spacing: shortest edge to an existing neighbour node.
        Real h = 1e300;
        for (int d = 0; d < 3; ++d) {
          Index3 a{i, j, k}, c{i, j, k};
          if (a[d] > 0) {
            a[d] -= 1;
            h = std::min(h, (b.x(a) - b.x(i, j, k)).norm());
          }
          if (c[d] < b.n(d)) {
            c[d] += 1;
            h = std::min(h, (b.x(c) - b.x(i, j, k)).norm());
          }
        }
        b.x(i, j, k) += fraction * h * Vec3(U(rng), U(rng), U(rng));
      }
}

Block extract_block(const Block& parent, const std::string& name, const Index3& lo, const Index3& hi) {
  Block b(name, hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  for (int k = 0; k <= b.nk; ++k)
    for (int j = 0; j <= b.nj; ++j)
      for (int i = 0; i <= b.ni; ++i) b.x(i, j, k) = parent.x(i + lo[0], j + lo[1], k + lo[2]);
  for (const auto& p : parent.patches) {
    const int d = side_dir(p.side);
    const bool on_side = side_high(p.side) ? hi[d] == parent.n(d) : lo[d] == 0;
    if (!on_side) continue;
    Patch q = p;
    bool empty = false;
    for (int t = 0; t < 3; ++t) {
      if (t == d) continue;
      q.lo[t] = std::max(p.lo[t], lo[t]) - lo[t];
      q.hi[t] = std::min(p.hi[t], hi[t]) - lo[t];
      if (q.lo[t] >= q.hi[t]) empty = true;
    }
    if (!empty) b.patches.push_back(q);
  }
  return b;
}

Block reorient_block(const Block& b, const Index3& perm, const Index3& sign) {
  Eigen::Matrix3i P = Eigen::Matrix3i::Zero();
  for (int m = 0; m < 3; ++m) P(m, perm[m]) = sign[m];
  if (P.determinant() != 1) fail("reorient_block: the index map must be a proper rotation (determinant +1)");
  Block r(b.name, b.n(perm[0]), b.n(perm[1]), b.n(perm[2]));
  for (int k = 0; k <= r.nk; ++k)
    for (int j = 0; j <= r.nj; ++j)
      for (int i = 0; i <= r.ni; ++i) {
        const Index3 nw{i, j, k};
        Index3 old{};
        for (int m = 0; m < 3; ++m) old[perm[m]] = sign[m] > 0 ? nw[m] : b.n(perm[m]) - nw[m];
        r.x(i, j, k) = b.x(old);
      }
  for (const auto& p : b.patches) {
    const int d = side_dir(p.side);
    Patch q = p;
    for (int m = 0; m < 3; ++m) {
      const int o = perm[m];
      if (o == d) {
        const bool high = side_high(p.side) != (sign[m] < 0);
        q.side = 2 * m + (high ? 1 : 0);
        q.lo[m] = q.hi[m] = 0;
      } else if (sign[m] > 0) {
        q.lo[m] = p.lo[o];
        q.hi[m] = p.hi[o];
      } else {
        q.lo[m] = b.n(o) - p.hi[o];
        q.hi[m] = b.n(o) - p.lo[o];
      }
    }
    r.patches.push_back(q);
  }
  return r;
}

}  // namespace narwhal

namespace narwhal {
Grid split_blocks(const Grid& g, const Index3& parts, bool rotate) {
  static const Index3 perms[4] = {{0, 1, 2}, {1, 0, 2}, {2, 0, 1}, {0, 1, 2}};
  static const Index3 signs[4] = {{1, 1, 1}, {-1, 1, 1}, {1, 1, 1}, {-1, -1, 1}};
  Grid out;
  int counter = 0;
  for (const Block& b : g.blocks) {
    std::array<std::vector<int>, 3> cuts;
    for (int d = 0; d < 3; ++d) {
      if (parts[d] < 1 || parts[d] > b.n(d))
        fail("split: block '{}' has {} cells in direction {}, cannot make {} parts", b.name, b.n(d), "ijk"[d],
             parts[d]);
      for (int p = 0; p <= parts[d]; ++p) cuts[d].push_back(b.n(d) * p / parts[d]);
    }
    for (int pk = 0; pk < parts[2]; ++pk)
      for (int pj = 0; pj < parts[1]; ++pj)
        for (int pi = 0; pi < parts[0]; ++pi) {
          const Index3 lo{cuts[0][pi], cuts[1][pj], cuts[2][pk]};
          const Index3 hi{cuts[0][pi + 1], cuts[1][pj + 1], cuts[2][pk + 1]};
          Block sub = extract_block(b, fmt::format("{}_{}_{}_{}", b.name, pi, pj, pk), lo, hi);
          if (rotate) {
            const int r = counter % 4;
            sub = reorient_block(sub, perms[r], signs[r]);
          }
          ++counter;
          out.blocks.push_back(std::move(sub));
        }
  }
  return out;
}
}  // namespace narwhal
