// A dual-time run from its case file ([time]): the steps it takes and writes, and the
// input it refuses, naming the key.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "app/driver.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

// The laminar plate, small, impulsively started (uniform stream on a no-slip plate).
std::vector<std::string> small_plate(std::vector<std::string> more) {
  std::vector<std::string> o = {"grid.cells_runup=8", "grid.cells_plate=24", "grid.cells_normal=24",
                                "grid.dx_leading_edge=1.0e-2", "grid.dy_wall=1.0e-3"};
  o.insert(o.end(), more.begin(), more.end());
  return o;
}

std::string plate_text() { return test::read_text(test::source_path("validation/cases/flat_plate_laminar/flat_plate.toml")); }

std::string error_of(const std::vector<std::string>& overrides) {
  try {
    parse_case(plate_text(), "plate.toml", ".", small_plate(overrides));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const std::vector<std::string> kBdf2 = {"time.scheme=\"bdf2\"", "time.step=0.05", "time.steps=4",
                                        "time.max_subiterations=6", "time.subiteration_drop=1e-3"};

TEST(DualTimeRun, TakesItsStepsAndWritesOneRowPerStep) {
  const CaseConfig c = parse_case(plate_text(), "plate.toml", ".", small_plate(kBdf2));
  const fs::path dir = test::fresh_temp_dir("narwhal_dual_time_run");
  RunOptions o;
  o.out_dir = dir.string();
  const RunSummary s = run_case(c, o);
  EXPECT_EQ(s.status, RunStatus::Completed) << s.message;
  const auto steps = test::read_csv((dir / "steps.csv").string());
  ASSERT_EQ(steps.at("step").size(), 4u);
  int subiterations = 0;
  for (std::size_t n = 0; n < 4; ++n) {
    EXPECT_NEAR(steps.at("time")[n], 0.05 * (n + 1), 1e-14);
    EXPECT_GE(steps.at("subiterations")[n], 1.0);
    EXPECT_LE(steps.at("subiterations")[n], 6.0);
    subiterations += static_cast<int>(steps.at("subiterations")[n]);
  }
  // every sub-iteration is a row of history.csv; the plate's drag is there at each step
  EXPECT_EQ(s.iterations, subiterations);
  EXPECT_EQ(test::read_csv((dir / "history.csv").string()).at("iteration").size(), static_cast<std::size_t>(subiterations));
  EXPECT_GT(steps.at("plate_cfx")[3], 0.0);
  EXPECT_NE(test::read_text((dir / "run.json").string()).find("\"status\": \"completed\""), std::string::npos);
}

TEST(DualTimeRun, BadTimeInputIsNamed) {
  std::string e = error_of({"time.scheme=\"rk4\"", "time.step=0.1", "time.steps=2"});
  EXPECT_NE(e.find("time.scheme"), std::string::npos) << e;
  EXPECT_NE(e.find("bdf2"), std::string::npos) << e;
  e = error_of({"time.scheme=\"bdf2\"", "time.steps=2"});
  EXPECT_NE(e.find("time.step"), std::string::npos) << e;
  e = error_of({"time.scheme=\"bdf1\"", "time.step=0.1", "time.steps=2", "time.min_subiterations=5",
                "time.max_subiterations=3"});
  EXPECT_NE(e.find("time.max_subiterations"), std::string::npos) << e;
}

// The plate moving with its grid (a heaving, pitching oscillation) and BDF2: stopped
// at a restart and continued, the run's steps and iterations are the uninterrupted
// run's bit for bit; also with the blocks cut into pieces (the restart in the case's
// layout) and with multigrid (every level's grid placed again).
const std::vector<std::string> kMovingPlate = {
    "time.scheme=\"bdf2\"", "time.step=0.05", "time.steps=8", "time.max_subiterations=4",
    "motion.type=\"prescribed\"", "motion.pivot=[0.5, 0.0, 0.0]",
    "motion.oscillation=[{dof=\"y\", amplitude=0.02, angular_frequency=6.0}, "
    "{dof=\"pitch\", amplitude=2.0, angular_frequency=6.0, phase=30.0}]"};

// The plate with overrides `o` run whole, and stopped after 3 steps and continued from
// its restart: the same steps and iterations to the last digit.
void expect_continued_run_repeats_the_whole(const std::vector<std::string>& o) {
  const CaseConfig c = parse_case(plate_text(), "plate.toml", ".", small_plate(o));
  const fs::path dir = test::fresh_temp_dir("narwhal_dual_time_restart");
  RunOptions whole;
  whole.out_dir = (dir / "whole").string();
  const RunSummary w = run_case(c, whole);
  ASSERT_EQ(w.status, RunStatus::Completed) << w.message;
  const CaseConfig first = parse_case(plate_text(), "plate.toml", ".", [&] {
    auto f = small_plate(o);
    f.push_back("time.steps=3");
    return f;
  }());
  RunOptions split;
  split.out_dir = (dir / "split").string();
  run_case(first, split);
  RunOptions resumed = split;
  resumed.restart = (dir / "split" / "restart.h5").string();
  const RunSummary r = run_case(c, resumed);
  ASSERT_EQ(r.status, RunStatus::Completed) << r.message;
  EXPECT_EQ(r.iterations, w.iterations);
  auto rows = [](const fs::path& p) {
    auto t = test::read_csv(p.string());
    t.erase("wall_s");
    return t;
  };
  EXPECT_EQ(rows(dir / "split" / "steps.csv"), rows(dir / "whole" / "steps.csv"));
  EXPECT_EQ(rows(dir / "split" / "history.csv"), rows(dir / "whole" / "history.csv"));
}

void expect_restart_equals_uninterrupted(std::vector<std::string> extra) {
  std::vector<std::string> o = kMovingPlate;
  o.insert(o.end(), extra.begin(), extra.end());
  expect_continued_run_repeats_the_whole(o);
}

TEST(DualTimeRun, Bdf2RestartOnAMovingGridEqualsTheUninterruptedRun) { expect_restart_equals_uninterrupted({}); }

TEST(DualTimeRun, Bdf2RestartEqualsTheUninterruptedRunInPiecesAndWithMultigrid) {
  expect_restart_equals_uninterrupted({"parallel.split_for=2", "solver.multigrid_levels=2"});
}

TEST(DualTimeRun, Bdf2RestartOfATurbulentRunEqualsTheUninterruptedRun) {
  // SST's k and omega carry their level n-1 in the restart like the mean flow's Q.
  std::vector<std::string> o = kBdf2;
  o.insert(o.end(), {"turbulence.model=\"sst\"", "time.steps=8", "time.max_subiterations=4"});
  expect_continued_run_repeats_the_whole(o);
}

TEST(DualTimeRun, Bdf2RestartOfATurbulentRunOnAMovingGridEqualsTheUninterruptedRun) {
  // The eddy viscosity a step starts from is made on that step's grid, which a restart
  // places as the run did (the face speeds of the step before are not in the file).
  expect_restart_equals_uninterrupted({"turbulence.model=\"sst\""});
  expect_restart_equals_uninterrupted({"turbulence.model=\"sst\"", "parallel.split_for=2", "solver.multigrid_levels=2"});
}

TEST(DualTimeRun, ASteadyRunDoesNotTakeADualTimeRestart) {
  const CaseConfig c = parse_case(plate_text(), "plate.toml", ".", small_plate(kBdf2));
  const fs::path dir = test::fresh_temp_dir("narwhal_dual_time_into_steady");
  RunOptions o;
  o.out_dir = (dir / "a").string();
  run_case(c, o);
  RunOptions again;
  again.out_dir = (dir / "b").string();
  again.restart = (dir / "a" / "restart.h5").string();
  again.max_iterations = 2;
  try {
    run_case(parse_case(plate_text(), "plate.toml", ".", small_plate({})), again);
    FAIL() << "a steady run took a dual-time restart";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("[time]"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace narwhal
