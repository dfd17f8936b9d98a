// A free body coupled to the flow ([motion] type = "free", motion/coupled_body.hpp): a
// sphere released in still, inviscid fluid. Potential flow's only force on it is its
// added mass, 1/2 rho V (Lamb), so it falls with (rho_s - rho_f) g / (rho_s + rho_f / 2)
// for as long as the flow stays linear; a light body needs the added-mass estimate; a
// neutral one started in still fluid shares its momentum with its added mass; restarts
// continue bit for bit. A body-force propulsor behind the sphere (NUMERICS §9.5) moves
// with it, takes its advance speed from the motion and pushes it forward.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/driver.hpp"
#include "core/error.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

constexpr Real kVolume = std::numbers::pi / 6.0;  // D = 1

// The sphere's coarse body grid (its centre at x = 0.5) in inviscid fluid, still unless
// overridden.
std::string sphere_in_fluid() {
  return R"([case]
title = "Sphere released in still fluid"
[grid]
type = "body_of_revolution"
body = "sphere"
length = 1.0
cells_along = 8
cells_around = 4
cells_normal = 12
first_spacing = 0.04
pole_spacing = 0.08
far_field = 20.0
[flow]
reynolds = 1000.0
beta = 5.0
viscous = "inviscid"
initial_velocity = [0.0, 0.0, 0.0]
[bc.body]
type = "slip_wall"
[bc.farfield]
type = "farfield"
velocity = [0.0, 0.0, 0.0]
[solver]
sgs_iterations = 8
multigrid_levels = 2
max_iterations = 400
residual_drop = 1e-8
[output]
reference_area = 0.7853981634
moment_centre = [0.5, 0.0, 0.0]
)";
}

// Released: density ratio `ratio`, gravity 1 along -z, BDF2 steps of 0.02.
std::string released_sphere(Real ratio) {
  const Real mass = ratio * kVolume, inertia = 0.1 * mass;  // (2/5) m (D/2)^2
  return sphere_in_fluid() + fmt::format(R"(
[time]
scheme = "bdf2"
step = 0.02
steps = 6
subiteration_drop = 1e-3
min_subiterations = 2
max_subiterations = 40
[motion]
type = "free"
mass = {}
displaced_volume = {}
inertia = [{}, {}, {}]
gravity = [0.0, 0.0, -1.0]
origin = [0.5, 0.0, 0.0]
)",
                                          mass, kVolume, inertia, inertia, inertia);
}

// Column `name` of a CSV file the run wrote.
std::vector<Real> csv_column(const fs::path& file, const std::string& name) {
  const auto columns = test::read_csv(file.string());
  const auto c = columns.find(name);
  if (c == columns.end()) ADD_FAILURE() << file << ": no column " << name;
  return c == columns.end() ? std::vector<Real>{} : c->second;
}

// motion.csv's column `name`, one value per step.
std::vector<Real> column(const fs::path& dir, const std::string& name) { return csv_column(dir / "motion.csv", name); }

RunSummary run(const std::string& text, const fs::path& dir, const std::vector<std::string>& overrides = {},
               std::optional<std::string> restart = std::nullopt) {
  RunOptions o;
  o.out_dir = dir.string();
  o.restart = restart;
  return run_case(parse_case(text, "sphere.toml", ".", overrides), o);
}

TEST(FreeBodyRun, ASphereFallsWithItsAddedMass) {
  const fs::path dir = test::fresh_temp_dir("narwhal_free_fall");
  const RunSummary s = run(released_sphere(1.5), dir);
  ASSERT_EQ(s.status, RunStatus::Completed) << s.message;
  const std::vector<Real> w = column(dir, "w"), q = column(dir, "q");
  ASSERT_EQ(w.size(), 6u);
  // z_B = z: w is the fall's velocity along z. Past the start (BDF1's first step):
  const Real acceleration = (w[5] - w[3]) / 0.04, exact = -(1.5 - 1.0) / (1.5 + 0.5);
  // This coarse grid's added mass is 3 % low; the acceleration, (rho_s - 1) / (rho_s + C_a), 1 % high.
  EXPECT_NEAR(acceleration, exact, 0.03 * std::abs(exact));
  for (Real r : q) EXPECT_LT(std::abs(r), 1e-6);  // no turn: the centre is the origin
}

TEST(FreeBodyRun, ALightBodyNeedsTheAddedMassEstimate) {
  // rho_s = 0.2: m_a / m = 2.5, above the first step's limit (coupled_body.hpp): the
  // run without the estimate diverges at once; with it every step's coupling converges
  // and the body rises with its added mass (the force's mean over the last steps: a
  // decaying step-to-step oscillation of -0.73 per step remains, §11.6's interpolation).
  const fs::path plain = test::fresh_temp_dir("narwhal_light_plain"), estimated = test::fresh_temp_dir("narwhal_light");
  EXPECT_EQ(run(released_sphere(0.2), plain, {"time.steps=2"}).status, RunStatus::Diverged);
  const Real half = 0.5 * kVolume;
  const RunSummary e = run(released_sphere(0.2), estimated,
                           {"time.steps=10", fmt::format("motion.added_mass_estimate=[{0}, {0}, {0}, 0.0, 0.0, 0.0]", half)});
  ASSERT_EQ(e.status, RunStatus::Completed) << e.message;
  const std::vector<Real> z = column(estimated, "Z"), change = column(estimated, "coupling_change"),
                          its = column(estimated, "subiterations");
  for (std::size_t n = 0; n < change.size(); ++n) {
    EXPECT_LT(change[n], 1e-6) << "step " << n + 1;
    EXPECT_LT(its[n], 40) << "step " << n + 1;
  }
  const Real mean = (z[6] + z[7] + z[8] + z[9]) / 4.0;
  const Real exact = -half * (1.0 - 0.2) / (0.2 + 0.5);  // -m_a a, a upwards
  EXPECT_NEAR(mean, exact, 0.04 * std::abs(exact));
}

TEST(FreeBodyRun, ANeutralSphereStartedInStillFluidSharesItsMomentumWithItsAddedMass) {
  // Released at V0 in fluid at rest: V0 m / (m + m_a) = V0 / 1.5 once the fluid moves
  // with it (inviscid: nothing else acts), and stable at density ratio 1.
  const fs::path dir = test::fresh_temp_dir("narwhal_neutral");
  const RunSummary s = run(released_sphere(1.0), dir,
                           {"motion.gravity=[0.0, 0.0, 0.0]", "motion.velocity=[0.0, 0.0, -0.1]", "time.steps=8"});
  ASSERT_EQ(s.status, RunStatus::Completed) << s.message;
  const std::vector<Real> w = column(dir, "w"), change = column(dir, "coupling_change");
  for (Real c : change) EXPECT_LT(c, 1e-6);
  EXPECT_NEAR(w.back(), -0.1 / 1.5, 0.03 * 0.1 / 1.5);
}

// A DTMB 4119 disk of D = 0.5 just behind the sphere turning at 2 rev per unit time.
std::string propulsor_behind_the_sphere() {
  return fmt::format(R"(
[propulsor]
open_water = "{}"
diameter = 0.5
hub_ratio = 0.2
thickness = 0.08
centre = [1.2, 0.0, 0.0]
rps = 2.0
)", test::source_path("reference_data/propulsor/dtmb4119_open_water_openprop.csv"));
}

// The sphere held in a stream of 0.5 along +x (it heads into it: x_B = -x), then
// released weightless and free in surge, the propulsor behind it (J 0.5 at the start).
const std::vector<std::string> kInAStream = {"flow.initial_velocity=[0.5, 0.0, 0.0]", "bc.farfield.velocity=[0.5, 0.0, 0.0]"};
const std::vector<std::string> kReleasedInSurge = {"flow.initial_velocity=[0.5, 0.0, 0.0]",
                                                   "bc.farfield.velocity=[0.5, 0.0, 0.0]",
                                                   "motion.gravity=[0.0, 0.0, 0.0]", "motion.free=[\"surge\"]"};

// The towed flow with the propulsor working, converged: where the releases start.
fs::path towed_propelled_sphere() {
  static const fs::path dir = [] {
    const fs::path d = test::fresh_temp_dir("narwhal_propelled_towed");
    const RunSummary s = run(sphere_in_fluid() + propulsor_behind_the_sphere(), d, kInAStream);
    EXPECT_EQ(s.status, RunStatus::Converged) << s.message;
    return d;
  }();
  return dir / "restart.h5";
}

TEST(FreeBodyRun, APropulsorMovesWithTheBodyAndPushesItForward) {
  const fs::path dir = test::fresh_temp_dir("narwhal_propelled");
  const RunSummary s = run(released_sphere(1.0) + propulsor_behind_the_sphere(), dir, kReleasedInSurge,
                           towed_propelled_sphere().string());
  ASSERT_EQ(s.status, RunStatus::Completed) << s.message;
  const std::vector<Real> u = column(dir, "u"), X = column(dir, "X"), x = column(dir, "x"),
                          change = column(dir, "coupling_change");
  const std::vector<Real> its = csv_column(dir / "steps.csv", "subiterations"),
                          wall_cx = csv_column(dir / "steps.csv", "body_cfx");
  const std::vector<Real> thrust = csv_column(dir / "propulsor.csv", "thrust"),
                          advance = csv_column(dir / "propulsor.csv", "advance_speed");
  ASSERT_EQ(u.size(), 6u);
  const Real area = 0.7853981634;
  std::size_t last = 0;  // the row of each step's last sub-iteration
  for (std::size_t n = 0; n < u.size(); ++n) {
    last += static_cast<std::size_t>(its[n]);
    ASSERT_LE(last, thrust.size());
    EXPECT_LT(change[n], 1e-6) << "step " << n + 1;
    // The body's surge force is the walls' (x_B = -x) and the thrust, F = T e_a with
    // e_a = x_B (motion.csv keeps ten digits).
    const Real expected = -0.5 * area * wall_cx[n] + thrust[last - 1];
    EXPECT_NEAR(X[n], expected, 1e-9 * std::max(std::abs(X[n]), thrust[last - 1])) << "step " << n + 1;
    // The advance speed is the body's speed through the water (no wake fraction): its
    // own, u, and the stream's, taken at the last correction but one (the coupling's
    // change apart).
    EXPECT_NEAR(advance[last - 1], u[n] + 0.5, 1e-5) << "step " << n + 1;
    EXPECT_GT(thrust[last - 1], 0.0);
  }
  // The thrust (0.07) wins over the coarse grid's numerical drag on the inviscid sphere
  // (0.027 towed, with the disk's suction on it): the body speeds up forward.
  EXPECT_GT(u[0], 0.0);
  for (std::size_t n = 1; n < u.size(); ++n) EXPECT_GT(u[n], u[n - 1]) << "step " << n + 1;
  EXPECT_LT(x.back(), 0.5);
}

TEST(FreeBodyRun, APropelledRunRestartsBitForBit) {
  const fs::path whole = test::fresh_temp_dir("narwhal_propelled_whole"),
                 part = test::fresh_temp_dir("narwhal_propelled_part");
  const std::string text = released_sphere(1.0) + propulsor_behind_the_sphere();
  std::vector<std::string> first = kReleasedInSurge, all = kReleasedInSurge;
  first.push_back("time.steps=2");
  all.push_back("time.steps=4");
  ASSERT_EQ(run(text, whole, all, towed_propelled_sphere().string()).status, RunStatus::Completed);
  ASSERT_EQ(run(text, part, first, towed_propelled_sphere().string()).status, RunStatus::Completed);
  ASSERT_EQ(run(text, part, all, (part / "restart.h5").string()).status, RunStatus::Completed);
  for (const char* name : {"x", "u", "X"}) EXPECT_EQ(column(whole, name), column(part, name)) << name;
  EXPECT_EQ(csv_column(whole / "propulsor.csv", "thrust"), csv_column(part / "propulsor.csv", "thrust"));
}

TEST(FreeBodyRun, ANeutralSphereWhoseTankIsBlownRisesWithItsAddedMass) {
  // A tenth of the displaced water's weight blown at the centre, as a step at t = 0:
  // the sphere rises with dW / (m + m_a) = 0.1 / 1.5 (gravity along -z).
  const std::string blown = released_sphere(1.0) + fmt::format(R"(
[[motion.ballast]]
mass = {}
tank = [0.0, 0.0, 0.0]
)", 0.1 * kVolume);
  const fs::path dir = test::fresh_temp_dir("narwhal_blown");
  const RunSummary s = run(blown, dir);
  ASSERT_EQ(s.status, RunStatus::Completed) << s.message;
  const std::vector<Real> w = column(dir, "w");
  const Real acceleration = (w[5] - w[3]) / 0.04, exact = 0.1 / 1.5;
  // As ASphereFallsWithItsAddedMass: this grid's added mass is 3 % low.
  EXPECT_NEAR(acceleration, exact, 0.03 * exact);
  // Without gravity a change of ballast has no weight to change: refused, naming the key.
  try {
    (void)parse_case(blown, "sphere.toml", ".", {"motion.gravity=[0.0, 0.0, 0.0]"});
    ADD_FAILURE() << "a ballast change without gravity was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("motion.ballast[0].mass"), std::string::npos) << e.what();
  }
}

TEST(FreeBodyRun, TrimmedAtReleaseAHeavySphereWithItsWeightAheadStaysAtRest) {
  // Density ratio 1.2, its centre of gravity 0.05 ahead of O: untrimmed it sinks and
  // pitches; trimmed in heave and pitch (motion.trim) the weights balance W - B and
  // W x_G at release, and in still fluid nothing else acts.
  const std::vector<std::string> held = {"time.steps=3", "motion.centre_of_gravity=[0.05, 0.0, 0.0]",
                                         "motion.free=[\"heave\", \"pitch\"]"};
  std::vector<std::string> trimmed = held;
  trimmed.emplace_back("motion.trim=[\"heave\", \"pitch\"]");
  const fs::path still = test::fresh_temp_dir("narwhal_trimmed"), sinking = test::fresh_temp_dir("narwhal_untrimmed");
  ASSERT_EQ(run(released_sphere(1.2), still, trimmed).status, RunStatus::Completed);
  ASSERT_EQ(run(released_sphere(1.2), sinking, held).status, RunStatus::Completed);
  for (const char* name : {"w", "q"}) {
    for (Real v : column(still, name)) EXPECT_LT(std::abs(v), 1e-12) << name;
    EXPECT_GT(std::abs(column(sinking, name).back()), 1e-3) << name;
  }
  // Gravity along -z = -z_B: the weight taken out is W - B = 0.2 V, its first moment
  // W x_G (run.json, flow units).
  std::ifstream in(still / "run.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_NEAR(j["trim"]["weight"].get<Real>(), -0.2 * kVolume, 1e-14);
  EXPECT_NEAR(std::abs(j["trim"]["first_moment"].get<Real>()), 1.2 * kVolume * 0.05, 1e-14);
}

TEST(FreeBodyRun, AStepEndsWhenTheForcesHaveSettledIfTheCaseSaysSo) {
  // A residual drop the steps cannot reach (1e-12 in at most 30 sub-iterations) against
  // time.force_change = 1e-4: with it every step ends once the sphere's force changed by
  // less than 1e-4 of its largest component over its last sub-iteration (history.csv has
  // every sub-iteration's), and earlier than without.
  const std::vector<std::string> strict = {"time.subiteration_drop=1e-12", "time.max_subiterations=30",
                                           "time.steps=3"};
  std::vector<std::string> settled = strict;
  settled.emplace_back("time.force_change=1e-4");
  const fs::path all = test::fresh_temp_dir("narwhal_force_all"), early = test::fresh_temp_dir("narwhal_force_early");
  ASSERT_EQ(run(released_sphere(1.5), all, strict).status, RunStatus::Completed);
  ASSERT_EQ(run(released_sphere(1.5), early, settled).status, RunStatus::Completed);
  const std::vector<Real> its_all = csv_column(all / "steps.csv", "subiterations"),
                          its = csv_column(early / "steps.csv", "subiterations");
  ASSERT_EQ(its.size(), 3u);
  const std::vector<Real> fx = csv_column(early / "history.csv", "body_cfx"), fz = csv_column(early / "history.csv", "body_cfz");
  std::size_t last = 0;
  for (std::size_t n = 0; n < 3; ++n) {
    EXPECT_EQ(its_all[n], 30.0) << "step " << n + 1;
    EXPECT_LT(its[n], 30.0) << "step " << n + 1;
    last += static_cast<std::size_t>(its[n]);
    const Real scale = std::max(std::abs(fx[last - 1]), std::abs(fz[last - 1]));
    EXPECT_LT(std::max(std::abs(fx[last - 1] - fx[last - 2]), std::abs(fz[last - 1] - fz[last - 2])), 1e-4 * scale)
        << "step " << n + 1;
  }
}

TEST(FreeBodyRun, ARestartContinuesBitForBit) {
  const fs::path whole = test::fresh_temp_dir("narwhal_fall_whole"), part = test::fresh_temp_dir("narwhal_fall_part");
  ASSERT_EQ(run(released_sphere(1.5), whole).status, RunStatus::Completed);
  ASSERT_EQ(run(released_sphere(1.5), part, {"time.steps=3"}).status, RunStatus::Completed);
  ASSERT_EQ(run(released_sphere(1.5), part, {}, (part / "restart.h5").string()).status, RunStatus::Completed);
  for (const char* name : {"z", "w", "Z", "e0"}) EXPECT_EQ(column(whole, name), column(part, name)) << name;
}

}  // namespace
}  // namespace narwhal
