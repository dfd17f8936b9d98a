#pragma once
// Halo exchange over blocks distributed on ranks (issue #6): one precomputed plan per
// grid level says which ghost cells of the blocks a rank owns come from which donor
// cells, on this rank or another. On-rank and off-rank interfaces take the same path:
// values are gathered into per-peer buffers in the plan's order, sent (MPI
// non-blocking, or copied when the peer is this rank), and scattered into the ghosts,
// velocities rotated by the interface's R (rotational periodicity).
//
// The ranges are those of the serial ghost fill (mesh/ghost_sweep.hpp): both ghost
// layers, extended into the ghosts of earlier directions, so edge and corner ghosts
// come along; as there, two rounds make donor ghosts consistent.
#include <vector>

#include "fields/ghost_array.hpp"
#include "mesh/block.hpp"
#include "mesh/ghost_sweep.hpp"

namespace narwhal {

struct HaloCell {
  int block = -1;   // block index in the grid
  Index3 cell;      // ghost cell (receive) or donor cell (send)
  int interface = -1;  // the interface (receive side: rotation of vectors)
};

struct HaloPeer {
  int rank = -1;
  std::vector<HaloCell> send, receive;  // same length and order on both ends
};

struct ExchangePlan {
  int rank = 0;
  std::vector<HaloPeer> peers;  // one per rank this rank talks to (itself included)
  std::size_t sent_cells() const;  // off-rank only
};

// Calls visit(interface, ghost cell, donor block, donor cell) for every interface
// ghost of block ib, in the serial sweep's order (the plan's order).
template <class F>
void for_each_interface_ghost(const Grid& g, int ib, F&& visit) {
  const Block& b = g.blocks[ib];
  for (int d = 0; d < 3; ++d)
    for (int m = 1; m <= kGhost; ++m)
      for (const Patch& p : b.patches) {
        if (side_dir(p.side) != d || p.type != BcType::Interface) continue;
        const Interface& itf = g.interfaces[p.interface];
        for_each_in(extended_cell_range(b, p), [&](Index3 c) {
          const Index3 gc = ghost_cell(b, p.side, c, m);
          visit(p.interface, gc, itf.donor, itf.map_cell(gc));
        });
      }
}

// The plan of `rank` for a grid whose blocks are owned as `owner` says.
ExchangePlan build_exchange_plan(const Grid& g, const std::vector<int>& owner, int rank);

// Fills the interface ghosts of the owned blocks of Q (arrays of blocks not owned may
// be empty). Collective: every rank calls it with its own plan.
void exchange_halo(const Grid& g, const ExchangePlan& plan, std::vector<GhostArray<State>>& Q);

}  // namespace narwhal
