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

// The bounding-volume hierarchy over the wall faces.
class FaceTree {
 public:
  explicit FaceTree(const std::vector<Quad>& quads) : quads_(quads), order_(quads.size()) {
    for (std::size_t f = 0; f < quads.size(); ++f) {
      order_[f] = static_cast<int>(f);
      centre_.push_back(0.25 * (quads[f].x[0] + quads[f].x[1] + quads[f].x[2] + quads[f].x[3]));
    }
    nodes_.reserve(2 * quads.size() / kLeafFaces + 2);
    build(0, static_cast<int>(quads.size()));
  }

  // The nearest face to p and its distance; `hint`, a face likely near (or -1), is
  // measured first. Faces as near as the best are still visited (pruning is strict), so
  // that ties go to the lowest index.
  std::pair<Real, int> nearest(const Vec3& p, int hint) const {
    Real best = std::numeric_limits<Real>::infinity();
    int best_face = -1;
    auto visit_face = [&](int f) {
      if (box_distance(p, quads_[static_cast<std::size_t>(f)].lo, quads_[static_cast<std::size_t>(f)].hi) > best)
        return;
      const Real d = quad_distance(p, quads_[static_cast<std::size_t>(f)]);
      if (d < best || (d == best && f < best_face)) best = d, best_face = f;
    };
    if (hint >= 0) visit_face(hint);
    int stack[kMaxDepth];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[static_cast<std::size_t>(stack[--top])];
      if (box_distance(p, n.lo, n.hi) > best) continue;
      if (n.left < 0) {
        for (int q = n.first; q < n.first + n.count; ++q) visit_face(order_[static_cast<std::size_t>(q)]);
        continue;
      }
      const Node &l = nodes_[static_cast<std::size_t>(n.left)], &r = nodes_[static_cast<std::size_t>(n.right)];
      const Real dl = box_distance(p, l.lo, l.hi), dr = box_distance(p, r.lo, r.hi);
      const bool left_first = dl <= dr;
      // The nearer child on top of the stack, so it is searched first.
      const int far = left_first ? n.right : n.left, near = left_first ? n.left : n.right;
      if ((left_first ? dr : dl) <= best) stack[top++] = far;
      if ((left_first ? dl : dr) <= best) stack[top++] = near;
    }
    return {best, best_face};
  }

 private:
  static constexpr int kLeafFaces = 4;
  static constexpr int kMaxDepth = 128;  // median splits: depth log2(faces / 4) + 1
  struct Node {
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    int left = -1, right = -1;  // children, or -1 for a leaf
    int first = 0, count = 0;   // a leaf's faces: order_[first, first + count)
  };

  int build(int first, int count) {
    const int id = static_cast<int>(nodes_.size());
    nodes_.push_back({});
    Vec3 lo = quads_[static_cast<std::size_t>(order_[static_cast<std::size_t>(first)])].lo, hi = lo;
    Vec3 clo = centre_[static_cast<std::size_t>(order_[static_cast<std::size_t>(first)])], chi = clo;
    for (int q = first; q < first + count; ++q) {
      const std::size_t f = static_cast<std::size_t>(order_[static_cast<std::size_t>(q)]);
      lo = lo.cwiseMin(quads_[f].lo);
      hi = hi.cwiseMax(quads_[f].hi);
      clo = clo.cwiseMin(centre_[f]);
      chi = chi.cwiseMax(centre_[f]);
    }
    nodes_[static_cast<std::size_t>(id)].lo = lo;
    nodes_[static_cast<std::size_t>(id)].hi = hi;
    if (count <= kLeafFaces) {
      nodes_[static_cast<std::size_t>(id)].first = first;
      nodes_[static_cast<std::size_t>(id)].count = count;
      return id;
    }
    int axis = 0;
    (chi - clo).maxCoeff(&axis);
    const int half = count / 2;
    const auto begin = order_.begin() + first;
    std::nth_element(begin, begin + half, begin + count, [&](int a, int b) {
      const Real ca = centre_[static_cast<std::size_t>(a)][axis], cb = centre_[static_cast<std::size_t>(b)][axis];
      return ca < cb || (ca == cb && a < b);
    });
    const int left = build(first, half);
    const int right = build(first + half, count - half);
    nodes_[static_cast<std::size_t>(id)].left = left;
    nodes_[static_cast<std::size_t>(id)].right = right;
    return id;
  }

  const std::vector<Quad>& quads_;
  std::vector<int> order_;
  std::vector<Vec3> centre_;
  std::vector<Node> nodes_;
};

}  // namespace

Real wall_face_distance(const Grid& g, const WallFaceRef& f, const Vec3& p) {
  // face_quad puts the corners on the boundary plane whatever the cell's normal index.
  return quad_distance(p, face_quad(g.blocks[static_cast<std::size_t>(f.block)], f.side, f.cell));
}

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
  const FaceTree tree(quads);
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    int hint = -1;  // the previous cell's face: the neighbour's along i, mostly
    for_each_cell(b, [&](int i, int j, int k) {
      const auto [d, face] = tree.nearest(b.xc(i, j, k), hint);
      w.d[ib](i, j, k) = d;
      w.face[ib](i, j, k) = face;
      hint = face;
    });
  }
  return w;
}

}  // namespace narwhal
