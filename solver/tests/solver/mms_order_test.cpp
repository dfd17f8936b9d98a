// Verification by the manufactured solution of NUMERICS §12.2 on a family of
// smoothly perturbed curvilinear 3-D grids: observed order of the L2 error of
// p, u, v, w on the two finest grid pairs must be >= 1.9 (issue bar 3).
#include <gtest/gtest.h>

#include <cmath>

#include "app/driver.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

// Volume-weighted L2 error of each variable after converging 11 orders.
State mms_error(int n) {
  const CaseConfig base = load_case(test::source_path("validation/cases/mms/mms.toml"));
  CaseConfig c = base;
  c.grid.perturbed_cells = n;
  Grid g = build_grid(c);
  const FlowParams fp = flow_params(c);
  FlowField f;
  f.allocate(g, fp, c.initial);
  NewtonSolver s(g, f, fp, c.solver.newton, Communicator::world());
  const Real drop = test::converge(s, 1e-11, 2000);
  EXPECT_LT(drop, 1e-11) << "grid " << n;
  State e2 = State::Zero();
  Real V = 0.0;
  const Block& b = g.blocks[0];
  for (int k = 0; k < b.nk; ++k)
    for (int j = 0; j < b.nj; ++j)
      for (int i = 0; i < b.ni; ++i) {
        const State d = f.Q[0](i, j, k) - c.mms.exact(b.xc(i, j, k));
        e2 += b.vol(i, j, k) * d.cwiseAbs2();
        V += b.vol(i, j, k);
      }
  return (e2 / V).cwiseSqrt();
}

TEST(ManufacturedSolution, SecondOrderOnPerturbedCurvilinearGrids) {
  const std::vector<int> cells = {8, 12, 16, 24, 32};
  std::vector<State> err;
  for (int n : cells) err.push_back(mms_error(n));
  for (std::size_t m = 1; m < cells.size(); ++m) {
    const Real ratio = Real(cells[m]) / cells[m - 1];
    for (int q = 0; q < kNumEq; ++q) {
      const Real order = std::log(err[m - 1][q] / err[m][q]) / std::log(ratio);
      std::printf("MMS %s: %2d -> %2d cells, L2 error %.4e -> %.4e, observed order %.3f\n", kEquationNames[q],
                  cells[m - 1], cells[m], err[m - 1][q], err[m][q], order);
      if (m + 2 >= cells.size()) {
        EXPECT_GE(order, 1.9) << kEquationNames[q] << " pair " << m;
      }
    }
  }
}

}  // namespace
}  // namespace narwhal
