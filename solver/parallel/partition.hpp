#pragma once
// Blocks as the unit of distribution over MPI ranks (issue #6):
// - assign_blocks: two candidates, the better balanced one wins (within 1 %, the one
//   cutting fewer interface faces): largest block first onto the least loaded rank,
//   and the blocks in breadth-first order over the interface graph cut into
//   consecutive runs of total/ranks cells (neighbours stay together).
// - split_for_balance: splits blocks into tensor-product pieces, one more cut at a
//   time in the direction in which the largest pieces are longest, until the balancer
//   reaches the tolerance; cuts fall on multiples of 2^(levels-1) cells, so every
//   multigrid level stays valid. Works on grids before connectivity: the new faces are
//   left free and joined as 1-to-1 interfaces by finalize_grid. Limitation: faces
//   between two original blocks stay conforming only if both are cut alike along the
//   shared face (the connectivity matches whole faces); single-block grids always are.
#include <array>
#include <vector>

#include "mesh/block.hpp"

namespace narwhal {

struct BlockAssignment {
  std::vector<int> owner;            // rank of each block
  std::vector<std::size_t> cells;    // cells per rank
  // max load / mean load - 1 (0: perfect balance)
  Real imbalance() const;
};

// `interfaces` may be empty (an unconnected grid): placement by cells alone.
BlockAssignment assign_blocks(const Grid& g, int ranks);

// The grid with its blocks cut into pieces until assign_blocks' imbalance is at most
// `tolerance` (or no block can be cut further, or `max_blocks` is reached).
// `uncut[ib][d]`: never cut block ib across direction d (e.g. the wall-normal lines an
// algebraic turbulence model searches); empty: every direction may be cut.
Grid split_for_balance(const Grid& g, int ranks, Real tolerance, int multigrid_levels, int max_blocks = 4096,
                       const std::vector<std::array<bool, 3>>& uncut = {});

}  // namespace narwhal
