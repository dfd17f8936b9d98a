// The transport turbulence models in physical time (NUMERICS §6.1 with §8.6): decaying
// homogeneous turbulence. A uniform stream in a periodic box has no velocity gradient,
// so no production and no diffusion: Launder-Sharma's k and epsilon obey
//   dk/dt = -eps,  deps/dt = -C2 f2 eps^2 / k   (f2 = 1 at these turbulence Reynolds numbers)
// whose exact solution is k = k0 (1 + t / tau)^(-n), n = 1 / (C2 - 1), tau = n k0 / eps0
// (the classic power-law decay). BDF1 and BDF2 must reach it at their orders.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <Eigen/LU>
#include <fmt/format.h>

#include "app/driver.hpp"
#include "io/restart.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

constexpr Real kC2 = 1.92, kCmu = 0.09;
constexpr Real kIntensity = 0.1, kRatio = 10.0, kReynolds = 1.0e4;

constexpr Real kK0 = 1.5 * kIntensity * kIntensity, kEps0 = kCmu * kK0 * kK0 / (kRatio / kReynolds);

Real exact_k(Real t) {
  const Real n = 1.0 / (kC2 - 1.0), tau = n * kK0 / kEps0;
  return kK0 * std::pow(1.0 + t / tau, -n);
}

// The same ODE stepped by BDF1 or BDF2 (a BDF1 first step), each step solved by Newton:
// what the solver's time term must reproduce to round-off.
Real bdf_k(bool bdf2, int steps, Real end) {
  const Real dt = end / steps;
  Eigen::Vector2d y(kK0, kEps0), y_old = y;
  for (int s = 0; s < steps; ++s) {
    const bool second = bdf2 && s > 0;
    const Real c0 = second ? 1.5 : 1.0, c1 = second ? -2.0 : -1.0, c2 = second ? 0.5 : 0.0;
    Eigen::Vector2d z = y;
    for (int it = 0; it < 30; ++it) {
      const Real k = z[0], e = z[1];
      const Eigen::Vector2d f(-e, -kC2 * e * e / k);
      Eigen::Matrix2d jac;
      jac << 0.0, -1.0, kC2 * e * e / (k * k), -2.0 * kC2 * e / k;
      const Eigen::Vector2d r = (c0 * z + c1 * y + c2 * y_old) / dt - f;
      z -= (c0 / dt * Eigen::Matrix2d::Identity() - jac).lu().solve(r);
    }
    y_old = y;
    y = z;
  }
  return y[0];
}

// k at t = `end` from a run of `steps` steps; every step's sub-iterations converged.
Real k_at_end(const std::string& scheme, int steps, Real end) {
  const std::string text = fmt::format(R"(
[case]
title = "Decaying homogeneous turbulence"
[grid]
type = "box"
x = [0.0, 1.0, 2]
y = [0.0, 1.0, 2]
z = [0.0, 1.0, 2]
[flow]
reynolds = {}
initial_velocity = [1.0, 0.0, 0.0]
[turbulence]
model = "launder-sharma"
intensity = {}
freestream_nut_ratio = {}
[[periodic]]
a = "imin"
b = "imax"
[[periodic]]
a = "jmin"
b = "jmax"
[[periodic]]
a = "kmin"
b = "kmax"
[time]
scheme = "{}"
step = {}
steps = {}
subiteration_drop = 1e-11
max_subiterations = 60
)",
                                       kReynolds, kIntensity, kRatio, scheme, end / steps, steps);
  const CaseConfig c = parse_case(text, "decay.toml", ".");
  const fs::path dir = test::fresh_temp_dir("narwhal_decay");
  RunOptions o;
  o.out_dir = dir.string();
  const RunSummary s = run_case(c, o);
  EXPECT_EQ(s.status, RunStatus::Completed) << s.message;
  // k of the field the run ends with (its restart): uniform, as the decay is.
  Grid g = build_grid(c);
  FlowField f, previous;
  f.allocate(g, flow_params(c), c.initial);
  previous.allocate_states(g, c.initial);
  read_restart((dir / "restart.h5").string(), g, f, "launder-sharma", &previous);
  const Real k = f.turb[0](0, 0, 0)[0];
  EXPECT_NEAR(f.turb[0](1, 1, 1)[0], k, 1e-12 * k);
  return k;
}

TEST(TurbulenceInTime, DecayingTurbulenceIsTheBdfRecursionOfItsEquations) {
  const Real end = 1.6;
  for (const bool bdf2 : {false, true}) {
    const Real solver = k_at_end(bdf2 ? "bdf2" : "bdf1", 16, end), recursion = bdf_k(bdf2, 16, end);
    EXPECT_NEAR(solver, recursion, 1e-10 * recursion) << (bdf2 ? "bdf2" : "bdf1");
  }
}

TEST(TurbulenceInTime, DecayingTurbulenceReachesThePowerLawAtTheSchemesOrder) {
  // 128 to 512 steps: BDF2's first (BDF1) step and its own error cancel in part on
  // coarser steps (orders 1.7-1.9 there, the same for the recursion of the ODE itself).
  const Real end = 1.6;
  for (const auto& [scheme, order] : {std::pair<std::string, Real>{"bdf1", 1.0}, {"bdf2", 2.0}}) {
    Real errors[3];
    for (int r = 0; r < 3; ++r) errors[r] = std::abs(k_at_end(scheme, 128 << r, end) - exact_k(end));
    const Real p1 = std::log2(errors[0] / errors[1]), p2 = std::log2(errors[1] / errors[2]);
    std::printf("%s: k errors %.3e %.3e %.3e, observed orders %.3f %.3f\n", scheme.c_str(), errors[0], errors[1],
                errors[2], p1, p2);
    EXPECT_GT(p2, order - 0.1) << scheme;
    EXPECT_LT(errors[2], 0.05 * exact_k(end)) << scheme;
  }
}

}  // namespace
}  // namespace narwhal
