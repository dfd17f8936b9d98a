// Exact solutions of NUMERICS §12.3: plane Couette (exact on any grid) and plane
// Poiseuille (second order with the §4.5 wall flux).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "bc/boundary.hpp"
#include "implicit/newton.hpp"
#include "mesh/connectivity.hpp"
#include "mesh/generators.hpp"
#include "mesh/setup.hpp"
#include "physics/flow_rate.hpp"
#include "physics/wall_forces.hpp"

namespace narwhal {
namespace {

struct ChannelRun {
  Grid g;
  FlowField f;
  FlowParams fp;
  int iterations = 0;
  Real drop = 0.0;
};

// Channel 0<y<1, periodic in x, symmetric in z; bottom wall fixed, top wall at
// `top_speed`; optional streamwise body force G (pressure gradient -dp/dx = G), fixed
// or, with target_ub > 0, adjusted to that bulk velocity from G as first estimate.
ChannelRun run_channel(int ny, Real stretch_dy, Real top_speed, Real G, Real Re,
                       ViscousForm form = ViscousForm::Full, Real target_ub = 0.0, Real* final_G = nullptr) {
  ChannelRun r;
  auto ys = stretch_dy > 0 ? geometric_nodes(0.0, 1.0, ny, stretch_dy) : uniform_nodes(0.0, 1.0, ny);
  r.g.blocks.push_back(make_box("channel", uniform_nodes(0.0, 0.5, 4), ys, uniform_nodes(0.0, 0.1, 1)));
  assign_bc(r.g, "jmin", {BcType::Wall, Vec3::Zero(), 0.0});
  assign_bc(r.g, "jmax", {BcType::Wall, Vec3(top_speed, 0, 0), 0.0});
  assign_bc(r.g, "kmin", {BcType::Symmetry, Vec3::Zero(), 0.0});
  assign_bc(r.g, "kmax", {BcType::Symmetry, Vec3::Zero(), 0.0});
  connect_periodic(r.g, "imin", "imax", Mat3::Identity(), std::nullopt);
  finalize_grid(r.g);
  r.fp.reynolds = Re;
  r.fp.beta = 5.0;
  r.fp.viscous = form;
  if (G != 0.0) r.fp.sources = {position_source("body force", [G](const Vec3&) { return Vec3(G, 0.0, 0.0); })};
  std::unique_ptr<FlowRateControl> control;
  if (target_ub > 0.0) {
    control = std::make_unique<FlowRateControl>(Communicator::world(), r.g, Vec3(G, 0.0, 0.0), target_ub);
    r.fp.sources = {position_source("flow-rate control", control->source())};
  }
  State init;
  init << 0.0, 0.0, 0.0, 0.0;
  r.f.allocate(r.g, r.fp, init);
  NewtonSettings s;
  s.cfl_start = 1e6;
  s.sgs_iterations = 20;
  NewtonSolver solver(r.g, r.f, r.fp, s, Communicator::world());
  Real first = -1.0, last = 0.0;
  std::map<std::string, std::vector<WallFace>> faces;
  for (int it = 0; it < 500; ++it) {
    auto n = solver.iterate();
    if (control) {
      fill_ghosts(r.g, r.f, r.fp);
      wall_faces(r.g, r.f, r.fp, faces);
      control->update(r.g, r.f, faces);
      if (final_G) *final_G = control->force()[0];
    }
    if (first < 0) first = n.total;
    last = n.total;
    r.iterations = it + 1;
    if (last < 1e-14 * first || last < 1e-15) break;
  }
  r.drop = last / first;
  return r;
}

TEST(ExactSolutions, CouetteIsReproducedToRoundOff) {
  for (auto form : {ViscousForm::Full, ViscousForm::ThinLayer})
  for (Real dy : {0.0, 0.01}) {
    auto r = run_channel(16, dy, 1.0, 0.0, 100.0, form);
    const Block& b = r.g.blocks[0];
    Real err = 0.0;
    for (int j = 0; j < b.nj; ++j)
      for (int i = 0; i < b.ni; ++i) {
        const Real y = b.xc(i, j, 0).y();
        err = std::max(err, std::abs(r.f.Q[0](i, j, 0)[1] - y));
        err = std::max(err, std::abs(r.f.Q[0](i, j, 0)[2]));
      }
    EXPECT_LT(err, 1e-10) << "stretch " << dy << " after " << r.iterations << " iterations, drop " << r.drop;
  }
}

TEST(ExactSolutions, PoiseuilleConvergesAtSecondOrder) {
  const Real Re = 10.0, G = 0.8;
  std::vector<Real> err;
  for (int ny : {8, 16, 32}) {
    auto r = run_channel(ny, 0.0, 0.0, G, Re);
    const Block& b = r.g.blocks[0];
    Real e2 = 0.0;
    for (int j = 0; j < b.nj; ++j) {
      const Real y = b.xc(0, j, 0).y();
      const Real exact = 0.5 * Re * G * y * (1.0 - y);
      e2 += std::pow(r.f.Q[0](0, j, 0)[1] - exact, 2);
    }
    err.push_back(std::sqrt(e2 / b.nj));
  }
  for (std::size_t m = 1; m < err.size(); ++m) {
    const Real order = std::log(err[m - 1] / err[m]) / std::log(2.0);
    std::printf("Poiseuille: grid %d -> %d, L2 error %.6e -> %.6e, observed order %.6f\n", 8 << (m - 1), 8 << m,
                err[m - 1], err[m], order);
    EXPECT_GE(order, 1.999) << "grids " << m - 1 << "->" << m << " errors " << err[m - 1] << " " << err[m];
  }
}

TEST(FlowRateControl, FindsTheForceOfTheFixedForceRunWithItsBulkVelocity) {
  // Fixed G = 0.8 gives some discrete bulk velocity U_b; asking for that U_b from a
  // wrong first estimate (G = 0.3) must converge to the same discrete solution, G = 0.8.
  const Real Re = 10.0;
  auto fixed = run_channel(16, 0.0, 0.0, 0.8, Re);
  const FlowRateControl probe(Communicator::world(), fixed.g, Vec3(1.0, 0.0, 0.0), 1.0);
  const Real ub = probe.bulk_velocity(fixed.g, fixed.f);
  EXPECT_NEAR(ub / (Re * 0.8 / 12.0), 1.0, 1e-2);  // plane Poiseuille U_b = Re G / 12, to O(h^2)
  Real G = 0.0;
  auto controlled = run_channel(16, 0.0, 0.0, 0.3, Re, ViscousForm::Full, ub, &G);
  EXPECT_NEAR(G / 0.8, 1.0, 1e-9) << controlled.iterations << " iterations, drop " << controlled.drop;
  EXPECT_NEAR(probe.bulk_velocity(controlled.g, controlled.f) / ub, 1.0, 1e-10);
}

}  // namespace
}  // namespace narwhal
