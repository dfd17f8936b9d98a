// Halo exchange on however many ranks the test runs with: each rank owns some blocks
// of a split, re-oriented box; the arrays of blocks it does not own are NaN, and after
// the exchange its blocks' interface ghosts must equal the serial ghost fill's exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "bc/boundary.hpp"
#include "mesh/generators.hpp"
#include "mesh/ghost_sweep.hpp"
#include "mesh/setup.hpp"
#include "parallel/communicator.hpp"
#include "parallel/halo.hpp"
#include "parallel/partition.hpp"

namespace narwhal {
namespace {

Grid rotated_split_box() {
  Grid g;
  g.blocks.push_back(make_box("box", uniform_nodes(0.0, 2.0, 12), uniform_nodes(0.0, 1.0, 8), uniform_nodes(0.0, 1.0, 6)));
  g = split_blocks(g, {3, 2, 1}, true);
  for (auto& b : g.blocks)
    for (auto& p : b.patches) {
      p.type = BcType::Farfield;
      p.velocity = Vec3(1.0, 0.0, 0.0);
    }
  finalize_grid(g);
  return g;
}

TEST(Halo, ExchangeReproducesTheSerialGhostFillOnAnyRankCount) {
  const Communicator comm = Communicator::world();
  Grid g = rotated_split_box();
  FlowParams fp;
  FlowField ref;
  ref.allocate(g, fp, State::Zero());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
      const Vec3 x = g.blocks[ib].xc(i, j, k);
      ref.Q[ib](i, j, k) << x[0] + 2 * x[1], std::sin(x[0]), x[1] * x[2], 1.0 + x[2];
    });
  fill_ghosts(g, ref, fp);

  const BlockAssignment a = assign_blocks(g, comm.size());
  const ExchangePlan plan = build_exchange_plan(g, a.owner, comm.rank());
  std::vector<GhostArray<State>> Q = ref.Q;
  const State nan = State::Constant(std::nan(""));
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (a.owner[ib] != comm.rank()) {
      Q[ib].fill(nan);  // not ours: must never be read
      continue;
    }
    for_each_interface_ghost(g, static_cast<int>(ib), [&](int, const Index3& gc, int, const Index3&) { Q[ib](gc) = nan; });
  }
  for (int round = 0; round < 2; ++round) exchange_halo(g, plan, Q);

  long long wrong = 0, checked = 0;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (a.owner[ib] != comm.rank()) continue;
    for_each_interface_ghost(g, static_cast<int>(ib), [&](int, const Index3& gc, int, const Index3&) {
      ++checked;
      if (!(Q[ib](gc) == ref.Q[ib](gc))) ++wrong;
    });
  }
  EXPECT_EQ(comm.sum(wrong), 0);
  EXPECT_GT(comm.sum(checked), 0);
  if (comm.size() > 1) {
    EXPECT_GT(comm.sum(static_cast<long long>(plan.sent_cells())), 0);
  }
}

}  // namespace
}  // namespace narwhal
