// Observed order in time on a moving grid (issue 17, bar 1): an unsteady manufactured
// solution, u = a(t) U(x), p = a(t)^2 P(x) with U, P those of NUMERICS §12.2 and
// a(t) = 1 + sin(2 t) / 2, its source S = a' U + a^2 ((U.grad) U + grad P) - a nu lap U,
// on a perturbed four-block grid that turns and translates. On one grid the differences
// of the solutions at T for dt, dt/2, dt/4 ... shrink at the scheme's order (spatial
// error is the same in all of them).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "app/dual_time.hpp"
#include "config/case_config.hpp"
#include "implicit/newton.hpp"
#include "motion/attitude.hpp"
#include "motion/grid_motion.hpp"
#include "physics/manufactured.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

Real amplitude(Real t) { return 1.0 + 0.5 * std::sin(2.0 * t); }
Real amplitude_rate(Real t) { return std::cos(2.0 * t); }

class UnsteadyManufacturedSource final : public VolumeSource {
 public:
  explicit UnsteadyManufacturedSource(ManufacturedSolution ms) : ms_(ms) {}
  std::string name() const override { return "unsteady manufactured solution's forcing"; }
  void at_time(Real t) override { t_ = t; }
  void add_to_residual(const Block& b, const GhostArray<State>&, GhostArray<State>& R) const override {
    const Real a = amplitude(t_), da = amplitude_rate(t_), lap = 3.0 * M_PI * M_PI * ms_.nu;
    for_each_cell(b, [&](int i, int j, int k) {
      const Vec3 x = b.xc(i, j, k);
      const Vec3 U = ms_.exact(x).tail<3>();
      const Vec3 steady_inviscid = ms_.momentum_source(x) - lap * U;  // (U.grad) U + grad P
      R(i, j, k).tail<3>() -= b.vol(i, j, k) * Vec3(da * U + a * a * steady_inviscid + a * lap * U);
    });
  }

 private:
  ManufacturedSolution ms_;
  Real t_ = 0.0;
};

RigidPose pose_at(Real t) {
  RigidPose p;
  p.rotation = rotation_matrix(quaternion_from_euler({0.2 * std::sin(3 * t), 0.15 * t, -0.25 * t * t}));
  p.displacement = Vec3(0.1 * t, -0.05 * std::sin(2 * t), 0.03 * t * t);
  return p;
}

std::vector<State> solve(TimeConfig::Scheme scheme, int steps) {
  const Real T = 0.5, dt = T / steps;
  CaseConfig c = parse_case(test::read_text(test::source_path("validation/cases/mms/mms.toml")), "mms.toml", ".",
                            {"grid.cells=8", "grid.split=[2, 2, 1]", "grid.split_rotate=true"});
  Grid g = build_grid(c);
  FlowParams fp = c.flow;
  auto time_now = std::make_shared<Real>(0.0);
  const ManufacturedSolution ms = c.mms;
  auto source = std::make_shared<UnsteadyManufacturedSource>(ms);
  fp.sources = {source};
  fp.exact = [ms, time_now](const Vec3& x) {
    const Real a = amplitude(*time_now);
    State q = ms.exact(x);
    q[0] *= a * a;
    q.tail<3>() *= a;
    return q;
  };
  FlowField f;
  f.allocate(g, fp, State::Zero());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) { f.Q[ib](i, j, k) = fp.exact(g.blocks[ib].xc(i, j, k)); });
  DualTime time(g, test::time_config(scheme, dt, steps));
  NewtonSettings ns;
  ns.sgs_iterations = 10;
  NewtonSolver solver(g, f, fp, ns, Communicator::world());
  solver.set_physical_time(&time.term());
  MovingGrid moving(g, Vec3(0.5, 0.5, 0.5));
  const Real inf = std::numeric_limits<Real>::infinity();
  for (int s = 1; s <= steps; ++s) {
    time.begin_step(g, f);
    moving.move_to(RigidMotionSample{pose_at(s * dt)}, dt, time.term().coefficients());
    *time_now = time.time();
    source->at_time(time.time());
    test::converge_step([&] { return solver.iterate_with_cfl(inf); }, 1e-11, 80);
  }
  std::vector<State> out;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) { out.push_back(f.Q[ib](i, j, k)); });
  return out;
}

Real difference(const std::vector<State>& a, const std::vector<State>& b) {
  Real s = 0.0;
  for (std::size_t n = 0; n < a.size(); ++n) s += (a[n] - b[n]).squaredNorm();
  return std::sqrt(s / a.size());
}

TEST(MovingGridMms, Bdf2IsSecondOrderInTimeOnATurningPerturbedMultiblockGrid) {
  for (auto [scheme, order, name] :
       {std::tuple{TimeConfig::Scheme::Bdf1, 1.0, "BDF1"}, {TimeConfig::Scheme::Bdf2, 2.0, "BDF2"}}) {
    const auto q4 = solve(scheme, 4), q8 = solve(scheme, 8), q16 = solve(scheme, 16), q32 = solve(scheme, 32);
    const Real d1 = difference(q4, q8), d2 = difference(q8, q16), d3 = difference(q16, q32);
    std::printf("%s on a moving grid: differences %.3e %.3e %.3e, orders %.3f %.3f\n", name, d1, d2, d3,
                std::log2(d1 / d2), std::log2(d2 / d3));
    if (order > 1.5) {
      EXPECT_GE(std::log2(d2 / d3), 1.9);
    } else {
      EXPECT_NEAR(std::log2(d2 / d3), 1.0, 0.15);
    }
  }
}

}  // namespace
}  // namespace narwhal
