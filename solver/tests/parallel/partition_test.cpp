// Block distribution over ranks: the load balancer and the balancing splitter.
#include <gtest/gtest.h>

#include "multigrid/coarsen.hpp"
#include "parallel/partition.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

Grid box_grid(int ni, int nj, int nk, const Index3& parts = {1, 1, 1}) {
  Grid g;
  g.blocks.push_back(make_box("box", uniform_nodes(0.0, 2.0, ni), uniform_nodes(0.0, 1.0, nj), uniform_nodes(0.0, 0.5, nk)));
  if (parts != Index3{1, 1, 1}) g = split_blocks(g, parts, false);
  return g;
}

void finalize_with_farfield(Grid& g) {
  for (auto& b : g.blocks)
    for (auto& p : b.patches) p.type = BcType::Farfield;
  finalize_grid(g);
}

TEST(Partition, EqualBlocksShareEvenly) {
  const Grid g = box_grid(16, 8, 4, {4, 1, 1});
  const BlockAssignment a = assign_blocks(g, 2);
  EXPECT_EQ(a.cells[0], a.cells[1]);
  EXPECT_EQ(a.imbalance(), 0.0);
  const BlockAssignment one = assign_blocks(g, 1);
  EXPECT_EQ(one.cells[0], g.cells());
}

TEST(Partition, NeighboursStayTogetherWhenLoadAllows) {
  // Four equal blocks in a row on two ranks: the balancer keeps each rank's pair
  // adjacent (one cut interface, not three).
  Grid g = box_grid(16, 8, 4, {4, 1, 1});
  finalize_with_farfield(g);
  const BlockAssignment a = assign_blocks(g, 2);
  int cut = 0;
  for (const Interface& itf : g.interfaces) cut += a.owner[itf.block] != a.owner[itf.donor];
  EXPECT_EQ(cut, 2);  // one interface, seen from both sides
  EXPECT_EQ(a.imbalance(), 0.0);
}

TEST(Partition, SplitterBalancesThreeRanksAndKeepsMultigridLevels) {
  const Grid g = box_grid(64, 40, 2);
  const Grid s = split_for_balance(g, 3, 0.05, 3);
  const BlockAssignment a = assign_blocks(s, 3);
  EXPECT_LE(a.imbalance(), 0.05);
  EXPECT_EQ(s.cells(), g.cells());
  for (const Block& b : s.blocks) {
    EXPECT_EQ(b.ni % 4, 0) << b.name;  // two coarsenings still possible
    EXPECT_EQ(b.nj % 4, 0) << b.name;
  }
  Grid connected = s;
  finalize_with_farfield(connected);
  EXPECT_FALSE(connected.interfaces.empty());
  EXPECT_LE(test::interface_ghost_node_mismatch(connected, 0), 1e-14);
  EXPECT_EQ(why_not_coarsenable(connected), "");
  const Grid balanced_already = split_for_balance(box_grid(16, 8, 4, {4, 1, 1}), 2, 0.05, 3);
  EXPECT_EQ(balanced_already.blocks.size(), 4u);  // nothing to cut
}

TEST(Partition, SplitterLeavesProtectedDirectionsWholeAndRecordsWherePiecesCameFrom) {
  const Grid g = box_grid(40, 64, 2);  // j is the longest: cut there unless protected
  const Grid free_cut = split_for_balance(g, 2, 0.05, 1);
  ASSERT_EQ(free_cut.blocks.size(), 2u);
  EXPECT_EQ(free_cut.blocks[0].nj, 32);
  const Grid kept = split_for_balance(g, 2, 0.05, 1, 4096, {{false, true, false}});
  ASSERT_EQ(kept.blocks.size(), 2u);
  for (const Block& b : kept.blocks) {
    EXPECT_EQ(b.nj, 64) << b.name;  // whole j lines
    EXPECT_EQ(b.parent, "box");
  }
  EXPECT_EQ(kept.blocks[0].parent_offset, (Index3{0, 0, 0}));
  EXPECT_EQ(kept.blocks[1].parent_offset, (Index3{20, 0, 0}));
}

}  // namespace
}  // namespace narwhal
