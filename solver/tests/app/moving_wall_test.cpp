// A moving grid with its wall (NUMERICS §5.1, §2.4): Stokes' second problem. The whole
// grid of a periodic channel oscillates along x with the plate at its bottom; the water
// far above is at rest. The periodic state is u = U e^{-ky} cos(w t - pi/2 - k y),
// k = sqrt(w / (2 nu)), for the plate velocity U sin(w t), and its wall shear stress
// tau_w = nu U k (-cos w t - sin w t) (Landau & Lifshitz, Fluid Mechanics §24).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <Eigen/Cholesky>
#include <fmt/format.h>

#include "app/driver.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

TEST(MovingWall, StokesSecondProblemWallShearHasTheExactAmplitudeAndPhase) {
  const Real omega = 2.0 * M_PI, amplitude = 0.01, nu = 0.01;
  const int per_period = 40, periods = 4;
  const std::string text = fmt::format(R"(
[case]
title = "Stokes' second problem on an oscillating grid"
[grid]
type = "box"
x = [0.0, 0.1, 1]
y = [0.0, 0.6, 48]
z = [0.0, 0.1, 1]
first_spacing_y = 0.002
[flow]
reynolds = {}
initial_velocity = [0.0, 0.0, 0.0]
[bc.jmin]
type = "wall"
[bc.jmax]
type = "farfield"
velocity = [0.0, 0.0, 0.0]
[bc.kmin]
type = "symmetry"
[bc.kmax]
type = "symmetry"
[[periodic]]
a = "imin"
b = "imax"
[time]
scheme = "bdf2"
step = {}
steps = {}
subiteration_drop = 1e-6
max_subiterations = 30
[motion]
type = "prescribed"
[[motion.oscillation]]
dof = "x"
amplitude = {}
angular_frequency = {}
phase = -90.0
[output]
reference_area = 0.02   # twice the plate's area: cfx is the mean wall shear stress
)", 1.0 / nu, 2.0 * M_PI / omega / per_period, per_period * periods, amplitude, omega);
  const CaseConfig c = parse_case(text, "stokes2.toml", ".");
  const fs::path dir = test::fresh_temp_dir("narwhal_stokes_second");
  RunOptions o;
  o.out_dir = dir.string();
  const RunSummary s = run_case(c, o);
  ASSERT_EQ(s.status, RunStatus::Completed) << s.message;
  // Least-squares fit tau = a sin(w t) + b cos(w t) over the last period.
  const auto steps = test::read_csv((dir / "steps.csv").string());
  const auto& t = steps.at("time");
  const auto& tau = steps.at("jmin_cfx");
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d r = Eigen::Vector2d::Zero();
  for (std::size_t n = t.size() - per_period; n < t.size(); ++n) {
    const Eigen::Vector2d phi(std::sin(omega * t[n]), std::cos(omega * t[n]));
    A += phi * phi.transpose();
    r += phi * tau[n];
  }
  const Eigen::Vector2d ab = A.ldlt().solve(r);
  const Real U = amplitude * omega, k = std::sqrt(omega / (2.0 * nu));
  const Real exact_amplitude = std::sqrt(2.0) * nu * U * k, exact_phase = std::atan2(-1.0, -1.0);
  const Real amp = ab.norm(), phase = std::atan2(ab[1], ab[0]);
  std::printf("Stokes' second problem: wall shear amplitude %.5e (exact %.5e, %+.2f %%), phase %.4f (exact %.4f)\n", amp,
              exact_amplitude, 100.0 * (amp / exact_amplitude - 1.0), phase, exact_phase);
  // 1 %, 0.01 rad: BDF2 at 40 steps per period errs by about (w dt)^2 / 12 = 0.2 %
  // in phase speed, the 48 cells (13 across the Stokes layer) by a few 0.1 %.
  EXPECT_NEAR(amp / exact_amplitude, 1.0, 0.01);
  EXPECT_NEAR(phase, exact_phase, 0.01);
}

}  // namespace
}  // namespace narwhal
