#pragma once
// The shapes of a run's grids with its control surfaces turned (issue 19's manoeuvres):
// the nodes as built, ghost nodes included, of every grid a moving run keeps (the
// multigrid levels of the blocks it computes on, then the case's own blocks when it
// computes on pieces of them: app/run_motion.hpp's order), for a new set of
// deflections. The case's recipe is run again with the new angles: the appended grid
// deforms its boxes about the turned surfaces (mesh/DESIGN.md, "Deflected control
// surfaces") without a change of topology, so every grid keeps its blocks and layout and
// MovingGrid::reshape can take the nodes.
//
// Usage:
//   GridShapes shapes(c, split_for, mg_levels, pieces);
//   const auto nodes = shapes.at(suboff::Deflections{rudder, 0.0, 0.0});  // one list per grid
//   for (std::size_t i = 0; i < moving.size(); ++i) moving[i]->reshape(nodes[i]);
#include <vector>

#include "config/case_config.hpp"

namespace narwhal {

class GridShapes {
 public:
  // `split_for`: the ranks the run's blocks were cut for (1: the case's blocks);
  // `levels`: the multigrid levels the run has (1: single grid); `pieces`: whether the
  // run also keeps the case's own blocks (split_for > 1). Throws Error unless the case's
  // grid is an appended SUBOFF (the one recipe with control surfaces).
  GridShapes(const CaseConfig& c, int split_for, int levels, bool pieces);

  // The nodes of every grid for deflections d (radians, suboff_geometry.hpp's signs);
  // an Error names the deflection a box cannot hold.
  std::vector<std::vector<GhostArray<Vec3>>> at(const suboff::Deflections& d) const;
  const suboff::Deflections& as_built() const { return c_.grid.appended.deflections; }

 private:
  CaseConfig c_;
  int split_for_, levels_;
  bool pieces_;
};

}  // namespace narwhal
