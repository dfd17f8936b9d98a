// Issue 14's findings, one test each: bad input of every kind is a clear error naming
// the file and the key (or byte offset), and faults (a full disk, a kill, a second run
// in the same directory, a corrupt restart) never pass silently.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <signal.h>
#include <sys/resource.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include <nlohmann/json.hpp>

#include "app/driver.hpp"
#include "config/reader.hpp"
#include "io/monitors.hpp"
#include "io/output_directory.hpp"
#include "io/restart.hpp"
#include "mesh/generators.hpp"
#include "mesh/plot3d.hpp"
#include "multigrid/coarsen.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void spit(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
}

const std::string kPlate = "validation/cases/flat_plate_laminar/flat_plate.toml";

// The message of the Error that loading (and building) the case with `overrides` throws.
std::string error_with(const std::vector<std::string>& overrides, const std::string& file = kPlate) {
  try {
    const CaseConfig c = load_case(test::source_path(file), overrides);
    build_grid(c);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// ---- integers that used to wrap, numbers that used to pass ------------------------

TEST(Hardening, OutOfRangeIntegersAreRefusedBeforeNarrowing) {
  // Each of these used to wrap to a small or negative int, run nothing, or hang.
  for (const std::string s : {"grid.cells_plate=4294967297", "solver.max_iterations=4294967296",
                              "output.restart_interval=4294967296", "solver.sgs_iterations=-2147483649",
                              "solver.post_smooth=1000000000", "turbulence.iterations=1000000000",
                              "parallel.split_for=1000000", "grid.cells_normal=0", "solver.multigrid_levels=99"}) {
    const std::string key = s.substr(0, s.find('='));
    const std::string e = error_with({s});
    EXPECT_NE(e.find("key '" + key + "'"), std::string::npos) << s << ": " << e;
    EXPECT_NE(e.find("flat_plate.toml"), std::string::npos) << e;
    EXPECT_NE(e.find("an integer between"), std::string::npos) << e;
  }
}

TEST(Hardening, NonFiniteAndOutOfRangeNumbersAreRefused) {
  for (const std::string s :
       {"solver.cfl_start=nan", "solver.cfl_start=-1.0", "solver.cfl_max=inf", "solver.residual_drop=nan",
        "solver.residual_drop=2.0", "solver.divergence_factor=nan", "solver.divergence_factor=0.5",
        "solver.fd_epsilon=0.0", "output.reference_area=0.0", "output.reference_length=-inf",
        "bc.inlet.velocity=[nan, 0.0, 0.0]", "bc.top.velocity=[1.0, inf, 0.0]", "turbulence.intensity=-1.0",
        "flow.reynolds=inf", "flow.beta=-nan", "flow.initial_velocity=[0.0, nan, 0.0]", "solver.cfl_growth=-1.0",
        "solver.cfl_growth=1.0", "solver.cfl_growth=nan", "solver.multigrid_min_cells=0", "solver.retreats=-1"}) {
    const std::string key = s.substr(0, s.find('='));
    const std::string e = error_with({s});
    EXPECT_NE(e.find("key '" + key + "'"), std::string::npos) << s << ": " << e;
  }
}

TEST(Hardening, CflMaxBelowCflStartIsRefused) {
  const std::string e = error_with({"solver.cfl_start=100.0", "solver.cfl_max=10.0"});
  EXPECT_NE(e.find("key 'solver.cfl_max'"), std::string::npos) << e;
}

TEST(Hardening, SustainedFreeStreamNeedsATransportModel) {
  for (const char* model : {"laminar", "baldwin-lomax"}) {
    const std::string e =
        error_with({std::string("turbulence.model=\"") + model + "\"", "turbulence.sustain_freestream=true"});
    EXPECT_NE(e.find("key 'turbulence.sustain_freestream'"), std::string::npos) << model << ": " << e;
    EXPECT_NE(e.find("transport model"), std::string::npos) << e;
  }
  EXPECT_EQ(error_with({"turbulence.model=\"sst\"", "turbulence.sustain_freestream=true"}), "");
}

TEST(Hardening, OmegaWallDistanceIsNamedAndSstOnly) {
  std::string e = error_with({"turbulence.model=\"sst\"", "turbulence.omega_wall=\"wall\""});
  EXPECT_NE(e.find("key 'turbulence.omega_wall'"), std::string::npos) << e;
  EXPECT_NE(e.find("cell_height"), std::string::npos) << e;
  e = error_with({"turbulence.model=\"launder-sharma\"", "turbulence.omega_wall=\"cell_centre\""});
  EXPECT_NE(e.find("key 'turbulence.omega_wall'"), std::string::npos) << e;
  EXPECT_EQ(error_with({"turbulence.model=\"sst\"", "turbulence.omega_wall=\"cell_centre\""}), "");
}

// ---- --set into arrays of tables and patch ranges ------------------------------------

struct Plot3dCase {
  fs::path dir;
  std::string text;
};

// A one-block 8 x 4 x 1 box grid as a Plot3D file and a case with explicit patches.
Plot3dCase plot3d_case() {
  Plot3dCase p{test::fresh_temp_dir("narwhal_p3d_case"), ""};
  write_plot3d_ascii((p.dir / "box.xyz").string(),
                     {make_box("b", uniform_nodes(0, 2, 8), uniform_nodes(0, 1, 4), uniform_nodes(0, 0.1, 1))});
  p.text = "[grid]\ntype = \"plot3d\"\nfile = \"box.xyz\"\n";
  const std::pair<const char*, const char*> patches[] = {{"imin", "in"},   {"imax", "out"}, {"jmin", "wall"},
                                                         {"jmax", "top"},  {"kmin", "sym"}, {"kmax", "sym"}};
  for (const auto& [side, label] : patches)
    p.text += fmt::format("[[grid.patch]]\nblock = 1\nside = \"{}\"\nlabel = \"{}\"\n{}", side, label,
                          std::string(side) == "jmin" ? "range_i = [0, 8]\n" : "");
  p.text += "[flow]\nreynolds = 100.0\n[bc.in]\ntype = \"inflow\"\n[bc.out]\ntype = \"outflow\"\n"
            "[bc.wall]\ntype = \"wall\"\n[bc.top]\ntype = \"farfield\"\n[bc.sym]\ntype = \"symmetry\"\n";
  spit(p.dir / "case.toml", p.text);
  return p;
}

std::string plot3d_error(const std::vector<std::string>& overrides) {
  const Plot3dCase p = plot3d_case();
  try {
    build_grid(load_case((p.dir / "case.toml").string(), overrides));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Hardening, SetReachesArraysOfTables) {
  const Plot3dCase p = plot3d_case();
  // Applied: the wall patch shrinks to cells 2..5, so the rest of jmin is unlabelled.
  const std::string e = plot3d_error({"grid.patch[2].range_i=[2, 6]"});
  EXPECT_NE(e.find("jmin"), std::string::npos) << e;
  // A value of the wrong kind is refused, naming the key, instead of being ignored.
  const std::string bad = plot3d_error({"grid.patch[2].range_i=\"abc\""});
  EXPECT_NE(bad.find("key 'grid.patch[2].range_i'"), std::string::npos) << bad;
  const std::string index = plot3d_error({"grid.patch[9].range_i=[0, 8]"});
  EXPECT_NE(index.find("valid indices 0 to 5"), std::string::npos) << index;
  const std::string none = error_with({"grid.patch[4].range_j=[20, 64]"});
  EXPECT_NE(none.find("no array of tables 'grid.patch'"), std::string::npos) << none;
}

TEST(Hardening, PatchRangeOutsideTheBlockSaysTheValidRange) {
  const std::string e = plot3d_error({"grid.patch[2].range_i=[0, 9]"});
  EXPECT_NE(e.find("key 'grid.patch[2].range_i'"), std::string::npos) << e;
  EXPECT_NE(e.find("within [0, 8]"), std::string::npos) << e;
  const std::string three = plot3d_error({"grid.patch[2].range_i=[0, 8, 0]"});
  EXPECT_NE(three.find("two integers"), std::string::npos) << three;
}

TEST(Hardening, CheckRefusesMultigridLevelsTheGridCannotCoarsenTo) {
  // 96 + 32 plate cells, 64 normal: six coarsenings of 64 cells leave one; a seventh cannot.
  const CaseConfig c = load_case(test::source_path(kPlate), {"solver.multigrid_levels=9"});
  const Grid g = build_grid(c);
  std::string why;
  Grid level = g;
  for (int l = 1; l < 9 && why.empty(); ++l) {
    why = why_not_coarsenable(level);
    if (why.empty()) level = coarsen(level);
  }
  EXPECT_FALSE(why.empty());
}

// ---- grid files with hostile headers ---------------------------------------------------

std::string grid_error(const std::string& bytes) {
  const fs::path f = test::fresh_temp_dir("narwhal_bad_grid") / "g.xyz";
  spit(f, bytes);
  try {
    read_plot3d(f.string());
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

std::string int32s(std::initializer_list<int32_t> v) {
  std::string s;
  for (int32_t x : v) s.append(reinterpret_cast<const char*>(&x), 4);
  return s;
}

TEST(Hardening, GridHeadersAskingForMoreThanTheFileHoldsAreRefusedBeforeAllocating) {
  // 23 bytes declaring 100000^3 nodes once asked for 24 PB.
  EXPECT_NE(grid_error(int32s({1, 100000, 100000, 100000}) + "abcdefg").find("at most"), std::string::npos);
  // "1 / 400 400 400" in text once grew to 3 GB before failing.
  const std::string text = grid_error("1\n400 400 400\n");
  EXPECT_NE(text.find("truncated file"), std::string::npos) << text;
  EXPECT_NE(grid_error(int32s({2000000000, 2, 2, 2})).find("block count"), std::string::npos);
  EXPECT_NE(grid_error(int32s({1, 2147483647, 2, 2})).find("at most"), std::string::npos);
  EXPECT_NE(grid_error(int32s({1, -5, 2, 2})).find(">= 2"), std::string::npos);
  // A raw binary whose byte count wrapped to 0 in 32 bits: 2^30 nodes.
  EXPECT_NE(grid_error(int32s({1, 1024, 1024, 1024})).find("at most"), std::string::npos);
  // Fortran record markers that disagree with the header.
  EXPECT_NE(grid_error(int32s({4, 1, 4, 12, 2, 2, 2, 99}) + std::string(200, '\0')).find("record marker"),
            std::string::npos);
}

TEST(Hardening, TextGridWithNanIsReadAsTextAndRefusedAtItsByte) {
  std::string g = "1\n2 2 2\n";
  for (int m = 0; m < 24; ++m) g += m == 5 ? "nan\n" : "0.5\n";
  const std::string e = grid_error(g);
  EXPECT_NE(e.find("byte 28"), std::string::npos) << e;
  EXPECT_NE(e.find("'nan'"), std::string::npos) << e;
  EXPECT_NE(e.find("finite"), std::string::npos) << e;
}

TEST(Hardening, BinaryGridWithNonFiniteCoordinateIsRefusedAtItsByte) {
  std::string g = int32s({1, 2, 2, 2});
  for (int m = 0; m < 24; ++m) {
    const double v = m == 3 ? std::numeric_limits<double>::infinity() : 0.5;
    g.append(reinterpret_cast<const char*>(&v), 8);
  }
  const std::string e = grid_error(g);
  EXPECT_NE(e.find("byte 40"), std::string::npos) << e;
}

// ---- restarts ---------------------------------------------------------------------------

struct RestartFixture {
  CaseConfig c;
  Grid g;
  FlowField f;
  fs::path file;
};

RestartFixture written_restart(const std::string& model = "laminar") {
  RestartFixture r;
  r.c = load_case(test::source_path(kPlate), {"grid.cells_plate=12", "grid.cells_runup=4", "grid.cells_normal=8"});
  r.g = build_grid(r.c);
  r.f.allocate(r.g, flow_params(r.c), r.c.initial);
  std::mt19937 rng(7);
  for (auto& q : r.f.Q[0].raw()) q = State::Random();
  RestartInfo info;
  info.iteration = 17;
  info.turbulence_model = model;
  r.file = test::fresh_temp_dir("narwhal_restart_fixture") / "restart.h5";
  write_restart(r.file.string(), r.g, r.f, info, r.c.text);
  return r;
}

TEST(Hardening, EverySingleByteCorruptionOfARestartIsDetected) {
  RestartFixture r = written_restart();
  const std::string good = slurp(r.file);
  const fs::path bad = r.file.parent_path() / "bad.h5";
  std::mt19937 rng(2026);
  std::size_t tried = 0, detected = 0;
  // Every byte of the checksum header block, and 400 random bytes of the HDF5 body.
  std::vector<std::size_t> offsets;
  for (std::size_t i = 0; i < 4096; i += 7) offsets.push_back(i);
  for (int n = 0; n < 400; ++n) offsets.push_back(4096 + rng() % (good.size() - 4096));
  for (std::size_t at : offsets) {
    std::string b = good;
    b[at] = static_cast<char>(b[at] ^ (1 + rng() % 255));
    spit(bad, b);
    ++tried;
    try {
      read_restart(bad.string(), r.g, r.f, "laminar");
    } catch (const Error& e) {
      ++detected;
      EXPECT_NE(std::string(e.what()).find("bad.h5"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(detected, tried);
  // And the untouched file reads back what was written.
  FlowField back;
  back.allocate(r.g, flow_params(r.c), r.c.initial);
  EXPECT_EQ(read_restart(r.file.string(), r.g, back, "laminar").iteration, 17);
  EXPECT_EQ(back.Q[0](3, 2, 0), r.f.Q[0](3, 2, 0));
}

TEST(Hardening, TruncatedOrExtendedRestartIsDetected) {
  RestartFixture r = written_restart();
  const std::string good = slurp(r.file);
  spit(r.file, good.substr(0, good.size() - 1));
  EXPECT_THROW(read_restart(r.file.string(), r.g, r.f, "laminar"), Error);
  spit(r.file, good + "x");
  EXPECT_THROW(read_restart(r.file.string(), r.g, r.f, "laminar"), Error);
}

TEST(Hardening, RestartOfAnotherModelOrGridIsRefusedWithAMessage) {
  RestartFixture r = written_restart("sa");
  try {
    read_restart(r.file.string(), r.g, r.f, "sst");
    ADD_FAILURE() << "an SA restart loaded into an SST run";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'sa'"), std::string::npos) << e.what();
  }
  RestartFixture l = written_restart();
  const CaseConfig other =
      load_case(test::source_path(kPlate), {"grid.cells_plate=12", "grid.cells_runup=4", "grid.cells_normal=10"});
  const Grid g2 = build_grid(other);
  FlowField f2;
  f2.allocate(g2, flow_params(other), other.initial);
  try {
    read_restart(l.file.string(), g2, f2, "laminar");
    ADD_FAILURE() << "a restart of another grid loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("shape"), std::string::npos) << e.what();
  }
  const CaseConfig longer = load_case(test::source_path(kPlate), {"grid.cells_plate=12", "grid.cells_runup=4",
                                                                  "grid.cells_normal=8", "grid.length=2.0"});
  const Grid g3 = build_grid(longer);
  try {
    read_restart(l.file.string(), g3, f2, "laminar");
    ADD_FAILURE() << "a restart of another geometry loaded";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("another grid"), std::string::npos) << e.what();
  }
}

// The CFL controller's state travels whole (dataset cfl_control), and a restart in the older
// layout (the reference norm an attribute, the last CFL the monitors', the cut flag and the
// rise guard's pieces of their own) reads to the same state.
TEST(Restart, TheCflControllersStateIsReadWholeFromEitherLayout) {
  RestartFixture r = written_restart();
  RestartInfo info;
  info.iteration = 24;
  info.cfl = 144.0;
  info.cfl_control = {2.5e-3, 144.0, true, {288.0, {1.5e-4, 2.5e-4}, true}};
  write_restart(r.file.string(), r.g, r.f, info, r.c.text);
  auto expect_state = [](const CflControlState& a, const CflControlState& b) {
    EXPECT_EQ(a.reference_norm, b.reference_norm);
    EXPECT_EQ(a.last_cfl, b.last_cfl);
    EXPECT_EQ(a.recovering, b.recovering);
    EXPECT_EQ(a.rise_guard.ceiling, b.rise_guard.ceiling);
    EXPECT_EQ(a.rise_guard.recent, b.rise_guard.recent);
    EXPECT_EQ(a.rise_guard.armed, b.rise_guard.armed);
  };
  expect_state(read_restart(r.file.string(), r.g, r.f, "laminar").cfl_control, info.cfl_control);

  // The same state in the older layout.
  {
    const hid_t file = H5Fopen(r.file.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    ASSERT_GE(H5Ldelete(file, "cfl_control", H5P_DEFAULT), 0);
    auto attr = [&](const char* name, hid_t type, const void* value) {
      const hid_t space = H5Screate(H5S_SCALAR);
      const hid_t a = H5Acreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
      H5Awrite(a, type, value);
      H5Aclose(a);
      H5Sclose(space);
    };
    const double norm = 2.5e-3;
    const int recovering = 1;
    attr("reference_norm", H5T_NATIVE_DOUBLE, &norm);
    attr("cfl_recovering", H5T_NATIVE_INT, &recovering);
    const double guard[4] = {288.0, 1.5e-4, 2.5e-4, 1.0};
    const hsize_t n = 4;
    const hid_t space = H5Screate_simple(1, &n, nullptr);
    const hid_t d = H5Dcreate2(file, "cfl_rise_guard", H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, guard);
    H5Dclose(d);
    H5Sclose(space);
    H5Fclose(file);
  }
  stamp_restart_checksums(r.file.string());
  expect_state(read_restart(r.file.string(), r.g, r.f, "laminar").cfl_control, info.cfl_control);
}

TEST(Hardening, LargeCaseTextIsKeptInTheRestart) {
  RestartFixture r = written_restart();
  const std::string big = r.c.text + "\n#" + std::string(100000, 'x') + "\n";
  RestartInfo info;
  testing::internal::CaptureStderr();
  write_restart(r.file.string(), r.g, r.f, info, big);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");  // no HDF5 error stack
  EXPECT_NE(slurp(r.file).find(std::string(100000, 'x')), std::string::npos);
}

// ---- outputs and faults ------------------------------------------------------------------

TEST(Hardening, UnusableOutputDirectoriesAreErrorsNamingThem) {
  const fs::path d = test::fresh_temp_dir("narwhal_out");
  spit(d / "afile", "x");
  for (const std::string& bad : {(d / "afile").string(), std::string(""), (d / "afile" / "sub").string()}) {
    try {
      OutputDirectory o(bad, false, false);
      ADD_FAILURE() << "accepted --out '" << bad << "'";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("--out"), std::string::npos) << e.what();
    }
  }
}

TEST(Hardening, SecondRunIntoTheSameDirectoryStopsAtOnce) {
  const fs::path d = test::fresh_temp_dir("narwhal_lock");
  OutputDirectory first(d.string(), false, false);
  try {
    OutputDirectory second(d.string(), false, false);
    ADD_FAILURE() << "two runs share one output directory";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("another narwhal run"), std::string::npos) << e.what();
  }
}

TEST(Hardening, NewRunClearsThePreviousRunsOutputsAndTemporaryFiles) {
  const fs::path d = test::fresh_temp_dir("narwhal_clear");
  for (const char* f : {"restart.h5", "restart.h5.tmp", "history.csv", "run.json", "surface_plate.csv", "notes.txt"})
    spit(d / f, "old");
  {
    OutputDirectory o(d.string(), false, false);
    EXPECT_EQ(o.cleared().size(), 4u);
  }
  EXPECT_FALSE(fs::exists(d / "restart.h5"));
  EXPECT_FALSE(fs::exists(d / "restart.h5.tmp"));
  EXPECT_TRUE(fs::exists(d / "notes.txt"));  // not narwhal's
  spit(d / "restart.h5", "old");
  spit(d / "history.csv", "old");
  OutputDirectory cont(d.string(), true, true);
  EXPECT_TRUE(fs::exists(d / "restart.h5"));
  EXPECT_TRUE(fs::exists(d / "history.csv"));
}

TEST(Hardening, ResumedHistoryDropsRowsAfterTheCheckpointAndATornLine) {
  const fs::path d = test::fresh_temp_dir("narwhal_hist");
  const std::string header = history_header({"plate"}, {});
  std::string text = header;
  for (int it = 1; it <= 34; ++it) text += fmt::format("{},0,0,0,0,0,0,0,0,0,0,0,0\n", it);
  text += "35,0,0,0,0";  // torn by a kill
  spit(d / "history.csv", text);
  {
    HistoryWriter h((d / "history.csv").string(), {"plate"}, {}, 20);
    IterationNorms n;
    ForceCoefficients f;
    h.write(21, 0.0, n, {{"plate", f}});
  }
  const auto rows = test::history_rows((d / "history.csv").string());
  ASSERT_EQ(rows.size(), 21u);
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(std::stoi(rows[i]), static_cast<int>(i + 1));
}

// A full disk, simulated with a file-size limit (writes past it fail with EFBIG).
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    signal(SIGXFSZ, SIG_IGN);
    getrlimit(RLIMIT_FSIZE, &old_);
    rlimit r = old_;
    r.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &r);
  }
  ~FileSizeLimit() { setrlimit(RLIMIT_FSIZE, &old_); }

 private:
  rlimit old_{};
};

TEST(Hardening, FullDiskIsAnErrorNamingTheFile) {
  const fs::path d = test::fresh_temp_dir("narwhal_full");
  std::vector<WallFace> faces(200);
  {
    FileSizeLimit limit(4096);
    try {
      write_surface_csv((d / "surface_plate.csv").string(), faces);
      ADD_FAILURE() << "a surface file was cut short without an error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("surface_plate.csv"), std::string::npos) << e.what();
    }
    HistoryWriter h((d / "history.csv").string(), {"plate"}, {}, std::nullopt);
    IterationNorms n;
    ForceCoefficients f;
    try {
      for (int it = 1; it < 1000; ++it) h.write(it, 0.0, n, {{"plate", f}});
      ADD_FAILURE() << "history rows were lost without an error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("history.csv"), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(fs::exists(d / "surface_plate.csv"));  // never a partial file
}

TEST(SurfaceOutput, SignedWallShearHasTheMagnitudeAndTheSignOfItsStreamwisePart) {
  const fs::path d = test::fresh_temp_dir("narwhal_surface");
  std::vector<WallFace> faces(2);
  faces[0].cf = Vec3(-0.3, 0.4, 0.0);  // reversed flow: negative, magnitude 0.5
  faces[1].cf = Vec3(0.6, 0.0, -0.8);
  write_surface_csv((d / "surface_wall.csv").string(), faces);
  const auto cols = test::read_csv((d / "surface_wall.csv").string());
  ASSERT_EQ(cols.count("cf_signed"), 1u);
  EXPECT_NEAR(cols.at("cf_signed")[0], -0.5, 1e-12);
  EXPECT_NEAR(cols.at("cf_signed")[1], 1.0, 1e-12);
}

TEST(Hardening, RunJsonStaysValidWithNonFiniteNumbers) {
  CaseConfig c = load_case(test::source_path(kPlate), {"grid.cells_plate=12", "grid.cells_runup=4",
                                                      "grid.cells_normal=8", "flow.beta=1e-12",
                                                      "solver.cfl_start=1e8", "solver.cfl_max=1e12"});
  RunOptions o;
  o.out_dir = test::fresh_temp_dir("narwhal_nan_json").string();
  o.max_iterations = 50;
  const RunSummary s = run_case(c, o);
  ASSERT_EQ(s.status, RunStatus::Diverged);
  const nlohmann::json j = nlohmann::json::parse(slurp(fs::path(o.out_dir) / "run.json"));  // throws if invalid
  EXPECT_EQ(j["status"], "diverged");
}

// solver.retreats (app/retreat.hpp). The small plate at beta 1e-4 started at CFL 1e4
// diverges at iteration 81 when it may not retreat; allowed to, it goes back to its
// lowest-residual state with the CFL ceiling halved, and runs on.
const std::vector<std::string> kUnstablePlate{"grid.cells_plate=24", "grid.cells_runup=8", "grid.cells_normal=24",
                                              "flow.beta=1e-4",       "solver.cfl_start=1e4", "solver.cfl_max=1e12"};

TEST(Retreat, ADivergedRunGoesBackToItsLowestResidualWithTheCflCeilingHalved) {
  RunOptions o;
  o.max_iterations = 200;
  std::vector<std::string> none = kUnstablePlate;
  none.emplace_back("solver.retreats=0");
  o.out_dir = test::fresh_temp_dir("narwhal_retreat_none").string();
  const RunSummary stopped = run_case(load_case(test::source_path(kPlate), none), o);
  ASSERT_EQ(stopped.status, RunStatus::Diverged) << stopped.message;
  EXPECT_TRUE(stopped.retreats.empty());

  o.out_dir = test::fresh_temp_dir("narwhal_retreat").string();
  const RunSummary s = run_case(load_case(test::source_path(kPlate), kUnstablePlate), o);
  EXPECT_EQ(s.status, RunStatus::MaxIterations) << s.message;
  EXPECT_EQ(s.iterations, 200);
  ASSERT_FALSE(s.retreats.empty());
  EXPECT_EQ(s.retreats[0].diverged_at, stopped.iterations);  // the same path up to the first divergence
  EXPECT_NE(s.retreats[0].reason.find("above its lowest"), std::string::npos) << s.retreats[0].reason;
  Real previous = std::numeric_limits<Real>::infinity();
  for (const RetreatRecord& r : s.retreats) {
    EXPECT_LT(r.back_to, r.diverged_at);
    EXPECT_LE(r.cfl_ceiling, 0.5 * previous);
    previous = r.cfl_ceiling;
  }
  // Every CFL after the last retreat stays under its ceiling (history.csv has 7 digits).
  const nlohmann::json j = nlohmann::json::parse(slurp(fs::path(o.out_dir) / "run.json"));
  ASSERT_EQ(j["retreats"].size(), s.retreats.size());
  EXPECT_EQ(j["retreats"][0]["back_to"].get<int>(), s.retreats[0].back_to);
  EXPECT_EQ(j["settings"]["retreats"].get<int>(), 3);
  for (const std::string& row : test::history_rows((fs::path(o.out_dir) / "history.csv").string())) {
    const auto a = row.find(','), b = row.find(',', a + 1);  // iteration, CFL, ...
    if (std::stoi(row.substr(0, a)) > s.retreats.back().diverged_at) {
      EXPECT_LE(std::stod(row.substr(a + 1, b - a - 1)), s.retreats.back().cfl_ceiling * (1.0 + 1e-6)) << row;
    }
  }
}

// A run that never diverges follows exactly the path it has without retreats: the kept
// state is only read by a retreat.
TEST(Retreat, ARunThatNeverDivergesIsUnchangedByThem) {
  const std::vector<std::string> small{"grid.cells_plate=24", "grid.cells_runup=8", "grid.cells_normal=24"};
  RunOptions o;
  o.max_iterations = 60;
  std::vector<std::string> none = small;
  none.emplace_back("solver.retreats=0");
  const fs::path without = test::fresh_temp_dir("narwhal_retreat_off"), with = test::fresh_temp_dir("narwhal_retreat_on");
  o.out_dir = without.string();
  run_case(load_case(test::source_path(kPlate), none), o);
  o.out_dir = with.string();
  const RunSummary s = run_case(load_case(test::source_path(kPlate), small), o);
  EXPECT_TRUE(s.retreats.empty());
  const std::vector<std::string> a = test::history_rows((without / "history.csv").string()),
                                 b = test::history_rows((with / "history.csv").string());
  ASSERT_EQ(a.size(), 60u);
  EXPECT_EQ(a, b);
}

TEST(RunCost, TimePerCycleAndMemoryPerCellAreReported) {
  RunOptions o;
  o.out_dir = test::fresh_temp_dir("narwhal_cost").string();
  o.max_iterations = 4;
  const RunSummary s = run_case(load_case(test::source_path(kPlate), {"grid.cells_plate=12", "grid.cells_runup=4",
                                                                     "grid.cells_normal=8"}), o);
  EXPECT_GT(s.seconds_per_cycle, 0.0);
  EXPECT_GT(s.peak_bytes_per_cell, 0.0);
  const nlohmann::json j = nlohmann::json::parse(slurp(fs::path(o.out_dir) / "run.json"));
  EXPECT_DOUBLE_EQ(j["cost"]["seconds_per_cycle"].get<double>(), s.seconds_per_cycle);
  EXPECT_DOUBLE_EQ(j["cost"]["peak_bytes_per_cell"].get<double>(), s.peak_bytes_per_cell);
  // Every equation's drop, each against the largest residual it has had.
  for (const char* eq : {"p", "u", "v", "w"}) {
    ASSERT_TRUE(j["equation_drops"].contains(eq)) << eq;
    EXPECT_GE(j["equation_drops"][eq].get<double>(), 0.0);
    EXPECT_LE(j["equation_drops"][eq].get<double>(), 1.0);
  }
  EXPECT_GT(j["equation_drops"]["u"].get<double>(), 0.0);
}

TEST(Hardening, DivergingRunInAnOldDirectoryDoesNotClaimTheOldRestart) {
  const fs::path d = test::fresh_temp_dir("narwhal_old_dir");
  RunOptions o;
  o.out_dir = d.string();
  o.max_iterations = 3;
  const std::vector<std::string> small{"grid.cells_plate=12", "grid.cells_runup=4", "grid.cells_normal=8"};
  run_case(load_case(test::source_path(kPlate), small), o);
  ASSERT_TRUE(fs::exists(d / "restart.h5"));
  std::vector<std::string> bad = small;
  for (const char* s : {"flow.beta=1e-12", "solver.cfl_start=1e8", "solver.cfl_max=1e12", "output.restart_interval=0"})
    bad.push_back(s);
  o.max_iterations = 50;
  const RunSummary s = run_case(load_case(test::source_path(kPlate), bad), o);
  ASSERT_EQ(s.status, RunStatus::Diverged);
  EXPECT_NE(s.message.find("no restart was written before"), std::string::npos) << s.message;
  EXPECT_FALSE(fs::exists(d / "restart.h5"));
}

}  // namespace
}  // namespace narwhal
