// Multiblock equivalence (issue bar 2): the manufactured-solution case split into
// 4 blocks with rotated index orientations converges to the single-block answer.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "app/driver.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

struct Converged {
  Grid g;
  FlowField f;
};

Converged solve(CaseConfig c) {
  Converged r;
  r.g = build_grid(c);
  const FlowParams fp = flow_params(c);
  r.f.allocate(r.g, fp, c.initial);
  NewtonSolver s(r.g, r.f, fp, c.solver.newton, Communicator::world());
  EXPECT_LT(test::converge(s, 1e-13, 3000), 1e-13);
  return r;
}

TEST(Multiblock, RotatedFourBlockSplitMatchesSingleBlock) {
  CaseConfig c = load_case(test::source_path("validation/cases/mms/mms.toml"));
  c.grid.perturbed_cells = 12;
  const Converged one = solve(c);
  c.grid.split = {2, 2, 1};
  c.grid.split_rotate = true;
  const Converged four = solve(c);
  ASSERT_EQ(four.g.blocks.size(), 4u);
  // Match cells by their centres (identical nodes give identical centres).
  auto key = [](const Vec3& x) {
    return std::array<long long, 3>{std::llround(x[0] * 1e9), std::llround(x[1] * 1e9), std::llround(x[2] * 1e9)};
  };
  std::map<std::array<long long, 3>, State> reference;
  const Block& b1 = one.g.blocks[0];
  for (int k = 0; k < b1.nk; ++k)
    for (int j = 0; j < b1.nj; ++j)
      for (int i = 0; i < b1.ni; ++i) reference[key(b1.xc(i, j, k))] = one.f.Q[0](i, j, k);
  Real worst = 0.0;
  std::size_t matched = 0;
  for (std::size_t ib = 0; ib < four.g.blocks.size(); ++ib) {
    const Block& b = four.g.blocks[ib];
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i) {
          auto it = reference.find(key(b.xc(i, j, k)));
          ASSERT_NE(it, reference.end());
          worst = std::max(worst, (four.f.Q[ib](i, j, k) - it->second).cwiseAbs().maxCoeff());
          ++matched;
        }
  }
  EXPECT_EQ(matched, b1.cells());
  std::printf("multiblock vs single block: max |dQ| = %.3e over %zu cells\n", worst, matched);
  EXPECT_LT(worst, 1e-10);
}

}  // namespace
}  // namespace narwhal
