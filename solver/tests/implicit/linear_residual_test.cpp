// The linearized residual R + A dQ that decides whether a Newton correction is applied
// (NewtonSolver::relax_and_update) is that of the system the SGS sweeps solve: on a
// four-block grid with rotated blocks it falls with every sweep to round-off.
#include <gtest/gtest.h>

#include "app/driver.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

TEST(LinearResidual, FallsToRoundOffAsTheSweepsConverge) {
  CaseConfig c = load_case(test::source_path("validation/cases/mms/mms.toml"));
  c.grid.perturbed_cells = 12;
  c.grid.split = {2, 2, 1};
  c.grid.split_rotate = true;
  Grid g = build_grid(c);
  const FlowParams fp = flow_params(c);
  FlowField f;
  f.allocate(g, fp, c.initial);
  NewtonSettings ns = c.solver.newton;
  ns.sgs_iterations = 1;
  NewtonSolver s(g, f, fp, ns, Communicator::world());
  for (int it = 0; it < 3; ++it) s.iterate();  // away from the uniform start
  const IterationNorms n = s.evaluate_residual();
  s.relax_and_update(n, 50.0);  // one sweep pair; R and the matrices stay those of this state
  const Real after_one = s.linear_residual_ratio_collective(n.total);
  s.sweeps_only(4);
  const Real after_five = s.linear_residual_ratio_collective(n.total);
  s.sweeps_only(200);
  const Real after_many = s.linear_residual_ratio_collective(n.total);
  std::printf("linear residual over nonlinear: %.3e (1 pair), %.3e (5), %.3e (205)\n", after_one, after_five,
              after_many);
  EXPECT_LT(after_one, 1.0);
  EXPECT_LT(after_five, 0.5 * after_one);
  EXPECT_LT(after_many, 1e-10);
  EXPECT_EQ(s.cfl_cuts(), 0);
}

}  // namespace
}  // namespace narwhal
