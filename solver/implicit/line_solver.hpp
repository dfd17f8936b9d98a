#pragma once
// Line relaxation of a block's linearized equations (NUMERICS §6.5, §8.6):
// every line of one index direction solved exactly (block-tridiagonal, N x N blocks,
// Thomas algorithm) with the latest values of the neighbouring lines, the lines
// swept in order (forward, then backward: symmetric line Gauss-Seidel).
//
// Why lines: near a wall the cells are thin (aspect ratios 1e3 to 1e5 on turbulent
// grids) and the equations couple a cell far more strongly to its wall-normal
// neighbours than to any other. Point Gauss-Seidel removes an error that is smooth
// across the boundary layer only slowly, and the more slowly the finer the grid; a
// line solve treats that coupling exactly, and the sweep order treats convection
// along the other directions as point Gauss-Seidel does. Measurements:
// turbulence/DESIGN.md.
//
// The factorization depends on the matrices only: it is computed once per assembly
// and reused by every sweep, so a sweep costs little more than a point sweep.
#include <vector>

#include <Eigen/Dense>

#include "mesh/block.hpp"

namespace narwhal {

// The direction whose faces couple the block's cells most strongly by geometry: the
// largest sum over the cells of |S_d|^2 / V (the diffusive coupling per unit
// diffusivity, dominated by the thinnest cells). Never the invariant direction of a
// block (Block::invariant_dir), nor one with a single cell when another has more.
int stiffest_direction(const Block& b);

// Rows along a line of direction L, for every cell c of the block:
//   diag(c) x(c) + lower(c) x(c - e_L) + upper(c) x(c + e_L) = rhs(c),
// rhs holding everything else (the residual and the other lines' latest values).
template <int N>
class LineFactorization {
 public:
  using Mat = Eigen::Matrix<Real, N, N>;
  using Vec = Eigen::Matrix<Real, N, 1>;

  int direction() const { return dir_; }

  // diag(c), lower(c), upper(c): functions of the cell returning Mat. The lower
  // coupling of a line's first cell and the upper one of its last are not part of
  // the line (they reach the ghosts; the caller puts them into rhs).
  template <class Diag, class Lower, class Upper>
  void factorize(const Block& b, int dir, Diag diag, Lower lower, Upper upper) {
    dir_ = dir;
    if (pivot_inv_.ni() != b.ni || pivot_inv_.nj() != b.nj || pivot_inv_.nk() != b.nk) {
      pivot_inv_.resize(b.ni, b.nj, b.nk, 0, Mat::Identity());
      elim_.resize(b.ni, b.nj, b.nk, 0, Mat::Zero());
    }
    const Index3 e = unit(dir);
    for_each_cell(b, [&](int i, int j, int k) {
      const Index3 c{i, j, k};
      // Cells are visited with the line index increasing: the previous pivot is ready.
      Mat pivot = diag(c);
      if (c[dir] > 0) {
        const Index3 prev = add(c, e, -1);
        elim_(c) = lower(c) * pivot_inv_(prev);
        pivot.noalias() -= elim_(c) * upper(prev);
      }
      pivot_inv_(c) = pivot.inverse();
    });
  }

  // One sweep over the lines in lexicographic order of the other two indices
  // (reversed when !forward). rhs(c): the right-hand side of row c with the current
  // x of the other lines; upper(c) as in factorize.
  template <class Rhs, class Upper, class X>
  void sweep(const Block& b, bool forward, Rhs rhs, Upper upper, X& x) const {
    const int L = dir_, p = (L + 1) % 3, q = (L + 2) % 3;
    const int n = b.n(L), np = b.n(p), nq = b.n(q);
    const Index3 e = unit(L);
    static thread_local std::vector<Vec> y;
    y.resize(static_cast<std::size_t>(n));
    auto solve_line = [&](int ip, int iq) {
      Index3 c{};
      c[p] = ip;
      c[q] = iq;
      for (int t = 0; t < n; ++t) {
        c[L] = t;
        y[static_cast<std::size_t>(t)] = rhs(c);
        if (t > 0) y[static_cast<std::size_t>(t)].noalias() -= elim_(c) * y[static_cast<std::size_t>(t - 1)];
      }
      for (int t = n - 1; t >= 0; --t) {
        c[L] = t;
        Vec r = y[static_cast<std::size_t>(t)];
        if (t < n - 1) r.noalias() -= upper(c) * x(add(c, e));
        x(c) = pivot_inv_(c) * r;
      }
    };
    if (forward) {
      for (int iq = 0; iq < nq; ++iq)
        for (int ip = 0; ip < np; ++ip) solve_line(ip, iq);
    } else {
      for (int iq = nq - 1; iq >= 0; --iq)
        for (int ip = np - 1; ip >= 0; --ip) solve_line(ip, iq);
    }
  }

 private:
  int dir_ = 0;
  GhostArray<Mat> pivot_inv_;  // inverse pivots of the eliminated lines
  GhostArray<Mat> elim_;       // lower(c) * pivot_inv(c - e): the elimination factors
};

}  // namespace narwhal
