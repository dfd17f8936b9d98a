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
  // the transport models carry no physical-time term yet
  e = error_of({"time.scheme=\"bdf2\"", "time.step=0.1", "time.steps=2", "turbulence.model=\"sst\""});
  EXPECT_NE(e.find("time.scheme"), std::string::npos) << e;
  EXPECT_NE(e.find("sst"), std::string::npos) << e;
}

TEST(DualTimeRun, ContinuingFromARestartIsRefusedSayingWhy) {
  const CaseConfig c = parse_case(plate_text(), "plate.toml", ".", small_plate(kBdf2));
  const fs::path dir = test::fresh_temp_dir("narwhal_dual_time_restart");
  RunOptions o;
  o.out_dir = (dir / "a").string();
  run_case(c, o);
  RunOptions again;
  again.out_dir = (dir / "b").string();
  again.restart = (dir / "a" / "restart.h5").string();
  try {
    run_case(c, again);
    FAIL() << "a dual-time restart was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("dual-time"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace narwhal
