#include "motion/grid_motion.hpp"

#include <algorithm>

#include "core/error.hpp"

namespace narwhal {

Real hexahedron_volume(const std::array<Vec3, 8>& n) {
  auto x = [&](int p, int q, int r) -> const Vec3& { return n[p + 2 * q + 4 * r]; };
  // The faces as compute_metrics orients them (§2.2), at p, q or r = 0 and 1.
  auto term = [&](int d, int s) {
    Vec3 a, b, c, e;
    if (d == 0) {
      a = x(s, 0, 0), b = x(s, 1, 0), c = x(s, 1, 1), e = x(s, 0, 1);
    } else if (d == 1) {
      a = x(0, s, 0), b = x(0, s, 1), c = x(1, s, 1), e = x(1, s, 0);
    } else {
      a = x(0, 0, s), b = x(1, 0, s), c = x(1, 1, s), e = x(0, 1, s);
    }
    const Vec3 S = 0.5 * (c - a).cross(e - b);
    return (0.25 * (a + b + c + e)).dot(S);
  };
  Real v = 0.0;
  for (int d = 0; d < 3; ++d) v += term(d, 1) - term(d, 0);
  return v / 3.0;
}

Real swept_volume(const GhostArray<Vec3>& from, const GhostArray<Vec3>& to, int d, const Index3& f) {
  // The sweep takes the place of direction d (old position at 0, new at 1), the face's
  // own node offsets the other two: the hexahedron is right-handed when the face moves
  // towards +S.
  std::array<Vec3, 8> n;
  for (int r = 0; r < 2; ++r)
    for (int q = 0; q < 2; ++q)
      for (int p = 0; p < 2; ++p) {
        const int o[3] = {p, q, r};
        Index3 node = f;
        for (int t = 0; t < 3; ++t)
          if (t != d) node[t] += o[t];
        n[p + 2 * q + 4 * r] = (o[d] ? to : from)(node);
      }
  return hexahedron_volume(n);
}

MovingGrid::MovingGrid(Grid& g, const Vec3& pivot) : g_(g), pivot_(pivot) {
  x0_.reserve(g.blocks.size());
  swept_.resize(g.blocks.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    x0_.push_back(b.x);
    built_extents_.push_back(node_extent(b));
    previous_x_.push_back(b.x);  // the layout; its values are set by each move
    for (int d = 0; d < 3; ++d) swept_[ib][d] = b.kt[d];  // the face layout, ghosts included
    swept_n_.push_back(swept_[ib]);
  }
}

void MovingGrid::reshape(std::vector<GhostArray<Vec3>> reference) {
  if (reference.size() != x0_.size())
    fail("MovingGrid: a new shape has {} blocks, the grid {}", reference.size(), x0_.size());
  for (std::size_t ib = 0; ib < x0_.size(); ++ib)
    if (reference[ib].raw().size() != x0_[ib].raw().size() || reference[ib].ni() != x0_[ib].ni() ||
        reference[ib].nj() != x0_[ib].nj() || reference[ib].nk() != x0_[ib].nk())
      fail("MovingGrid: a new shape's block {} ('{}') has another layout than the grid's", ib, g_.blocks[ib].name);
  x0_ = std::move(reference);
}

std::vector<std::array<double, 6>> MovingGrid::reference_extents() const { return built_extents_; }

void MovingGrid::place_at(const RigidPose& pose) {
  for (std::size_t ib = 0; ib < g_.blocks.size(); ++ib) {
    Block& b = g_.blocks[ib];
    auto& x0 = x0_[ib].raw();
    auto& x = b.x.raw();
    for (std::size_t n = 0; n < x.size(); ++n) x[n] = pose.apply(x0[n], pivot_);
    compute_metrics(b);
  }
  moved_ = false;
}

void MovingGrid::move_to(const RigidMotionSample& m, Real dt, const BdfCoefficients& c, bool new_step) {
  if (new_step) {
    // The present nodes and sweeps become t^n's; b.x keeps its layout and is rewritten below.
    for (std::size_t ib = 0; ib < g_.blocks.size(); ++ib) {
      std::swap(previous_x_[ib], g_.blocks[ib].x);
      std::swap(swept_n_[ib], swept_[ib]);
    }
    have_sweep_n_ = moved_;
  } else if (!moved_) {
    fail("MovingGrid: a move within a step needs the step's first move");
  }
  const RigidVelocity motion{true, m.velocity, m.angular_velocity, pivot_ + m.pose.displacement};
  for (std::size_t ib = 0; ib < g_.blocks.size(); ++ib) {
    Block& b = g_.blocks[ib];
    b.motion = motion;
    const GhostArray<Vec3>& old = previous_x_[ib];
    auto& x0 = x0_[ib].raw();
    auto& x = b.x.raw();
    for (std::size_t n = 0; n < x.size(); ++n) x[n] = m.pose.apply(x0[n], pivot_);
    compute_metrics(b);
    for (int d = 0; d < 3; ++d) {
      auto& kt = b.kt[d];
      auto& swept = swept_[ib][d];
      const auto& swept_n = swept_n_[ib][d];
      // Every face whose four nodes exist (the range compute_metrics fills).
      for (int k = -kGhost; k < kt.nk() + kGhost; ++k)
        for (int j = -kGhost; j < kt.nj() + kGhost; ++j)
          for (int i = -kGhost; i < kt.ni() + kGhost; ++i) {
            const Index3 f{i, j, k};
            bool inside = f[d] <= b.n(d) + kGhost;
            for (int t = 0; t < 3; ++t)
              if (t != d && f[t] + 1 > b.n(t) + kGhost) inside = false;
            if (!inside) continue;
            // A collapsed face (a ghost face where extrapolated nodes meet) stays collapsed
            // under a rigid motion and sweeps nothing: no round-off speed on zero area.
            const Real dv = b.S[d](f).squaredNorm() > 0.0 ? swept_volume(old, b.x, d, f) : 0.0;
            kt(f) = -(c.c0 * dv - (have_sweep_n_ ? c.c2 * swept_n(f) : 0.0)) / dt;
            swept(f) = dv;
          }
    }
  }
  moved_ = true;
}

}  // namespace narwhal
