#pragma once
// Coarse grids for FAS multigrid (NUMERICS §7.1): every other node line is removed
// in each direction that has more than one cell; a direction with a single cell
// (2-D cases) is kept. Patches and 1-to-1 interfaces are inherited; the coarse
// geometry is computed from the coarse nodes (§2), so the GCL holds per level.
#include <string>
#include <vector>

#include "mesh/block.hpp"

namespace narwhal {

// Coarsening factor (1 or 2) of each direction of a block.
Index3 coarsening_factors(const Block& b);

// Why `g` cannot be coarsened once more ("" when it can): a direction that cannot halve,
// or (multigrid) one that would keep fewer than `min_cells` cells in some block.
std::string why_not_coarsenable(const Grid& g, int min_cells = 1);

// The next coarser grid (ghost nodes and metrics prepared).
Grid coarsen(const Grid& g);

// The coarse levels FAS multigrid builds below `fine` (NUMERICS §7.1): up to `levels` - 1
// of them, stopping where a coarsening is impossible or would keep fewer than `min_cells`
// cells in some block; `stop` says why it stopped short ("" when all were built), and
// `impossible` whether the grid cannot coarsen at all there (odd counts; not merely too
// few cells). The one place that decides the hierarchy: the solver and `narwhal check`
// (which refuses the impossible) both ask it.
struct CoarseLevels {
  std::vector<Grid> grids;
  std::string stop;
  bool impossible = false;
};
CoarseLevels coarse_levels(const Grid& fine, int levels, int min_cells);

}  // namespace narwhal
