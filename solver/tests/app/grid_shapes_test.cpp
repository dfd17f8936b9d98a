// The shapes of a run's grids with its control surfaces turned (app/grid_shapes.hpp):
// the case's own angles give back every grid's nodes bit for bit, other angles the
// nodes of the grid built with them, on the pieces, their multigrid levels and the
// case's blocks alike; only the turned surfaces' boxes move (and the ghost nodes their
// neighbours copy from them).
#include <gtest/gtest.h>

#include "app/grid_shapes.hpp"
#include "core/error.hpp"
#include "multigrid/coarsen.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

constexpr Real kDegree = 3.14159265358979323846 / 180.0;

const std::vector<std::string> kRoomyBoxes = {"grid.box_half_width=4", "solver.multigrid_levels=2"};

// The grids a run on two ranks keeps: the pieces, their coarse level, the case's blocks.
std::vector<std::vector<GhostArray<Vec3>>> run_grids(const CaseConfig& c) {
  std::vector<std::vector<GhostArray<Vec3>>> out;
  auto nodes = [](const Grid& g) {
    std::vector<GhostArray<Vec3>> x;
    for (const Block& b : g.blocks) x.push_back(b.x);
    return x;
  };
  const Grid pieces = build_grid(c, 2);
  out.push_back(nodes(pieces));
  for (const Grid& g : coarse_levels(pieces, 2, 1).grids) out.push_back(nodes(g));
  out.push_back(nodes(build_grid(c)));
  return out;
}

bool same(const GhostArray<Vec3>& a, const GhostArray<Vec3>& b) { return a.raw() == b.raw(); }

// Whether the nodes of the block itself (its ghost nodes, copies of its neighbours' or
// extrapolated, left out) are the same.
bool same_block_nodes(const GhostArray<Vec3>& a, const GhostArray<Vec3>& b) {
  for (int k = 0; k < a.nk(); ++k)
    for (int j = 0; j < a.nj(); ++j)
      for (int i = 0; i < a.ni(); ++i)
        if (a(i, j, k) != b(i, j, k)) return false;
  return true;
}

TEST(GridShapes, TheCasesAnglesGiveBackEveryGridAndOthersTheTurnedGrids) {
  const CaseConfig c = parse_case(test::kSmallAppendedCase, "appended.toml", ".", kRoomyBoxes);
  const GridShapes shapes(c, 2, 2, true);
  const auto straight = run_grids(c);
  const auto again = shapes.at(shapes.as_built());
  ASSERT_EQ(again.size(), 3u);
  for (std::size_t g = 0; g < 3; ++g) {
    ASSERT_EQ(again[g].size(), straight[g].size());
    for (std::size_t b = 0; b < again[g].size(); ++b) EXPECT_TRUE(same(again[g][b], straight[g][b])) << g << " " << b;
  }
  const std::vector<std::string> sets = {kRoomyBoxes[0], kRoomyBoxes[1], "grid.rudder_deflection=8"};
  const auto turned = run_grids(parse_case(test::kSmallAppendedCase, "appended.toml", ".", sets));
  const auto shaped = shapes.at(suboff::Deflections{8.0 * kDegree, 0.0, 0.0});
  const Grid pieces = build_grid(c, 2);
  int moved = 0;
  for (std::size_t g = 0; g < 3; ++g)
    for (std::size_t b = 0; b < shaped[g].size(); ++b) {
      EXPECT_TRUE(same(shaped[g][b], turned[g][b])) << g << " " << b;
      if (g == 0 && !same_block_nodes(shaped[0][b], straight[0][b])) {
        ++moved;
        EXPECT_EQ(pieces.blocks[b].name.rfind("rud_", 0), 0u) << pieces.blocks[b].name;
      }
    }
  EXPECT_GT(moved, 0);
}

TEST(GridShapes, OnlyAnAppendedSuboffHasControlSurfaces) {
  CaseConfig box = parse_case(test::kSmallAppendedCase, "appended.toml", ".");
  box.grid.type = "box";
  EXPECT_THROW(GridShapes(box, 1, 1, false), Error);
}

}  // namespace
}  // namespace narwhal
