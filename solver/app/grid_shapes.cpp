#include "app/grid_shapes.hpp"

#include "core/error.hpp"
#include "multigrid/coarsen.hpp"

namespace narwhal {

namespace {

std::vector<GhostArray<Vec3>> nodes_of(const Grid& g) {
  std::vector<GhostArray<Vec3>> x;
  x.reserve(g.blocks.size());
  for (const Block& b : g.blocks) x.push_back(b.x);
  return x;
}

}  // namespace

GridShapes::GridShapes(const CaseConfig& c, int split_for, int levels, bool pieces)
    : c_(c), split_for_(split_for), levels_(levels), pieces_(pieces) {
  if (c.grid.type != "appended_suboff")
    fail("{}: control surfaces turn only on an appended SUBOFF grid (grid.type = \"appended_suboff\"), this case's "
         "grid is '{}'", c.file, c.grid.type);
}

std::vector<std::vector<GhostArray<Vec3>>> GridShapes::at(const suboff::Deflections& d) const {
  CaseConfig turned = c_;
  turned.grid.appended.deflections = d;
  std::vector<std::vector<GhostArray<Vec3>>> shapes;
  Grid generated = generate_grid(turned);
  const Grid fine = finish_grid(turned, generated, split_for_);
  shapes.push_back(nodes_of(fine));
  if (levels_ > 1) {
    const CoarseLevels coarse = coarse_levels(fine, levels_, c_.solver.multigrid.min_cells);
    if (static_cast<int>(coarse.grids.size()) + 1 != levels_)
      fail("{}: the turned grid has {} multigrid levels, the run {}", c_.file, coarse.grids.size() + 1, levels_);
    for (const Grid& g : coarse.grids) shapes.push_back(nodes_of(g));
  }
  if (pieces_) shapes.push_back(nodes_of(finish_grid(turned, std::move(generated))));
  return shapes;
}

}  // namespace narwhal
