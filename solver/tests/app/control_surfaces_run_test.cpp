// Control surfaces turned during a run ([controls], [autopilot], app/control_surfaces.hpp).
// The vehicle reading the autopilots take. A schedule: the small
// appended SUBOFF's rudders ramped from 0 to +-8 degrees over two steps, the grid
// deforming in place (a stationary prescribed motion). The rudders' side force follows
// the angle's sign (trailing edges to port push them to starboard), the opposite ramp
// gives the turned grid's forces, and a restart in the middle of the ramp continues bit
// for bit (the grids reshaped to both time levels). An autopilot: a heading loop answers
// a prescribed yaw as its PID says, and a restart continues it bit for bit.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "app/control_surfaces.hpp"
#include "app/driver.hpp"
#include "core/error.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

// Two BDF2 steps of 0.01 on the small appended grid, 2 or 3 sub-iterations each: what these
// tests check (signs, symmetry, the control law, restarts) holds before the steps converge.
const char* kTwoSteps = R"(
[solver]
multigrid_levels = 2
[time]
scheme = "bdf2"
step = 0.01
steps = 2
subiteration_drop = 1e-2
min_subiterations = 2
max_subiterations = 3
pseudo_cfl = 5.0
)";

std::string ramped_rudders(Real degrees, bool in_time = true) {
  return std::string(test::kSmallAppendedCase) + fmt::format(R"(
[controls.rudder]
times = [0.0, 0.02]
angles = [0.0, {}]
)", degrees) + (in_time ? kTwoSteps : "\n[solver]\nmultigrid_levels = 2\n");
}

const std::vector<std::string> kRoomyBoxes = {"grid.box_half_width=4"};

RunSummary run(const std::string& text, const fs::path& dir, std::vector<std::string> sets = kRoomyBoxes,
               std::optional<std::string> restart = std::nullopt) {
  RunOptions o;
  o.out_dir = dir.string();
  o.restart = restart;
  return run_case(parse_case(text, "appended.toml", ".", sets), o);
}

// Column `name` of steps.csv.
std::vector<Real> step_column(const fs::path& dir, const std::string& name) {
  return test::read_csv((dir / "steps.csv").string()).at(name);
}

TEST(ControlSurfacesRun, RampedRuddersPushTheSternAsTheirAngleSaysAndRestartBitForBit) {
  const fs::path port = test::fresh_temp_dir("narwhal_rudder_port"), starboard = test::fresh_temp_dir("narwhal_rudder_sb");
  ASSERT_EQ(run(ramped_rudders(8.0), port).status, RunStatus::Completed);
  ASSERT_EQ(run(ramped_rudders(-8.0), starboard).status, RunStatus::Completed);
  // Side force in grid axes (y = -y_B): trailing edges to port (+) push the rudders to
  // starboard (+y_B), both rudders alike.
  const std::vector<Real> upper = step_column(port, "upper_rudder_cfy"), lower = step_column(port, "lower_rudder_cfy");
  ASSERT_EQ(upper.size(), 2u);
  for (std::size_t n = 0; n < 2; ++n) {
    EXPECT_LT(upper[n], 0.0) << "step " << n + 1;
    EXPECT_LT(lower[n], 0.0) << "step " << n + 1;
  }
  // Turned 180 degrees about the axis, the grid maps onto itself with the upper rudder
  // at +8 onto the lower at -8: their side forces are opposite, to the sub-iterations'
  // error (measured 5e-9 and 6e-7 of the force; a mirror in one plane alone does not map
  // the sweeps' order and leaves 1e-3).
  const std::vector<Real> lower_minus = step_column(starboard, "lower_rudder_cfy");
  for (std::size_t n = 0; n < 2; ++n)
    EXPECT_NEAR(lower_minus[n], -upper[n], 1e-5 * std::abs(upper[n])) << "step " << n + 1;
  // Stopped at the ramp's middle and restarted: the grids are reshaped to both levels.
  const fs::path part = test::fresh_temp_dir("narwhal_rudder_part");
  std::vector<std::string> first = kRoomyBoxes;
  first.emplace_back("time.steps=1");
  ASSERT_EQ(run(ramped_rudders(8.0), part, first).status, RunStatus::Completed);
  ASSERT_EQ(run(ramped_rudders(8.0), part, kRoomyBoxes, (part / "restart.h5").string()).status, RunStatus::Completed);
  EXPECT_EQ(test::history_rows((part / "steps.csv").string()), test::history_rows((port / "steps.csv").string()));
}

TEST(ControlSurfaces, TheVehicleReadingIsTheTurnSinceReleaseAndItsEulerRates) {
  // A body turned by yaw psi, pitch theta, roll phi from its axes at release (grid_axes:
  // B0 = diag(-1, -1, 1)), with Euler rates given: the reading gives them back.
  const Real phi = 0.1, theta = 0.3, psi = -0.7, dphi = 0.2, dtheta = -0.4, dpsi = 0.9;
  const Mat3 turn = (Eigen::AngleAxis<Real>(psi, Vec3::UnitZ()) * Eigen::AngleAxis<Real>(theta, Vec3::UnitY()) *
                     Eigen::AngleAxis<Real>(phi, Vec3::UnitX())).toRotationMatrix();
  const Mat3 b0 = Vec3(-1.0, -1.0, 1.0).asDiagonal();
  RigidMotionSample m;
  m.pose.rotation = b0 * turn * b0.transpose();
  m.pose.displacement = Vec3(0.3, -0.2, 1.25);
  m.velocity = Vec3(-1.0, 0.1, 0.05);
  // Body rates from the Euler rates (NUMERICS §11.4 inverted), then to grid axes.
  const Vec3 pqr(dphi - dpsi * std::sin(theta), dtheta * std::cos(phi) + dpsi * std::cos(theta) * std::sin(phi),
                 -dtheta * std::sin(phi) + dpsi * std::cos(theta) * std::cos(phi));
  m.angular_velocity = m.pose.rotation * b0 * pqr;
  const VehicleReading r = read_vehicle(m);
  EXPECT_NEAR(r.pitch, theta, 1e-14);
  EXPECT_NEAR(r.heading, psi, 1e-14);
  EXPECT_NEAR(r.pitch_rate, dtheta, 1e-14);
  EXPECT_NEAR(r.heading_rate, dpsi, 1e-14);
  EXPECT_EQ(r.depth, 1.25);  // z_B down: the grid's +z
  EXPECT_EQ(r.depth_rate, 0.05);
}

// The small appended grid yawing to and fro: a prescribed oscillation of 2 degrees.
std::string yawing() {
  return std::string(test::kSmallAppendedCase) + kTwoSteps + R"(
[motion]
type = "prescribed"
pivot = [0.5, 0.0, 0.0]
[[motion.oscillation]]
dof = "yaw"
amplitude = 2.0
angular_frequency = 40.0
phase = 30.0
)";
}

// Yawing, its rudders under a heading autopilot holding 0.
std::string yawing_under_autopilot() {
  return yawing() + R"(
[autopilot]
heading = 0.0
[autopilot.heading_loop]
kp = 1.5
ki = 20.0
)";
}

TEST(ControlSurfacesRun, AHeadingAutopilotTurnsTheRuddersAgainstTheYawAndRestartsBitForBit) {
  const fs::path whole = test::fresh_temp_dir("narwhal_pilot_whole"), part = test::fresh_temp_dir("narwhal_pilot_part");
  ASSERT_EQ(run(yawing_under_autopilot(), whole).status, RunStatus::Completed);
  // Each step's rudder angle is the loop's answer to the heading at the step's start,
  // psi(t^n) = A sin(w t^n + phase): -(kp e + ki sum e dt) with e = 0 - psi (no derivative
  // gain; far inside the limits).
  const auto rows = test::read_csv((whole / "controls.csv").string());
  const std::vector<Real>& rudder = rows.at("rudder_deg");
  ASSERT_EQ(rudder.size(), 2u);
  const Real degree = 3.14159265358979323846 / 180.0, dt = 0.01;
  Real integral = 0.0;
  for (std::size_t n = 0; n < 2; ++n) {
    const Real psi = 2.0 * degree * std::sin(40.0 * dt * static_cast<Real>(n) + 30.0 * degree);
    integral += -psi * dt;
    EXPECT_NEAR(rudder[n] * degree, -(1.5 * -psi + 20.0 * integral), 1e-12) << "step " << n + 1;
  }
  EXPECT_GT(rudder[0], 0.0);  // yawed to starboard: trailing edges to port
  std::vector<std::string> first = kRoomyBoxes;
  first.emplace_back("time.steps=1");
  ASSERT_EQ(run(yawing_under_autopilot(), part, first).status, RunStatus::Completed);
  ASSERT_EQ(run(yawing_under_autopilot(), part, kRoomyBoxes, (part / "restart.h5").string()).status,
            RunStatus::Completed);
  EXPECT_EQ(test::history_rows((part / "steps.csv").string()), test::history_rows((whole / "steps.csv").string()));
  EXPECT_EQ(test::history_rows((part / "controls.csv").string()), test::history_rows((whole / "controls.csv").string()));
}

// The same yawing grid, its rudders in a zig-zag of 5 degrees reversed at 1 degree of
// heading, the first deflection to starboard's side (-1: trailing edges to starboard,
// driving the heading up).
std::string yawing_in_a_zigzag() {
  return yawing() + R"(
[zigzag]
surface = "rudder"
angle = 5.0
switch_at = 1.0
first = -1
)";
}

TEST(ControlSurfacesRun, AZigzagReversesTheRuddersAtItsHeadingAndRestartsBitForBit) {
  // Step 1 takes the first deflection, -5; step 2 begins at psi = 2 sin(0.4 + 30 deg) =
  // 1.6 degrees, past the 1 degree the -5 drove it towards: reversed to +5.
  const fs::path whole = test::fresh_temp_dir("narwhal_zigzag_whole"), part = test::fresh_temp_dir("narwhal_zigzag_part");
  ASSERT_EQ(run(yawing_in_a_zigzag(), whole).status, RunStatus::Completed);
  const auto rows = test::read_csv((whole / "controls.csv").string());
  EXPECT_EQ(rows.at("rudder_deg"), (std::vector<Real>{-5.0, 5.0}));
  std::vector<std::string> first = kRoomyBoxes;
  first.emplace_back("time.steps=1");
  ASSERT_EQ(run(yawing_in_a_zigzag(), part, first).status, RunStatus::Completed);
  ASSERT_EQ(run(yawing_in_a_zigzag(), part, kRoomyBoxes, (part / "restart.h5").string()).status, RunStatus::Completed);
  EXPECT_EQ(test::history_rows((part / "controls.csv").string()), test::history_rows((whole / "controls.csv").string()));
  EXPECT_EQ(test::history_rows((part / "steps.csv").string()), test::history_rows((whole / "steps.csv").string()));
}

TEST(ControlSurfacesRun, ASurfaceTheConfigurationLacksOrASteadyRunIsRefusedByKey) {
  auto error_of = [](const std::string& text, const std::vector<std::string>& sets) {
    try {
      (void)parse_case(text, "appended.toml", ".", sets);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string e = error_of(ramped_rudders(8.0), {"grid.box_half_width=4", "controls.sail_planes.times=[0.0]",
                                                 "controls.sail_planes.angles=[1.0]"});
  EXPECT_NE(e.find("controls.sail_planes"), std::string::npos) << e;
  EXPECT_NE(e.find("has no starboard_sail_plane"), std::string::npos) << e;
  e = error_of(ramped_rudders(8.0), {"controls.rudder.times=[0.0, 0.0]"});
  EXPECT_NE(e.find("controls.rudder.times"), std::string::npos) << e;
  e = error_of(ramped_rudders(8.0), {"controls.rudder.angles=[0.0, 1.0, 2.0]"});
  EXPECT_NE(e.find("controls.rudder.angles"), std::string::npos) << e;
  e = error_of(yawing_under_autopilot(), {"grid.box_half_width=4", "controls.rudder.times=[0.0]",
                                          "controls.rudder.angles=[1.0]"});
  EXPECT_NE(e.find("autopilot.heading"), std::string::npos) << e;
  EXPECT_NE(e.find("one of the two drives them"), std::string::npos) << e;
  e = error_of(yawing_under_autopilot(), {"autopilot.depth_change=1.0", "autopilot.pitch=2.0"});
  EXPECT_NE(e.find("autopilot.pitch"), std::string::npos) << e;
  e = error_of(yawing_under_autopilot(), {"autopilot.heading_loop.kp=-1.0"});
  EXPECT_NE(e.find("autopilot.heading_loop.kp"), std::string::npos) << e;
  e = error_of(yawing_under_autopilot(), {"zigzag.surface=\"rudder\"", "zigzag.angle=10.0"});
  EXPECT_NE(e.find("zigzag.surface"), std::string::npos) << e;
  EXPECT_NE(e.find("[autopilot]"), std::string::npos) << e;
  e = error_of(yawing_in_a_zigzag(), {"zigzag.first=0"});
  EXPECT_NE(e.find("zigzag.first"), std::string::npos) << e;
  e = error_of(yawing_in_a_zigzag(), {"zigzag.surface=\"sail_planes\""});
  EXPECT_NE(e.find("zigzag.surface"), std::string::npos) << e;
  e = error_of(ramped_rudders(8.0, false), {});
  EXPECT_NE(e.find("'controls'"), std::string::npos) << e;
  EXPECT_NE(e.find("physical time"), std::string::npos) << e;
}

}  // namespace
}  // namespace narwhal
