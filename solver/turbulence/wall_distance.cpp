#include "turbulence/wall_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mesh/ghost_sweep.hpp"

namespace narwhal {

Real point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // Closest point by Voronoi regions of the triangle (vertices, edges, face).
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const Real denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

namespace {

struct Quad {
  Vec3 x[4];
  Vec3 lo, hi;  // bounding box
};

// Corner nodes of a boundary face, in cyclic order.
Quad face_quad(const Block& b, int side, const Index3& c) {
  const int d = side_dir(side);
  const int t1 = (d + 1) % 3, t2 = (d + 2) % 3;
  Index3 n = c;
  n[d] = side_high(side) ? b.n(d) : 0;
  Quad q;
  const Index3 e1 = unit(t1), e2 = unit(t2);
  q.x[0] = b.x(n);
  q.x[1] = b.x(add(n, e1));
  q.x[2] = b.x(add(add(n, e1), e2));
  q.x[3] = b.x(add(n, e2));
  q.lo = q.hi = q.x[0];
  for (const Vec3& v : q.x) {
    q.lo = q.lo.cwiseMin(v);
    q.hi = q.hi.cwiseMax(v);
  }
  return q;
}

// A warped quadrilateral has two triangulations; the distance to the nearer of the
// two keeps the result independent of which corner the block's indexing starts at, so
// mirror-image grids (whose mirrored blocks number their corners the other way round)
// get mirror-image wall distances.
Real quad_distance(const Vec3& p, const Quad& q) {
  return std::min(std::min(point_triangle_distance(p, q.x[0], q.x[1], q.x[2]),
                           point_triangle_distance(p, q.x[0], q.x[2], q.x[3])),
                  std::min(point_triangle_distance(p, q.x[0], q.x[1], q.x[3]),
                           point_triangle_distance(p, q.x[1], q.x[2], q.x[3])));
}

// Distance from p to an axis-aligned box (0 inside).
Real box_distance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return (p.cwiseMax(lo).cwiseMin(hi) - p).norm();
}

}  // namespace

WallDistance compute_wall_distance(const Grid& g) {
  WallDistance w;
  std::vector<Quad> quads;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    for (const Patch& p : b.patches) {
      if (p.type != BcType::Wall) continue;
      const PatchRange r = face_range(p);
      for_each_in(r, [&](Index3 c) {
        w.faces.push_back({static_cast<int>(ib), p.side, interior_cell(b, p.side, c, 1)});
        quads.push_back(face_quad(b, p.side, c));
      });
    }
  }
  const Real inf = std::numeric_limits<Real>::infinity();
  for (const Block& b : g.blocks) {
    w.d.emplace_back(b.ni, b.nj, b.nk, 0, inf);
    w.face.emplace_back(b.ni, b.nj, b.nk, 0, -1);
  }
  if (quads.empty()) return w;

  // Buckets: a uniform grid over the wall faces' bounding box, about one face per
  // bucket in each direction the walls extend in.
  Vec3 lo = quads[0].lo, hi = quads[0].hi;
  for (const Quad& q : quads) {
    lo = lo.cwiseMin(q.lo);
    hi = hi.cwiseMax(q.hi);
  }
  const Vec3 span = (hi - lo).cwiseMax(Vec3::Constant(1e-300));
  const Real per_dim = std::max<Real>(1.0, std::cbrt(static_cast<Real>(quads.size())));
  Index3 nb;
  Vec3 h;
  for (int m = 0; m < 3; ++m) {
    const bool flat = span[m] < 1e-9 * span.maxCoeff();
    nb[m] = flat ? 1 : std::clamp(static_cast<int>(std::ceil(per_dim * span[m] / span.maxCoeff() * 2.0)), 1, 256);
    h[m] = span[m] / nb[m];
  }
  auto bucket_of = [&](const Vec3& x, int m) {
    return std::clamp(static_cast<int>(std::floor((x[m] - lo[m]) / h[m])), 0, nb[m] - 1);
  };
  std::vector<std::vector<int>> buckets(static_cast<std::size_t>(nb[0]) * nb[1] * nb[2]);
  auto bucket_index = [&](int i, int j, int k) { return (static_cast<std::size_t>(k) * nb[1] + j) * nb[0] + i; };
  for (std::size_t f = 0; f < quads.size(); ++f) {
    const Vec3 c = 0.25 * (quads[f].x[0] + quads[f].x[1] + quads[f].x[2] + quads[f].x[3]);
    buckets[bucket_index(bucket_of(c, 0), bucket_of(c, 1), bucket_of(c, 2))].push_back(static_cast<int>(f));
  }
  // A face may stick out of its bucket by up to its own size: pad the bucket boxes.
  Vec3 pad = Vec3::Zero();
  for (const Quad& q : quads) pad = pad.cwiseMax(q.hi - q.lo);
  const Real pad_norm = pad.norm();
  Real h_active = inf;
  for (int m = 0; m < 3; ++m)
    if (nb[m] > 1) h_active = std::min(h_active, h[m]);
  if (!(h_active < inf)) h_active = 0.0;  // a single bucket: the first shell holds every face

  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    for_each_cell(b, [&](int i, int j, int k) {
      const Vec3 p = b.xc(i, j, k);
      Real best = inf;
      int best_face = -1;
      const Index3 home{bucket_of(p, 0), bucket_of(p, 1), bucket_of(p, 2)};
      const int max_shell = std::max({nb[0], nb[1], nb[2]});
      for (int s = 0; s <= max_shell; ++s) {
        // Every bucket of shell s or beyond lies at least (s - 1) buckets away
        // along an axis the walls extend in; its faces stick out by at most |pad|.
        if (s > 1 && (s - 1) * h_active - pad_norm >= best) break;
        Index3 from, to;
        for (int m = 0; m < 3; ++m) {
          from[m] = std::max(0, home[m] - s);
          to[m] = std::min(nb[m] - 1, home[m] + s);
        }
        for (int bk = from[2]; bk <= to[2]; ++bk)
          for (int bj = from[1]; bj <= to[1]; ++bj)
            for (int bi = from[0]; bi <= to[0]; ++bi) {
              if (std::max({std::abs(bi - home[0]), std::abs(bj - home[1]), std::abs(bk - home[2])}) != s) continue;
              const Vec3 blo = lo + Vec3(bi * h[0], bj * h[1], bk * h[2]) - pad;
              const Vec3 bhi = lo + Vec3((bi + 1) * h[0], (bj + 1) * h[1], (bk + 1) * h[2]) + pad;
              if (box_distance(p, blo, bhi) >= best) continue;
              for (int f : buckets[bucket_index(bi, bj, bk)]) {
                if (box_distance(p, quads[f].lo, quads[f].hi) >= best) continue;
                const Real df = quad_distance(p, quads[f]);
                if (df < best) {
                  best = df;
                  best_face = f;
                }
              }
            }
      }
      w.d[ib](i, j, k) = best;
      w.face[ib](i, j, k) = best_face;
    });
  }
  return w;
}

}  // namespace narwhal
