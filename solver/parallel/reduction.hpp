#pragma once
// Global sums that do not depend on how blocks are shared over ranks (issue #6):
// every rank sums its own blocks into per-block partials, the partials of all blocks
// are combined (each entry has one contributor, so the reduction is exact), and every
// rank adds them up in block order. Residual norms, forces and bulk quantities are
// then the same bit for bit on 1, 2 or 3 ranks for the same blocks, and so is the
// iteration path that depends on them (the SER CFL).
#include <string>
#include <vector>

#include "mesh/block.hpp"
#include "parallel/communicator.hpp"

namespace narwhal {

// `partials` holds `width` values per block (block-major; zeros for blocks not owned).
// Returns the `width` totals. Collective over `comm` when the grid's blocks are
// distributed (g.owner set): every rank must call it.
std::vector<Real> sum_in_block_order(const Communicator& comm, const Grid& g, std::vector<Real> partials, int width);

// Collective over `comm`: the description held by the lowest rank whose `local_largest`
// is the largest of all ranks' (where the worst cell is, whichever rank owns it).
std::string description_of_largest(const Communicator& comm, Real local_largest, std::string local_description);

}  // namespace narwhal
