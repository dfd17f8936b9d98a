// `narwhal simulate` (app/simulate.hpp): a case's manoeuvre flown by a manoeuvring model.
// A linear model under a rudder step settles into the linear steady turn; a heavy vehicle
// out of trim, trimmed at release, stays at rest; the zig-zag law reverses the stern planes
// as in a CFD run; the model file's mistakes are named.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/simulate.hpp"
#include "core/error.hpp"
#include "manoeuvring/linear_turn.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

constexpr Real kMass = 0.0085;

// The small appended grid (never built: simulate reads the case alone) as a free vehicle
// in still water, moving ahead at 1 (x_B = -x), free in `free`.
std::string free_vehicle(const std::string& free, const std::string& more) {
  return std::string(test::kSmallAppendedCase) + fmt::format(R"(
[time]
scheme = "bdf2"
step = 0.01
steps = {}
[motion]
type = "free"
mass = {}
displaced_volume = {}
inertia = [1.5e-5, 4.85e-4, 4.85e-4]
origin = [0.46, 0.0, 0.0]
velocity = [-1.0, 0.0, 0.0]
free = {}
{})", 6000, kMass, kMass, free, more);
}

CaseConfig still_water(const std::string& text, const std::vector<std::string>& sets = {}) {
  std::vector<std::string> all = {"bc.farfield.velocity=[0.0, 0.0, 0.0]", "grid.box_half_width=4"};
  all.insert(all.end(), sets.begin(), sets.end());
  return parse_case(text, "vehicle.toml", ".", all);
}

ManoeuvringModel linear_model() {
  ManoeuvringModel m;
  m.coefficients = test::linear_turning_coefficients();
  return m;
}

TEST(Simulate, ALinearModelUnderARudderStepSettlesIntoTheLinearSteadyTurn) {
  const fs::path dir = test::fresh_temp_dir("narwhal_simulate_turn");
  const CaseConfig c = still_water(free_vehicle("[\"sway\", \"yaw\"]", R"(
[controls.rudder]
times = [0.0, 0.1]
angles = [0.0, 10.0]
)"));
  const ManoeuvringModel m = linear_model();
  const SimulationSummary s = simulate(c, m, dir.string());
  EXPECT_EQ(s.steps, 6000);
  const auto motion = test::read_csv((dir / "motion.csv").string());
  const std::vector<Real>& r = motion.at("r");
  ASSERT_EQ(r.size(), 6000u);
  // Surge held at 1 through still water: m u r = Y, 0 = N (as the model's own test).
  const Real dr = 10.0 * std::acos(-1.0) / 180.0;
  const Eigen::Vector2d steady = test::linear_steady_turn(m.coefficients, kMass, dr);
  EXPECT_NEAR(r.back(), steady[1], 1e-6 * std::abs(steady[1]));
  EXPECT_NEAR(motion.at("v").back(), steady[0], 1e-6 * std::abs(steady[0]));
  // The rudder's angle in controls.csv, degrees.
  EXPECT_NEAR(test::read_csv((dir / "controls.csv").string()).at("rudder_deg").back(), 10.0, 1e-12);
}

TEST(Simulate, AVehicleOutOfTrimTrimmedAtReleaseStaysAtRest) {
  // The model's Z'_0 and M'_0 (a sail's lift and moment at zero incidence) and a centre of
  // gravity 0.01 ahead of O: trimmed in heave and pitch, it goes straight on; untrimmed it does not.
  ManoeuvringModel m = linear_model();
  m.coefficients.Z0 = -0.0004;
  m.coefficients.M0 = 0.0001;
  m.coefficients.Zw = -0.015;
  m.coefficients.Mw = 0.006;
  m.coefficients.Zq = -0.007;
  m.coefficients.Mq = -0.003;
  const std::string vehicle = free_vehicle("[\"heave\", \"pitch\"]", R"(gravity = [0.0, 0.0, 4.59]
centre_of_gravity = [0.01, 0.0, 0.005]
)");
  const fs::path trimmed = test::fresh_temp_dir("narwhal_simulate_trimmed"), loose = test::fresh_temp_dir("narwhal_simulate_loose");
  (void)simulate(still_water(vehicle, {"time.steps=300", "motion.trim=[\"heave\", \"pitch\"]"}), m, trimmed.string());
  (void)simulate(still_water(vehicle, {"time.steps=300"}), m, loose.string());
  for (const char* name : {"w", "q", "z"}) {
    for (Real v : test::read_csv((trimmed / "motion.csv").string()).at(name)) EXPECT_LT(std::abs(v), 1e-14) << name;
    EXPECT_GT(std::abs(test::read_csv((loose / "motion.csv").string()).at(name).back()), 1e-4) << name;
  }
}

// The error loading a model file of `text`, or "" when it loads.
std::string model_error(const std::string& text) {
  const fs::path dir = test::fresh_temp_dir("narwhal_simulate_model");
  std::ofstream(dir / "model.toml") << text;
  try {
    (void)load_manoeuvring_model((dir / "model.toml").string());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Simulate, ModelFileMistakesAreNamed) {
  std::string e = model_error("[coefficients]\nYv = -0.03\nNvdt = 0.1\n");
  EXPECT_NE(e.find("coefficients.Nvdt"), std::string::npos) << "a misspelled coefficient: " << e;
  EXPECT_NE(e.find("coefficients.Nvdot"), std::string::npos) << e;
  e = model_error("[coefficients]\nYv = -0.03\n[propulsion]\nwake_fraction = 0.2\n");
  EXPECT_NE(e.find("propulsion.rps"), std::string::npos) << "a propulsion table without its rotation rate: " << e;
}

}  // namespace
}  // namespace narwhal
