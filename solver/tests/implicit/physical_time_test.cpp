// Dual time stepping (NUMERICS §2.4, §2.5, §6.1): the BDF coefficients, and the observed
// order in time of the whole R* = 0 iteration, on an ODE the uniform state obeys exactly
// and on the Taylor-Green vortex (self-convergence in dt on a fixed grid).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "app/dual_time.hpp"
#include "bc/boundary.hpp"
#include "implicit/newton.hpp"
#include "mesh/connectivity.hpp"
#include "mesh/generators.hpp"
#include "mesh/setup.hpp"
#include "multigrid/fas.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

TEST(Bdf, CoefficientsIntegratePolynomialsOfTheirOrderExactly) {
  // sum_k c_k f(t_{n+1-k}) / dt_n = f'(t_{n+1}) for f of degree 1 (BDF1) or 2 (BDF2),
  // also with unequal steps (omega = dt_n / dt_{n-1}).
  for (Real omega : {1.0, 0.5, 2.0}) {
    const Real dt = 0.1, t1 = 1.0, t0 = t1 - dt, tm = t0 - dt / omega;
    const BdfCoefficients b2 = BdfCoefficients::bdf2(omega);
    auto f = [](Real t) { return 3.0 + 2.0 * t - 5.0 * t * t; };
    EXPECT_NEAR((b2.c0 * f(t1) + b2.c1 * f(t0) + b2.c2 * f(tm)) / dt, 2.0 - 10.0 * t1, 1e-11);
    EXPECT_NEAR(b2.c0 + b2.c1 + b2.c2, 0.0, 1e-14);
  }
  const BdfCoefficients b1 = BdfCoefficients::bdf1();
  EXPECT_NEAR((b1.c0 * 2.5 + b1.c1 * 2.3) / 0.1, 2.0, 1e-12);  // f = 2 t + 0.5 at t = 1, 0.9
  const BdfCoefficients b = BdfCoefficients::bdf2(1.0);
  EXPECT_DOUBLE_EQ(b.c0, 1.5);
  EXPECT_DOUBLE_EQ(b.c1, -2.0);
  EXPECT_DOUBLE_EQ(b.c2, 0.5);
}

// A momentum sink -lambda u with its Jacobian: a uniform state in a periodic box then
// obeys du/dt = -lambda u exactly (the fluxes cancel).
class LinearDamping final : public VolumeSource {
 public:
  explicit LinearDamping(Real lambda) : lambda_(lambda) {}
  std::string name() const override { return "linear damping"; }
  void add_to_residual(const Block& b, const GhostArray<State>& Q, GhostArray<State>& R) const override {
    for_each_cell(b, [&](int i, int j, int k) { R(i, j, k).tail<3>() += lambda_ * b.vol(i, j, k) * Q(i, j, k).tail<3>(); });
  }
  void add_to_diagonal(const Block& b, const Index3& c, const State&, Mat4& D) const override {
    for (int m = 1; m < kNumEq; ++m) D(m, m) += lambda_ * b.vol(c);
  }

 private:
  Real lambda_;
};

Grid periodic_box(int n, Real length, int nk = 1) {
  Grid g;
  g.blocks.push_back(make_box("box", uniform_nodes(0.0, length, n), uniform_nodes(0.0, length, n),
                              uniform_nodes(0.0, 0.1 * length, nk)));
  for (auto [a, b] : {std::pair{"imin", "imax"}, {"jmin", "jmax"}, {"kmin", "kmax"}})
    connect_periodic(g, a, b, Mat3::Identity(), std::nullopt);
  finalize_grid(g);
  return g;
}

struct Marched {
  Grid g;
  FlowField f;
};

// `steps` steps of dt, each iterated until its residual has dropped 1e-11 (the
// algebraic error far below the temporal one).
void march(Grid& g, FlowField& f, const FlowParams& fp, TimeConfig::Scheme scheme, Real dt, int steps,
           int multigrid_levels = 1) {
  DualTime time(g, test::time_config(scheme, dt, steps));
  NewtonSettings ns;
  ns.sgs_iterations = 8;
  std::unique_ptr<NewtonSolver> single;
  std::unique_ptr<Multigrid> mg;
  if (multigrid_levels > 1) {
    MultigridSettings ms;
    ms.levels = multigrid_levels;
    mg = std::make_unique<Multigrid>(g, f, fp, ns, ms, Communicator::world());
    mg->use_physical_time(&time.term());
  } else {
    single = std::make_unique<NewtonSolver>(g, f, fp, ns, Communicator::world());
    single->set_physical_time(&time.term());
  }
  const Real inf = std::numeric_limits<Real>::infinity();
  for (int s = 0; s < steps; ++s) {
    time.begin_step(g, f);
    test::converge_step([&] { return mg ? mg->cycle_with_cfl(inf) : single->iterate_with_cfl(inf); }, 1e-11, 60);
  }
}

Real uniform_decay_error(TimeConfig::Scheme scheme, Real dt, int multigrid_levels = 1) {
  const Real lambda = 2.0, T = 1.0;
  Grid g = periodic_box(4, 1.0, 4);
  FlowParams fp;
  fp.reynolds = 100.0;
  fp.sources = {std::make_shared<LinearDamping>(lambda)};
  FlowField f;
  State q0;
  q0 << 0.0, 1.0, 0.5, -0.25;
  f.allocate(g, fp, q0);
  march(g, f, fp, scheme, dt, static_cast<int>(std::lround(T / dt)), multigrid_levels);
  return std::abs(f.Q[0](1, 2, 3)[1] - std::exp(-lambda * T));
}

TEST(DualTime, UniformStateDecaysAtTheSchemesOrder) {
  for (auto [scheme, order] : {std::pair{TimeConfig::Scheme::Bdf1, 1.0}, {TimeConfig::Scheme::Bdf2, 2.0}}) {
    const Real e1 = uniform_decay_error(scheme, 0.05), e2 = uniform_decay_error(scheme, 0.025),
               e3 = uniform_decay_error(scheme, 0.0125);
    std::printf("decay, order %.0f scheme: errors %.3e %.3e %.3e, orders %.3f %.3f\n", order, e1, e2, e3,
                std::log2(e1 / e2), std::log2(e2 / e3));
    EXPECT_NEAR(std::log2(e1 / e2), order, 0.1);
    EXPECT_NEAR(std::log2(e2 / e3), order, 0.06);
  }
}

TEST(DualTime, MultigridCyclesReachTheSameStepAnswer) {
  // The coarse levels carry the time term without the old levels (they cancel in the
  // forcing, §7.3): the converged steps are those of the single grid.
  const Real single = uniform_decay_error(TimeConfig::Scheme::Bdf2, 0.05, 1);
  const Real multigrid = uniform_decay_error(TimeConfig::Scheme::Bdf2, 0.05, 2);
  std::printf("decay error: single grid %.6e, multigrid %.6e\n", single, multigrid);
  EXPECT_NEAR(single, multigrid, 1e-9);
}

// Taylor-Green vortex, 2-D periodic, nu = 1 / Re: the discrete solution at T for
// decreasing dt on one grid; its differences give the order in time alone.
std::vector<State> taylor_green(TimeConfig::Scheme scheme, Real dt, int multigrid_levels = 1) {
  const Real T = 0.5, L = 2.0 * M_PI;
  Grid g = periodic_box(16, L);
  FlowParams fp;
  fp.reynolds = 10.0;
  FlowField f;
  f.allocate(g, fp, State::Zero());
  const Block& b = g.blocks[0];
  for_each_cell(b, [&](int i, int j, int k) {
    const Vec3 x = b.xc(i, j, k);
    f.Q[0](i, j, k) << 0.25 * (std::cos(2 * x[0]) + std::cos(2 * x[1])), std::sin(x[0]) * std::cos(x[1]),
        -std::cos(x[0]) * std::sin(x[1]), 0.0;
  });
  march(g, f, fp, scheme, dt, static_cast<int>(std::lround(T / dt)), multigrid_levels);
  std::vector<State> out;
  for_each_cell(b, [&](int i, int j, int k) { out.push_back(f.Q[0](i, j, k)); });
  return out;
}

Real velocity_difference(const std::vector<State>& a, const std::vector<State>& b) {
  Real s = 0.0;
  for (std::size_t n = 0; n < a.size(); ++n) s += (a[n].tail<3>() - b[n].tail<3>()).squaredNorm();
  return std::sqrt(s / a.size());
}

TEST(DualTime, TaylorGreenVortexIsSecondOrderInTimeWithBdf2) {
  const auto ref = taylor_green(TimeConfig::Scheme::Bdf2, 0.5 / 64);
  const auto q1 = taylor_green(TimeConfig::Scheme::Bdf2, 0.5 / 4), q2 = taylor_green(TimeConfig::Scheme::Bdf2, 0.5 / 8),
             q3 = taylor_green(TimeConfig::Scheme::Bdf2, 0.5 / 16);
  const Real e1 = velocity_difference(q1, ref), e2 = velocity_difference(q2, ref), e3 = velocity_difference(q3, ref);
  std::printf("Taylor-Green BDF2: differences %.3e %.3e %.3e, orders %.3f %.3f\n", e1, e2, e3, std::log2(e1 / e2),
              std::log2(e2 / e3));
  EXPECT_GT(std::log2(e1 / e2), 1.9);
  EXPECT_GT(std::log2(e2 / e3), 1.9);
  // and BDF1 is first order
  const auto r1 = taylor_green(TimeConfig::Scheme::Bdf1, 0.5 / 8), r2 = taylor_green(TimeConfig::Scheme::Bdf1, 0.5 / 16);
  const Real f1 = velocity_difference(r1, ref), f2 = velocity_difference(r2, ref);
  std::printf("Taylor-Green BDF1: differences %.3e %.3e, order %.3f\n", f1, f2, std::log2(f1 / f2));
  EXPECT_NEAR(std::log2(f1 / f2), 1.0, 0.15);
}

}  // namespace
}  // namespace narwhal
