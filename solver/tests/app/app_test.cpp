// Application contract (issue bar 6 and the outputs): clear errors for bad input,
// restart equality, divergence diagnostics, and a CGNS file that cgnscheck accepts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "app/driver.hpp"
#include "io/restart.hpp"
#include "mesh/plot3d.hpp"
#include "mesh/grid_quality.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

std::string flat_plate_text() {
  return slurp(test::source_path("validation/cases/flat_plate_laminar/flat_plate.toml"));
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  return s.replace(pos, from.size(), to);
}

std::string error_of(const std::string& text, const std::string& name = "case.toml") {
  try {
    CaseConfig c = parse_case(text, name, ".");
    build_grid(c);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(CaseErrors, MissingKeyNamesFileKeyAndExpectation) {
  const std::string e = error_of(replace(flat_plate_text(), "reynolds = 1.0e5", ""), "plate.toml");
  EXPECT_NE(e.find("plate.toml"), std::string::npos) << e;
  EXPECT_NE(e.find("flow.reynolds"), std::string::npos) << e;
  EXPECT_NE(e.find("missing required key"), std::string::npos) << e;
}

TEST(CaseErrors, MisspelledKeySuggestsTheRightOne) {
  const std::string e = error_of(replace(flat_plate_text(), "cells_plate", "cells_plat"), "plate.toml");
  EXPECT_NE(e.find("unknown key 'grid.cells_plat'"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean 'grid.cells_plate'"), std::string::npos) << e;
}

TEST(CaseBase, ACaseLaidOverABaseSaysOnlyWhatDiffers) {
  // `base`: the flat plate's case as the base; this one changes its Reynolds number and a
  // grid count, adds a key, and keeps everything else, overrides applying last.
  const fs::path dir = test::fresh_temp_dir("narwhal_case_base");
  {
    std::ofstream(dir / "plate.toml") << flat_plate_text();
  }
  const std::string derived = "base = \"plate.toml\"\n[case]\ntitle = \"derived\"\n[flow]\nreynolds = 2.0e5\n";
  const CaseConfig plain = parse_case(flat_plate_text(), "plate.toml", dir.string());
  const CaseConfig c = parse_case(derived, "derived.toml", dir.string());
  EXPECT_EQ(c.title, "derived");
  EXPECT_EQ(c.flow.reynolds, 2.0e5);
  EXPECT_EQ(c.grid.plate.n_plate, plain.grid.plate.n_plate);
  EXPECT_EQ(c.grid.plate.dy_wall, plain.grid.plate.dy_wall);
  EXPECT_EQ(c.bcs.size(), plain.bcs.size());
  EXPECT_EQ(c.solver.max_iterations, plain.solver.max_iterations);
  EXPECT_NE(c.text.find("# ---- base: "), std::string::npos);  // the restart keeps both texts
  const CaseConfig o = parse_case(derived, "derived.toml", dir.string(), {"flow.reynolds=3.0e5"});
  EXPECT_EQ(o.flow.reynolds, 3.0e5);
  // A base may have a base: the third file over the derived over the plate.
  {
    std::ofstream(dir / "derived.toml") << derived;
  }
  const CaseConfig third = parse_case("base = \"derived.toml\"\n[solver]\nmax_iterations = 7\n", "third.toml", dir.string());
  EXPECT_EQ(third.flow.reynolds, 2.0e5);
  EXPECT_EQ(third.solver.max_iterations, 7);
  EXPECT_EQ(third.grid.plate.n_plate, plain.grid.plate.n_plate);
  // A misspelled key of the derived case is named; a missing base, or bases in a loop, too.
  auto error_in = [&](const std::string& text) {
    try {
      (void)parse_case(text, "derived.toml", dir.string());
    } catch (const Error& x) {
      return std::string(x.what());
    }
    return std::string();
  };
  std::string e = error_in(derived + "[solver]\nmax_iteratons = 3\n");
  EXPECT_NE(e.find("unknown key 'solver.max_iteratons'"), std::string::npos) << e;
  e = error_in("base = \"nowhere.toml\"\n");
  EXPECT_NE(e.find("'base'"), std::string::npos) << e;
  EXPECT_NE(e.find("nowhere.toml"), std::string::npos) << e;
  {
    std::ofstream(dir / "loop.toml") << "base = \"loop.toml\"\n";
  }
  e = error_in("base = \"loop.toml\"\n");
  EXPECT_NE(e.find("loops"), std::string::npos) << e;
  // A file a base names is found beside the base, wherever the case laid over it lies; a
  // file the case names (or an override) beside the case.
  fs::create_directories(dir / "tables");
  fs::create_directories(dir / "cases");
  fs::copy_file(test::source_path("reference_data/propulsor/dtmb4119_open_water_openprop.csv"), dir / "tables" / "curve.csv",
                fs::copy_options::overwrite_existing);
  {
    std::ofstream(dir / "tables" / "propelled.toml")
        << flat_plate_text()
        << "[propulsor]\nopen_water = \"curve.csv\"\ndiameter = 0.06\nhub_ratio = 0.21\nthickness = 0.012\n"
           "centre = [0.987, 0.0, 0.0]\nrps = 16.0\n";
  }
  const CaseConfig beside_base = parse_case("base = \"../tables/propelled.toml\"\n", "c.toml", (dir / "cases").string());
  ASSERT_TRUE(beside_base.propulsor.has_value());
  e = error_in("base = \"tables/propelled.toml\"\n[propulsor]\nopen_water = \"curve.csv\"\n");
  EXPECT_NE(e.find("propulsor.open_water"), std::string::npos) << "the case's own name is the case's: " << e;
  // A device or a directory as the base is refused, not read without end.
  for (const char* other : {"/dev/zero", "."}) {
    e = error_in(fmt::format("base = \"{}\"\n", other));
    EXPECT_NE(e.find("'base'"), std::string::npos) << e;
    EXPECT_NE(e.find("regular file"), std::string::npos) << e;
  }
}

TEST(CaseErrors, ACaseFileThatIsNoRegularFileIsRefused) {
  for (const char* other : {"/dev/zero", "/tmp"}) {
    try {
      (void)load_case(other, {});
      ADD_FAILURE() << other << " was read as a case";
    } catch (const Error& x) {
      EXPECT_NE(std::string(x.what()).find(other), std::string::npos) << x.what();
      EXPECT_NE(std::string(x.what()).find("regular file"), std::string::npos) << x.what();
    }
  }
}

TEST(CaseErrors, WrongTypeSaysWhatWasExpected) {
  const std::string e = error_of(replace(flat_plate_text(), "reynolds = 1.0e5", "reynolds = \"high\""));
  EXPECT_NE(e.find("flow.reynolds"), std::string::npos) << e;
  EXPECT_NE(e.find("got a string"), std::string::npos) << e;
}

TEST(CaseErrors, UnknownBoundaryTypeListsTheValidOnes) {
  const std::string e = error_of(replace(flat_plate_text(), "type = \"wall\"", "type = \"wal\""));
  EXPECT_NE(e.find("bc.plate.type"), std::string::npos) << e;
  EXPECT_NE(e.find("valid types: wall"), std::string::npos) << e;
}

// The model's scheme: its defaults by model, and a clear error for another value.
TEST(CaseErrors, TurbulenceSchemeDefaultsByModelAndBadValuesAreNamed) {
  const std::string sa = slurp(test::source_path("validation/cases/tmr_flat_plate/flat_plate_sa.toml"));
  const CaseConfig c = parse_case(sa, "sa.toml", ".");
  EXPECT_EQ(c.turbulence.smoother, "lines");
  EXPECT_EQ(c.turbulence.coupling, "smoothing");
  const CaseConfig mk = parse_case(sa, "sa.toml", ".", {"turbulence.model=\"myong-kasagi\""});
  EXPECT_EQ(mk.turbulence.smoother, "points");
  const CaseConfig forced = parse_case(sa, "sa.toml", ".", {"turbulence.smoother=\"points\""});
  EXPECT_EQ(forced.turbulence.smoother, "points");
  EXPECT_EQ(c.turbulence.iterations, 1);
  EXPECT_EQ(c.turbulence.relaxation, 0.7);
  const CaseConfig sst = parse_case(sa, "sa.toml", ".", {"turbulence.model=\"sst\""});
  EXPECT_EQ(sst.turbulence.iterations, 2);
  EXPECT_EQ(sst.turbulence.relaxation, 1.0);
  EXPECT_EQ(parse_case(sa, "sa.toml", ".", {"turbulence.model=\"sst\"", "turbulence.iterations=1"}).turbulence.iterations,
            1);
  // The low-Re k-epsilon models start with the robust scheme; the others have no start.
  EXPECT_EQ(*c.turbulence.start.force_span, 0.0);
  EXPECT_EQ(*mk.turbulence.start.force_span, 1e-2);
  EXPECT_EQ(mk.turbulence.start.coupling, "cycle");
  EXPECT_EQ(*mk.turbulence.start.relaxation, 0.7);
  EXPECT_EQ(mk.turbulence.coupling, "smoothing");
  EXPECT_EQ(*mk.turbulence.relaxation, 1.0);
  EXPECT_EQ(*mk.turbulence.iterations, 4);
  try {
    parse_case(sa, "sa.toml", ".", {"turbulence.start.coupling=\"often\""});
    ADD_FAILURE() << "an unknown start coupling was accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("turbulence.start.coupling"), std::string::npos) << m;
    EXPECT_NE(m.find("often"), std::string::npos) << m;
  }
  try {
    parse_case(sa, "sa.toml", ".", {"turbulence.coupling=\"iteration\""});
    ADD_FAILURE() << "an unknown coupling was accepted";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("turbulence.coupling"), std::string::npos) << m;
    EXPECT_NE(m.find("\"smoothing\""), std::string::npos) << m;
  }
}

TEST(CaseErrors, UnknownBodyAndOddMeridianCountAreNamed) {
  const std::string text = R"(
[grid]
type = "body_of_revolution"
body = "cube"
[flow]
reynolds = 100.0
[bc.body]
type = "wall"
[bc.farfield]
type = "farfield"
)";
  std::string m = error_of(text);
  EXPECT_NE(m.find("grid.body"), std::string::npos) << m;
  EXPECT_NE(m.find("cube"), std::string::npos) << m;
  m = error_of(replace(replace(text, "\"cube\"", "\"sphere\""), "[flow]", "cells_along = 15\n[flow]"));
  EXPECT_NE(m.find("grid.cells_along"), std::string::npos) << m;
  EXPECT_NE(m.find("even"), std::string::npos) << m;
  // The valid case builds: six blocks.
  const CaseConfig c = parse_case(replace(text, "\"cube\"", "\"sphere\""), "sphere.toml", ".");
  EXPECT_EQ(build_grid(c).blocks.size(), 6u);
}

// Angle of attack and drift (NUMERICS §0.1 body axes, nose at -x of the grid): the
// free stream passes the body at U (cos a cos b, -sin b, -sin a cos b); a far-field
// velocity given as well is refused, naming both keys.
TEST(CaseFreeStream, AnglesSetTheFreeStreamAndConflictWithAnExplicitVelocity) {
  const std::string text = test::read_text(test::source_path("validation/cases/sphere_laminar/sphere.toml"));
  const std::string no_velocity = replace(text, "\nvelocity = [1.0, 0.0, 0.0]", "\n");
  const CaseConfig c = parse_case(no_velocity, "s.toml", ".", {"flow.angle_of_attack=10.0", "flow.drift_angle=-4.0"});
  const Real a = 10.0 * M_PI / 180.0, b = -4.0 * M_PI / 180.0;
  const Vec3 expected(std::cos(a) * std::cos(b), -std::sin(b), -std::sin(a) * std::cos(b));
  EXPECT_LT((c.bcs.at("farfield").velocity - expected).norm(), 1e-15);
  EXPECT_LT((c.free_stream - expected).norm(), 1e-15);
  // The initial velocity keeps the case's own value when it gives one.
  EXPECT_EQ(c.initial.tail<3>(), Vec3(1, 0, 0));
  const std::string e = error_of(replace(text, "[flow]", "[flow]\nangle_of_attack = 5.0"), "s.toml");
  EXPECT_NE(e.find("bc.farfield.velocity"), std::string::npos) << e;
  EXPECT_NE(e.find("flow.angle_of_attack"), std::string::npos) << e;
}

// grid.first_spacing_yplus sets the wall spacing from the Reynolds number, so that
// the quality report's y+ estimate of the wall cells' centres is the target; it
// conflicts with an explicit grid.first_spacing.
TEST(BodyGridKeys, FirstSpacingFromTargetYPlus) {
  const std::string text = test::read_text(test::source_path("validation/cases/sphere_laminar/sphere.toml"));
  const std::string by_yplus = replace(text, "first_spacing = 0.0025", "first_spacing_yplus = 0.8");
  const CaseConfig c = parse_case(by_yplus, "s.toml", ".", {"flow.reynolds=1.0e7", "grid.body=\"suboff\""});
  const Real friction_velocity = std::sqrt(0.5 * flat_plate_friction_estimate(1.0e7));
  EXPECT_NEAR(c.grid.body.first_spacing * 1.0e7 * friction_velocity / 2.0, 0.8, 1e-12);
  const std::string e = error_of(replace(text, "first_spacing = 0.0025", "first_spacing = 0.0025\nfirst_spacing_yplus = 1.0"));
  EXPECT_NE(e.find("grid.first_spacing_yplus"), std::string::npos) << e;
}

// A slip wall is a symmetry condition whose faces belong to the body: surface output
// and forces (pressure only; the friction part is zero).
TEST(SlipWall, BodyFacesCarryPressureForcesAndNoFriction) {
  const fs::path dir = test::fresh_temp_dir("slip_wall");
  const std::string text = test::read_text(test::source_path("validation/cases/sphere_laminar/sphere.toml"));
  const CaseConfig c = parse_case(replace(replace(text, "type = \"wall\"", "type = \"slip_wall\""), "beta = 5.0",
                                          "beta = 5.0\nviscous = \"inviscid\""),
                                  (dir / "s.toml").string(), dir.string(),
                                  {"grid.coarsen=2", "solver.max_iterations=3", "solver.multigrid_levels=1"});
  RunOptions o;
  o.out_dir = (dir / "run").string();
  run_case(c, o);
  const auto surface = test::read_csv((dir / "run" / "surface_body.csv").string());
  ASSERT_EQ(surface.at("cp").size(), 4u * 16u * 8u + 2u * 8u * 8u);  // the coarse grid's body faces
  for (double cf : surface.at("cf_x")) EXPECT_EQ(cf, 0.0);
  const std::string json = test::read_text((dir / "run" / "run.json").string());
  EXPECT_NE(json.find("\"body_axes\""), std::string::npos);
  const auto hist = test::read_csv((dir / "run" / "history.csv").string());
  EXPECT_NE(hist.at("body_cfx").back(), 0.0);  // pressure drag of the starting flow
}

TEST(CaseOverrides, SetReplacesAndCreatesKeysAndUnknownOnesAreRejected) {
  const CaseConfig c = parse_case(flat_plate_text(), "p.toml", ".", {"grid.cells_plate=48", "solver.cfl_start = 3.5"});
  EXPECT_EQ(c.grid.plate.n_plate, 48);
  EXPECT_EQ(c.solver.newton.cfl_start, 3.5);
  const CaseConfig d = parse_case(flat_plate_text(), "p.toml", ".", {"output.reference_length=2.0"});
  EXPECT_EQ(d.output.reference_length, 2.0);
  std::string e;
  try {
    parse_case(flat_plate_text(), "p.toml", ".", {"grid.cells_plat=48"});
  } catch (const Error& err) {
    e = err.what();
  }
  EXPECT_NE(e.find("did you mean 'grid.cells_plate'"), std::string::npos) << e;
}

TEST(CaseErrors, MissingGridFileIsNamed) {
  const std::string text = "[grid]\ntype = \"plot3d\"\nfile = \"no_such_grid.xyz\"\n[flow]\nreynolds = 10.0\n";
  const std::string e = error_of(text);
  EXPECT_NE(e.find("no_such_grid.xyz"), std::string::npos) << e;
  EXPECT_NE(e.find("does not exist"), std::string::npos) << e;
}

TEST(CaseErrors, TruncatedPlot3dIsReported) {
  Grid g;
  g.blocks.push_back(make_box("b", uniform_nodes(0, 1, 4), uniform_nodes(0, 1, 3), uniform_nodes(0, 1, 2)));
  const fs::path dir = test::fresh_temp_dir("narwhal_p3d");
  fs::create_directories(dir);
  for (bool ascii : {true, false}) {
    const std::string path = (dir / (ascii ? "g.x" : "g.xyz")).string();
    ascii ? write_plot3d_ascii(path, g.blocks) : write_plot3d_fortran(path, g.blocks);
    // Round trip first.
    const auto back = read_plot3d(path);
    ASSERT_EQ(back.size(), 1u);
    EXPECT_EQ(back[0].ni, 4);
    EXPECT_LT((back[0].x(4, 3, 2) - g.blocks[0].x(4, 3, 2)).norm(), 1e-15);
    fs::resize_file(path, fs::file_size(path) - (ascii ? 30 : 16));
    std::string e;
    try {
      read_plot3d(path);
    } catch (const Error& err) {
      e = err.what();
    }
    EXPECT_NE(e.find("truncated"), std::string::npos) << e;
    EXPECT_NE(e.find(path), std::string::npos) << e;
  }
}

TEST(Plot3d, RawCBinaryMultiBlockRoundTrip) {
  std::vector<Block> blocks;
  blocks.push_back(make_box("a", uniform_nodes(0, 1, 3), uniform_nodes(0, 1, 2), uniform_nodes(0, 1, 2)));
  blocks.push_back(make_box("b", uniform_nodes(1, 2, 2), uniform_nodes(0, 1, 2), uniform_nodes(0, 1, 2)));
  const std::string path = (test::fresh_temp_dir("narwhal_raw") / "grid.xyz").string();
  {
    std::ofstream out(path, std::ios::binary);
    auto w32 = [&](int32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
    w32(2);
    for (const auto& b : blocks) {
      w32(b.ni + 1);
      w32(b.nj + 1);
      w32(b.nk + 1);
    }
    for (const auto& b : blocks)
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k <= b.nk; ++k)
          for (int j = 0; j <= b.nj; ++j)
            for (int i = 0; i <= b.ni; ++i) out.write(reinterpret_cast<const char*>(&b.x(i, j, k)[c]), 8);
  }
  const auto back = read_plot3d(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(back[1].ni, 2);
  EXPECT_LT((back[1].x(2, 2, 2) - Vec3(2, 1, 1)).norm(), 1e-15);
}

TEST(CaseErrors, LabelWithoutBoundaryConditionIsReported) {
  const std::string e = error_of(replace(flat_plate_text(), "[bc.runup]\ntype = \"symmetry\"", ""));
  EXPECT_NE(e.find("'runup'"), std::string::npos) << e;
  EXPECT_NE(e.find("no boundary condition"), std::string::npos) << e;
}

// A small, fast version of the flat plate for the run-level tests.
CaseConfig small_plate() {
  std::string t = flat_plate_text();
  t = replace(t, "cells_runup = 32", "cells_runup = 8");
  t = replace(t, "cells_plate = 96", "cells_plate = 24");
  t = replace(t, "cells_normal = 64", "cells_normal = 24");
  t = replace(t, "dx_leading_edge = 2.0e-3", "dx_leading_edge = 1.0e-2");
  t = replace(t, "dy_wall = 1.0e-4", "dy_wall = 1.0e-3");
  return parse_case(t, "small_plate.toml", ".");
}

// Runs `c` as `full` does but stopped after `stop_at` iterations (in dir/split), then
// resumed from the restart that stop wrote, up to `full`'s own iteration limit.
RunSummary stop_and_resume(const CaseConfig& c, const RunOptions& full, const fs::path& dir, int stop_at) {
  RunOptions first = full;
  first.out_dir = (dir / "split").string();
  first.max_iterations = stop_at;
  run_case(c, first);
  fs::copy_file(dir / "split" / "restart.h5", dir / "restart_first.h5");
  RunOptions second = first;
  second.max_iterations = full.max_iterations;
  second.restart = (dir / "restart_first.h5").string();
  return run_case(c, second);
}

// Runs `total` iterations uninterrupted and `first` + the rest from restart.h5; the
// two histories must agree to the last digit.
void expect_restart_reproduces_history(const CaseConfig& c, const std::string& name, int total, int first_part) {
  const fs::path dir = test::fresh_temp_dir(name);
  fs::remove_all(dir);
  RunOptions full;
  full.out_dir = (dir / "full").string();
  full.max_iterations = total;
  run_case(c, full);
  stop_and_resume(c, full, dir, first_part);
  const auto a = test::history_rows((dir / "full" / "history.csv").string());
  const auto b = test::history_rows((dir / "split" / "history.csv").string());
  ASSERT_EQ(a.size(), static_cast<std::size_t>(total)) << name;
  ASSERT_EQ(b.size(), static_cast<std::size_t>(total)) << name;
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << name << " iteration " << i + 1;
}

TEST(Restart, ContinuingFromRestartReproducesTheUninterruptedHistory) {
  expect_restart_reproduces_history(small_plate(), "narwhal_restart_test", 40, 20);
}

// The same with a turbulence model on multigrid: the model's variables, its residual
// reference and the eddy viscosity must come back exactly.
TEST(Restart, TurbulentMultigridRunContinuesBitForBit) {
  for (const char* model : {"sa", "sst"}) {
    const std::string file = std::string("validation/cases/tmr_flat_plate/flat_plate_") + model + ".toml";
    // A target beyond reach: SA converges on this level in about 20 cycles.
    const CaseConfig c = load_case(test::source_path(file), {"grid.coarsen=3", "solver.residual_drop=1e-15"});
    expect_restart_reproduces_history(c,
                                      std::string("narwhal_restart_turb_") + model, 30, 15);
  }
}

// The CFL column of a history.csv.
std::vector<Real> cfl_column(const fs::path& history) {
  std::vector<Real> cfl;
  for (const std::string& row : test::history_rows(history.string())) {
    const auto a = row.find(','), b = row.find(',', a + 1);
    cfl.push_back(std::stod(row.substr(a + 1, b - a - 1)));
  }
  return cfl;
}

// solver.cfl_growth: the SER CFL rises by at most the factor per cycle (without it, it
// jumps), and a run resumed from a restart continues the limited ramp bit for bit.
TEST(CflGrowth, SerCflRisesByAtMostTheFactorAndRestartsContinueTheRamp) {
  const std::string file = test::source_path("validation/cases/tmr_flat_plate/flat_plate_sst.toml");
  auto largest_rise = [](const std::vector<Real>& cfl) {
    Real rise = 0.0;
    for (std::size_t i = 1; i < cfl.size(); ++i) rise = std::max(rise, cfl[i] / cfl[i - 1]);
    return rise;
  };
  const fs::path dir = test::fresh_temp_dir("narwhal_cfl_growth_test");
  fs::remove_all(dir);
  RunOptions free_ramp;
  free_ramp.out_dir = (dir / "free").string();
  free_ramp.max_iterations = 15;
  run_case(load_case(file, {"grid.coarsen=3", "solver.residual_drop=1e-15"}), free_ramp);
  EXPECT_GT(largest_rise(cfl_column(dir / "free" / "history.csv")), 1.5);

  const CaseConfig c = load_case(file, {"grid.coarsen=3", "solver.residual_drop=1e-15", "solver.cfl_growth=1.2"});
  expect_restart_reproduces_history(c, "narwhal_cfl_growth_restart", 30, 15);
  RunOptions limited;
  limited.out_dir = (dir / "limited").string();
  limited.max_iterations = 30;
  run_case(c, limited);
  const std::vector<Real> cfl = cfl_column(dir / "limited" / "history.csv");
  EXPECT_LE(largest_rise(cfl), 1.2 * (1.0 + 1e-5));  // the history prints 6 significant digits
  EXPECT_GT(largest_rise(cfl), 1.19);                // the limit was what held it
}

// The coarsest TMR SST plate with a linear-residual limit its ordinary corrections trip
// (the production limit is 10), and a residual target beyond reach.
CaseConfig plate_tripping_the_linear_check(std::vector<std::string> overrides = {}) {
  overrides.insert(overrides.begin(), {"grid.coarsen=3", "solver.residual_drop=1e-15"});
  CaseConfig c = load_case(test::source_path("validation/cases/tmr_flat_plate/flat_plate_sst.toml"), overrides);
  c.solver.newton.linear_growth_limit = 0.02;
  return c;
}

// 30 iterations of `c` into dir/run (emptied first).
RunSummary run_30_cycles(const CaseConfig& c, const fs::path& dir) {
  fs::remove_all(dir);
  RunOptions o;
  o.out_dir = (dir / "run").string();
  o.max_iterations = 30;
  return run_case(c, o);
}

// A correction the linearized equations call amplifying is rejected and the CFL cut
// (NewtonSolver::relax_and_update); the CFL then regrows by at most 1.5 per cycle, and a
// run resumed from a restart between continues it bit for bit.
TEST(CflCut, ARejectedCorrectionCutsTheCflWhichRegrowsAndRestartsContinue) {
  CaseConfig c = plate_tripping_the_linear_check();
  // The rise guard off: its ceiling would hold the CFL below the later cuts.
  c.solver.newton.rise_limit = std::numeric_limits<Real>::infinity();
  const fs::path dir = test::fresh_temp_dir("narwhal_cfl_cut_test");
  const RunSummary s = run_30_cycles(c, dir);
  EXPECT_GE(s.cfl_cuts, 1);
  const std::vector<Real> cfl = cfl_column(dir / "run" / "history.csv");
  std::size_t first_cut = 0;
  for (std::size_t i = 1; i < cfl.size() && first_cut == 0; ++i)
    if (cfl[i] < 0.5 * cfl[i - 1]) first_cut = i;
  ASSERT_GT(first_cut, 0u) << "no cut in the CFL history";
  Real rise = 0.0;  // SER alone rises faster here (CflGrowth's free ramp: above 1.5 per cycle)
  for (std::size_t i = first_cut + 1; i < cfl.size(); ++i)
    if (cfl[i] < 1e6) rise = std::max(rise, cfl[i] / cfl[i - 1]);  // 1e6: the case's cfl_max
  EXPECT_LE(rise, 1.5 * (1.0 + 1e-5));  // the history prints 6 significant digits
  // Resumed at cycle 11, within a regrowth (cuts at cycles 7, 10 and 12 on this build).
  expect_restart_reproduces_history(c, "narwhal_cfl_cut_restart", 30, 11);
}

// Once the CFL has reached its cap, a residual that rises in two successive iterations
// lowers the CFL's ceiling (implicit/cfl_rise_guard.hpp), which then holds; a run resumed
// between the two rises sees the same rise (the guard's state is in the restart). The
// same plate as above, its CFL capped at 2e3: with the low linear limit its residual
// rises over cycles 7-9.
TEST(CflRiseGuard, ASustainedRiseLowersTheCeilingWhichHoldsAndRestartsContinue) {
  const CaseConfig c = plate_tripping_the_linear_check({"solver.cfl_max=2e3"});
  const fs::path dir = test::fresh_temp_dir("narwhal_rise_guard_test");
  const RunSummary s = run_30_cycles(c, dir);
  ASSERT_GE(s.cfl_ceiling_cuts, 1);
  EXPECT_NE(slurp((dir / "run" / "run.json").string()).find(fmt::format("\"cfl_ceiling_cuts\": {}", s.cfl_ceiling_cuts)),
            std::string::npos);
  const std::vector<Real> cfl = cfl_column(dir / "run" / "history.csv");
  std::size_t held_from = 0;  // the first of the iterations at the ceiling
  for (std::size_t i = 1; i < cfl.size() && held_from == 0; ++i)
    if (cfl[i] < cfl[i - 1] && cfl[i] == cfl.back()) held_from = i;
  ASSERT_GT(held_from, 0u);
  for (std::size_t i = held_from; i < cfl.size(); ++i) EXPECT_LE(cfl[i], cfl[held_from]) << "iteration " << i + 1;
  expect_restart_reproduces_history(c, "narwhal_rise_guard_restart", 20, 8);
}

// When no CFL makes the sweeps acceptable the run stops as diverged, naming the cell with
// the largest linearized residual, after the cuts (here: a limit no correction meets).
TEST(CflCut, SweepsThatNeverConvergeStopTheRunNamingTheCell) {
  CaseConfig c = small_plate();
  c.solver.newton.linear_growth_limit = 1e-30;
  const fs::path dir = test::fresh_temp_dir("narwhal_cfl_cut_fail_test");
  fs::remove_all(dir);
  RunOptions o;
  o.out_dir = dir.string();
  o.max_iterations = 5;
  const RunSummary s = run_case(c, o);
  EXPECT_EQ(s.status, RunStatus::Diverged);
  EXPECT_NE(s.message.find("sweeps diverge"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("after 6 cuts; largest linear residual at block 'plate' cell ("), std::string::npos)
      << s.message;
}

// A small non-linear k-epsilon duct whose start (window 5, span 0.1) ends at cycle 12.
CaseConfig small_duct_with_start() {
  return load_case(test::source_path("validation/cases/square_duct_turbulent/duct_nl.toml"),
                   {"grid.y=[-1.0, 1.0, 16]", "grid.z=[-1.0, 1.0, 16]", "grid.first_spacing_y=0.02",
                    "grid.first_spacing_z=0.02", "turbulence.start.force_span=0.1", "turbulence.start.window=5"});
}

// The start ends when the forces have settled, once, and is reported; a restart
// written before the switch (its force window part-filled) turns at the same cycle,
// one written after it does not start again.
TEST(TurbulenceStart, EndsOnceWhenTheForcesSettleAndRestartsTurnWhereTheRunDid) {
  const CaseConfig c = small_duct_with_start();
  const fs::path dir = test::fresh_temp_dir("narwhal_turbulence_start_test");
  fs::remove_all(dir);
  RunOptions full;
  full.out_dir = (dir / "full").string();
  full.max_iterations = 30;
  const RunSummary whole = run_case(c, full);
  ASSERT_GT(whole.turbulence_start_ended, c.turbulence.start.window);
  ASSERT_LT(whole.turbulence_start_ended, 20);
  EXPECT_NE(slurp((dir / "full" / "run.json").string())
                .find(fmt::format("\"turbulence_start_ended\": {}", whole.turbulence_start_ended)),
            std::string::npos);
  const auto a = test::history_rows((dir / "full" / "history.csv").string());
  for (const int split : {whole.turbulence_start_ended - 2, whole.turbulence_start_ended + 3}) {
    const fs::path at = dir / fmt::format("resumed_{}", split);
    fs::create_directories(at);
    const RunSummary resumed = stop_and_resume(c, full, at, split);
    EXPECT_EQ(resumed.turbulence_start_ended, whole.turbulence_start_ended) << "split at " << split;
    const auto b = test::history_rows((at / "split" / "history.csv").string());
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << "split at " << split << ", iteration " << i + 1;
  }
  // Without a start, none ends.
  CaseConfig no_start = c;
  no_start.turbulence.start.force_span = 0.0;
  full.out_dir = (dir / "no_start").string();
  EXPECT_EQ(run_case(no_start, full).turbulence_start_ended, 0);
}

// The non-linear k-epsilon duct at constant flow rate: the adjusted body force must
// come back from the restart too (the history holds the residuals it drives).
TEST(Restart, FlowRateControlledNonlinearDuctContinuesBitForBit) {
  const std::string file = "validation/cases/square_duct_turbulent/duct_nl.toml";
  expect_restart_reproduces_history(
      load_case(test::source_path(file), {"grid.y=[-1.0, 1.0, 16]", "grid.z=[-1.0, 1.0, 16]",
                                          "grid.first_spacing_y=0.02", "grid.first_spacing_z=0.02"}),
      "narwhal_restart_duct_nl", 30, 15);
}

TEST(Robustness, NonFiniteStateIsReportedWithBlockCellAndEquation) {
  const CaseConfig c = small_plate();
  Grid g = build_grid(c);
  const FlowParams fp = flow_params(c);
  FlowField f;
  f.allocate(g, fp, c.initial);
  f.Q[0](5, 3, 0)[2] = std::nan("");
  NewtonSolver s(g, f, fp, c.solver.newton, Communicator::world());
  std::string e;
  try {
    s.evaluate_residual();
  } catch (const DivergenceError& err) {
    e = err.what();
  }
  EXPECT_NE(e.find("block 'plate'"), std::string::npos) << e;
  EXPECT_NE(e.find("(5, 3, 0)"), std::string::npos) << e;
  EXPECT_NE(e.find(" v "), std::string::npos) << e;
}

TEST(Robustness, DivergingRunStopsAndKeepsTheLastGoodRestart) {
  CaseConfig c = small_plate();
  c.output.restart_interval = 2;
  // An absurd artificial compressibility makes the pressure waves explode.
  c.flow.beta = 1e-12;
  c.solver.newton.cfl_start = 1e8;
  c.solver.newton.cfl_max = 1e12;
  const fs::path dir = test::fresh_temp_dir("narwhal_diverge_test");
  fs::remove_all(dir);
  RunOptions o;
  o.out_dir = dir.string();
  o.max_iterations = 200;
  const RunSummary s = run_case(c, o);
  ASSERT_EQ(s.status, RunStatus::Diverged) << "drop " << s.residual_drop;
  std::printf("diverged run: %s (after %d iterations)\n", s.message.c_str(), s.iterations);
  EXPECT_NE(s.message.find("restart"), std::string::npos) << s.message;
  const std::string json = slurp((dir / "run.json").string());
  EXPECT_NE(json.find("\"status\": \"diverged\""), std::string::npos);
  // The kept restart is the last finite state, written before the blow-up.
  EXPECT_NE(s.message.find("last good restart.h5 (iteration"), std::string::npos) << s.message;
  Grid g = build_grid(c);
  FlowField f;
  f.allocate(g, flow_params(c), c.initial);
  const RestartInfo info = read_restart((dir / "restart.h5").string(), g, f, "laminar");
  EXPECT_GE(info.iteration, 2);
  EXPECT_LE(info.iteration, s.iterations);  // s.iterations counts completed iterations
  for (const auto& q : f.Q[0].raw()) EXPECT_TRUE(q.allFinite());
}

TEST(Robustness, ResidualBlowUpNamesTheWorstCell) {
  // A divergence limit below 1 makes the very first residual count as a blow-up,
  // which exercises the finite-blow-up path of the driver deterministically.
  CaseConfig c = small_plate();
  c.solver.divergence_factor = 0.5;
  RunOptions o;
  o.out_dir = (test::fresh_temp_dir("narwhal_blowup_test")).string();
  o.max_iterations = 3;
  const RunSummary s = run_case(c, o);
  ASSERT_EQ(s.status, RunStatus::Diverged);
  EXPECT_NE(s.message.find("block 'plate' cell ("), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("equation: |R|/V ="), std::string::npos) << s.message;
}

TEST(Robustness, ResidualRegrowthAboveItsLowestStopsTheRun) {
  // The exploding plate of DivergingRunStopsAndKeepsTheLastGoodRestart first falls to
  // 0.17 of its start, then regrows 199-fold in three iterations, still below 1e4 of its
  // start: a regrowth limit of 10 stops it there, naming the rule.
  CaseConfig c = small_plate();
  c.flow.beta = 1e-12;
  c.solver.newton.cfl_start = 1e8;
  c.solver.newton.cfl_max = 1e12;
  c.solver.regrowth_factor = 10.0;
  c.solver.retreats = 0;  // the rule's own verdict, not a retreat from it
  RunOptions o;
  o.out_dir = (test::fresh_temp_dir("narwhal_regrowth_test")).string();
  o.max_iterations = 50;
  const RunSummary s = run_case(c, o);
  ASSERT_EQ(s.status, RunStatus::Diverged) << s.message;
  EXPECT_NE(s.message.find("above its lowest"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("block 'plate' cell ("), std::string::npos) << s.message;
  EXPECT_LT(s.residual_drop, c.solver.divergence_factor);  // the start-relative rule would not have fired
}

// SA on the coarsest TMR level with full steps once per cycle and point relaxation
// oscillates with period 2 (turbulence/DESIGN.md): a run made to stall.
CaseConfig oscillating_sa_plate(int stall_window) {
  return load_case(test::source_path("validation/cases/tmr_flat_plate/flat_plate_sa.toml"),
                   {"grid.coarsen=3", "turbulence.relaxation=1.0", "turbulence.smoother=\"points\"",
                    "turbulence.coupling=\"cycle\"", "solver.stall_window=" + std::to_string(stall_window)});
}

TEST(Robustness, StalledRunEndsNamingTheSlowestEquationAndItsWorstCell) {
  const CaseConfig c = oscillating_sa_plate(100);
  const fs::path dir = test::fresh_temp_dir("narwhal_stall_test");
  fs::remove_all(dir);
  RunOptions o;
  o.out_dir = dir.string();
  const RunSummary s = run_case(c, o);
  ASSERT_EQ(s.status, RunStatus::Stalled) << s.message;
  std::printf("stalled run: %s (after %d iterations)\n", s.message.c_str(), s.iterations);
  EXPECT_LT(s.iterations, 300);  // the limit is 3000: the plateau ends the run, not the limit
  EXPECT_GT(s.residual_drop, 1e-4);
  EXPECT_NE(s.message.find("not fallen by a factor 2 in 100 iterations"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("the slowest equation is "), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("block 'plate' cell ("), std::string::npos) << s.message;
  const std::string json = slurp((dir / "run.json").string());
  EXPECT_NE(json.find("\"status\": \"stalled\""), std::string::npos);
  // The same case converges with the model's default scheme (lines, in the cycle).
  const CaseConfig ok = load_case(test::source_path("validation/cases/tmr_flat_plate/flat_plate_sa.toml"),
                                  {"grid.coarsen=3", "solver.stall_window=100"});
  o.out_dir = (dir / "default").string();
  EXPECT_EQ(run_case(ok, o).status, RunStatus::Converged);
}

// solver.turbulence_drop sets the model's residual drop apart from the mean flow's:
// tighter than residual_drop, the run goes on until the model's residuals are down too.
TEST(Convergence, TurbulenceDropIsWaitedForApartFromTheMeanFlows) {
  const std::string plate = test::source_path("validation/cases/tmr_flat_plate/flat_plate_sa.toml");
  const fs::path dir = test::fresh_temp_dir("narwhal_turbulence_drop_test");
  fs::remove_all(dir);
  RunOptions o;
  o.out_dir = (dir / "shared").string();
  const std::vector<std::string> loose{"grid.coarsen=3", "solver.residual_drop=1e-3", "solver.force_tolerance=0"};
  const RunSummary shared = run_case(load_case(plate, loose), o);
  ASSERT_EQ(shared.status, RunStatus::Converged);
  ASSERT_GT(shared.turbulence_drop, 1e-9);  // else the tighter target below decides nothing
  o.out_dir = (dir / "apart").string();
  std::vector<std::string> tight = loose;
  tight.push_back("solver.turbulence_drop=1e-9");
  const RunSummary apart = run_case(load_case(plate, tight), o);
  ASSERT_EQ(apart.status, RunStatus::Converged);
  EXPECT_LT(apart.turbulence_drop, 1e-9);
  EXPECT_GT(apart.iterations, shared.iterations);
}

// A run resumed from a restart written on the plateau stalls at the same iteration
// as the uninterrupted one: the detector's anchor travels with the restart.
TEST(Restart, StallDetectorStateContinuesFromTheRestart) {
  const CaseConfig c = oscillating_sa_plate(100);
  const fs::path dir = test::fresh_temp_dir("narwhal_stall_restart_test");
  fs::remove_all(dir);
  RunOptions full;
  full.out_dir = (dir / "full").string();
  const RunSummary whole = run_case(c, full);
  ASSERT_EQ(whole.status, RunStatus::Stalled);
  const RunSummary resumed = stop_and_resume(c, full, dir, whole.iterations - 30);
  EXPECT_EQ(resumed.status, RunStatus::Stalled);
  EXPECT_EQ(resumed.iterations, whole.iterations);
  EXPECT_EQ(resumed.message, whole.message);
}

// A run that waits for its forces to settle stops at the same iteration when resumed
// from a restart written while its force window was filling.
TEST(Restart, ForceSteadinessWindowContinuesFromTheRestart) {
  CaseConfig c = small_plate();
  c.solver.residual_drop = 1e-3;
  const fs::path dir = test::fresh_temp_dir("narwhal_force_window_restart_test");
  fs::remove_all(dir);
  RunOptions residuals_only;
  residuals_only.out_dir = (dir / "residuals").string();
  const RunSummary early = run_case(c, residuals_only);
  ASSERT_EQ(early.status, RunStatus::Converged);
  EXPECT_LT(early.force_span, 0.0);  // not tested, not reported
  c.solver.force_tolerance = 1e-9;
  c.solver.force_window = 6;
  RunOptions full;
  full.out_dir = (dir / "full").string();
  const RunSummary whole = run_case(c, full);
  ASSERT_EQ(whole.status, RunStatus::Converged);
  EXPECT_GT(whole.iterations, early.iterations + c.solver.force_window);  // the forces decided
  EXPECT_LE(whole.force_span, 1e-9);
  // Three samples short of the uninterrupted stop.
  const RunSummary resumed = stop_and_resume(c, full, dir, whole.iterations - 3);
  EXPECT_EQ(resumed.status, RunStatus::Converged);
  EXPECT_EQ(resumed.iterations, whole.iterations);
  EXPECT_EQ(resumed.force_span, whole.force_span);
}

TEST(Outputs, RunWritesTheContractFilesAndCgnscheckAcceptsTheSolution) {
  CaseConfig c = small_plate();
  c.grid.split = {2, 1, 1};
  c.grid.split_rotate = true;
  const fs::path dir = test::fresh_temp_dir("narwhal_outputs_test");
  fs::remove_all(dir);
  RunOptions o;
  o.out_dir = dir.string();
  o.max_iterations = 5;
  run_case(c, o);
  for (const char* f : {"history.csv", "surface_plate.csv", "solution.cgns", "restart.h5", "run.json"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const auto surf = test::read_csv((dir / "surface_plate.csv").string());
  EXPECT_EQ(surf.at("cf_x").size(), 24u);
  const std::string cmd = "cgnscheck " + (dir / "solution.cgns").string() + " > " + (dir / "cgnscheck.log").string() + " 2>&1";
  const int rc = std::system(cmd.c_str());
  const std::string log = slurp((dir / "cgnscheck.log").string());
  EXPECT_EQ(rc, 0) << log;
  EXPECT_EQ(log.find("ERROR"), std::string::npos) << log;
}

}  // namespace
}  // namespace narwhal
