#pragma once
// The traversal shared by every ghost fill (nodes, flow state, corrections):
// directions are processed in order i, j, k, and each patch's tangential range is
// extended into the ghost layers of the directions already processed. Edge and
// corner ghosts are thereby filled from face ghosts. Two rounds make interface
// copies of donor ghosts (which the donor may fill later in a round) consistent.
#include "mesh/block.hpp"

namespace narwhal {

struct PatchRange {
  Index3 lo, hi;  // half-open cell range, normal direction excluded
};

// The boundary-adjacent cells of a patch (its range with the normal index 0): one
// entry per boundary face; interior_cell/ghost_cell/boundary_face_index map it.
inline PatchRange face_range(const Patch& p) {
  PatchRange r{p.lo, p.hi};
  r.lo[side_dir(p.side)] = 0;
  r.hi[side_dir(p.side)] = 1;
  return r;
}

// Tangential cell range of a patch, extended into ghosts for directions < dir.
inline PatchRange extended_cell_range(const Block& b, const Patch& p) {
  const int d = side_dir(p.side);
  PatchRange r{p.lo, p.hi};
  for (int t = 0; t < 3; ++t) {
    if (t == d) {
      r.lo[t] = 0;
      r.hi[t] = 1;
      continue;
    }
    if (t < d) {
      if (r.lo[t] == 0) r.lo[t] = -kGhost;
      if (r.hi[t] == b.n(t)) r.hi[t] = b.n(t) + kGhost;
    }
  }
  return r;
}

// Cell just inside the boundary (depth m = 1, 2, ...) and the matching ghost,
// for a boundary cell whose tangential indices are given in `c`.
inline Index3 interior_cell(const Block& b, int side, Index3 c, int m) {
  const int d = side_dir(side);
  c[d] = side_high(side) ? b.n(d) - m : m - 1;
  return c;
}
inline Index3 ghost_cell(const Block& b, int side, Index3 c, int m) {
  const int d = side_dir(side);
  c[d] = side_high(side) ? b.n(d) - 1 + m : -m;
  return c;
}

// The donor's value for ghost cell `gc` of an interface, velocity mapped by R
// (identity for plain interfaces, a rotation for rotational periodicity).
inline State donor_state(const Interface& itf, const GhostArray<State>& donor_field, const Index3& gc) {
  State q = donor_field(itf.map_cell(gc));
  q.tail<3>() = itf.R * q.tail<3>();
  return q;
}

// Calls fn(face) for every face of direction d between two cells of the block (the
// face index is that of the cell on its high side); block faces are left to patches.
template <class F>
void for_each_interior_face(const Block& b, int d, F&& fn) {
  Index3 lo{0, 0, 0}, hi = b.dims();
  lo[d] = 1;
  for (int k = lo[2]; k < hi[2]; ++k)
    for (int j = lo[1]; j < hi[1]; ++j)
      for (int i = lo[0]; i < hi[0]; ++i) fn(Index3{i, j, k});
}

template <class F>
void for_each_in(const PatchRange& r, F&& f) {
  for (int k = r.lo[2]; k < r.hi[2]; ++k)
    for (int j = r.lo[1]; j < r.hi[1]; ++j)
      for (int i = r.lo[0]; i < r.hi[0]; ++i) f(Index3{i, j, k});
}

// Calls fill(block_index, patch, depth) for every patch in the sweep order above;
// within a direction all depth-1 ghosts come before any depth-2 ghost, so that in a
// block with a single cell in that direction a depth-2 ghost (which mirrors the
// opposite side's depth-1 ghost) reads a value of this sweep.
template <class F>
void ghost_sweep(const Grid& g, F&& fill) {
  // Without interfaces every ghost depends only on its own block's cells and on
  // ghosts filled earlier in the sweep: one round suffices. Interfaces copy donor
  // ghosts that the donor may fill later in a round, hence a second round.
  const int rounds = g.interfaces.empty() ? 1 : 2;
  for (int round = 0; round < rounds; ++round)
    for (int d = 0; d < 3; ++d)
      for (int m = 1; m <= kGhost; ++m)
        for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
          for (const Patch& p : g.blocks[ib].patches)
            if (side_dir(p.side) == d) fill(static_cast<int>(ib), p, m);
}

}  // namespace narwhal
