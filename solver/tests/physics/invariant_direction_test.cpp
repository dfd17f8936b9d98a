// Planar slabs (physics/invariant_direction.hpp): detection, and that skipping the symmetry
// planes changes neither the residual nor the converged answer.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "app/driver.hpp"
#include "physics/invariant_direction.hpp"
#include "physics/residual.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

const std::string kPlateCase = "validation/cases/flat_plate_laminar/flat_plate.toml";
const std::vector<std::string> kSmallPlate = {"grid.cells_runup=8", "grid.cells_plate=24", "grid.cells_normal=24",
                                              "grid.dx_leading_edge=8e-3", "grid.dy_wall=4e-4"};

struct CaseSetup {
  CaseConfig c;
  Grid g;
  FlowParams fp;
  FlowField f;
};

// The case, its grid and its initial field; `extra` overrides after `overrides`.
CaseSetup set_up(const std::string& path, std::vector<std::string> overrides, const std::vector<std::string>& extra) {
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  CaseSetup s{load_case(test::source_path(path), overrides), {}, {}, {}};
  s.g = build_grid(s.c);
  s.fp = flow_params(s.c);
  s.f.allocate(s.g, s.fp, s.c.initial);
  return s;
}

CaseSetup small_plate(std::vector<std::string> extra = {}) { return set_up(kPlateCase, kSmallPlate, extra); }

// A non-uniform in-plane state: every face carries a different flux.
void randomize_in_plane(CaseSetup& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(-0.5, 0.5);
  for (std::size_t ib = 0; ib < s.g.blocks.size(); ++ib)
    for_each_cell(s.g.blocks[ib], [&](int i, int j, int k) { s.f.Q[ib](i, j, k) << u(rng), 1 + u(rng), u(rng), 0.0; });
}

TEST(Planar, FlatPlateIsASlabInK) {
  CaseSetup s = small_plate();
  const Slab slab = slab_direction(s.g, 0);
  EXPECT_EQ(slab.kind, SlabKind::SymmetryPlanes);
  EXPECT_EQ(slab.dir, 2);
  EXPECT_NEAR(std::abs(slab.normal[2]), 1.0, 1e-15);
  EXPECT_FALSE(mark_invariant_directions(s.g, s.f, s.fp).empty());
  EXPECT_EQ(s.g.blocks[0].invariant_dir, 2);
}

TEST(Planar, NotASlabWhenThickerOrNotSymmetricOrTilted) {
  {  // two cells across
    Grid g;
    g.blocks.push_back(make_box("b", {0, 1, 2}, {0, 1, 2}, {0, 0.5, 1}));
    for (auto& p : g.blocks[0].patches) p.type = BcType::Symmetry;
    finalize_grid(g);
    EXPECT_EQ(slab_direction(g, 0).dir, -1);
  }
  {  // a wall on one of the planes
    CaseSetup s = small_plate({"bc.side_hi.type=\"wall\""});
    EXPECT_EQ(slab_direction(s.g, 0).dir, -1);
  }
  {  // planes not parallel: one node of the upper plane lifted
    CaseSetup s = small_plate();
    Block& b = s.g.blocks[0];
    b.x(3, 3, 1)[2] += 0.01;
    prepare_geometry(s.g);
    EXPECT_EQ(slab_direction(s.g, 0).dir, -1);
  }
}

TEST(Planar, FlowAcrossThePlaneKeepsTheFullTreatment) {
  CaseSetup s = small_plate();
  s.f.Q[0](5, 5, 0)[3] = 1e-3;
  const std::string why = mark_invariant_directions(s.g, s.f, s.fp);
  EXPECT_NE(why.find("not planar"), std::string::npos) << why;
  EXPECT_EQ(s.g.blocks[0].invariant_dir, -1);
  CaseSetup t = small_plate({"flow.initial_velocity=[1.0, 0.0, 0.1]"});
  EXPECT_NE(mark_invariant_directions(t.g, t.f, t.fp).find("not planar"), std::string::npos);
  EXPECT_EQ(t.g.blocks[0].invariant_dir, -1);
}

TEST(Planar, SkippingThePlanesLeavesTheResidualUnchanged) {
  CaseSetup s = small_plate();
  randomize_in_plane(s, 7);
  fill_ghosts(s.g, s.f, s.fp);
  std::vector<GhostArray<State>> full, planar;
  compute_residual(s.g, s.f, s.fp, full);
  ASSERT_FALSE(mark_invariant_directions(s.g, s.f, s.fp).empty());
  fill_ghosts(s.g, s.f, s.fp);
  compute_residual(s.g, s.f, s.fp, planar);
  Real scale = 0.0, diff = 0.0;
  for_each_cell(s.g.blocks[0], [&](int i, int j, int k) {
    scale = std::max(scale, full[0](i, j, k).cwiseAbs().maxCoeff());
    diff = std::max(diff, (full[0](i, j, k) - planar[0](i, j, k)).cwiseAbs().maxCoeff());
  });
  EXPECT_GT(scale, 1e-3);
  EXPECT_LE(diff, 1e-13 * scale) << "the symmetry-plane fluxes do not cancel";
}

TEST(Planar, SameConvergedSkinFrictionWithAndWithoutTheShortcut) {
  std::map<std::string, std::vector<double>> cf;
  for (const char* on : {"true", "false"}) {
    auto overrides = kSmallPlate;
    overrides.push_back(std::string("solver.invariant_shortcut=") + on);
    overrides.push_back("solver.multigrid_levels=3");
    const CaseConfig c = load_case(test::source_path(kPlateCase), overrides);
    const std::string out = test::fresh_temp_dir(std::string("narwhal_planar_") + on).string();
    std::filesystem::remove_all(out);
    RunOptions opt;
    opt.out_dir = out;
    const RunSummary r = run_case(c, opt);
    ASSERT_EQ(r.status, RunStatus::Converged) << r.message;
    cf[on] = test::read_csv(out + "/surface_plate.csv").at("cf_x");
  }
  ASSERT_EQ(cf["true"].size(), cf["false"].size());
  Real worst = 0.0;
  for (std::size_t i = 0; i < cf["true"].size(); ++i)
    worst = std::max(worst, std::abs(cf["true"][i] / cf["false"][i] - 1.0));
  EXPECT_LE(worst, 1e-8);
}

const std::string kDuctCase = "validation/cases/square_duct_laminar/duct.toml";

// A laminar duct periodic in x over `cells_x` cells, small cross-section.
CaseSetup small_duct(int cells_x, std::vector<std::string> extra = {}) {
  return set_up(kDuctCase,
                {"grid.x=[0.0, 0.2, " + std::to_string(cells_x) + "]", "grid.y=[-1.0, 1.0, 12]", "grid.z=[-1.0, 1.0, 12]"},
                extra);
}

TEST(SelfPeriodic, OneCellPeriodicDuctIsInvariantAlongX) {
  CaseSetup s = small_duct(1);
  const Slab slab = slab_direction(s.g, 0);
  EXPECT_EQ(slab.kind, SlabKind::SelfPeriodic);
  EXPECT_EQ(slab.dir, 0);
  EXPECT_NEAR(std::abs(slab.normal[0]), 1.0, 1e-15);
  // The streamwise velocity is the flow itself: no "flow across" refusal here.
  const std::string why = mark_invariant_directions(s.g, s.f, s.fp);
  EXPECT_NE(why.find("invariant along"), std::string::npos) << why;
  EXPECT_EQ(s.g.blocks[0].invariant_dir, 0);
}

TEST(SelfPeriodic, TwoCellsOrAnotherBlockAreNotALayer) {
  EXPECT_EQ(slab_direction(small_duct(2).g, 0).kind, SlabKind::None);
  // One cell but not periodic: walls at both x ends.
  Grid g;
  g.blocks.push_back(make_box("b", {0, 0.2, 1}, {0, 1, 4}, {0, 1, 4}));
  for (auto& p : g.blocks[0].patches) p.type = BcType::Wall;
  finalize_grid(g);
  EXPECT_EQ(slab_direction(g, 0).kind, SlabKind::None);
}

// Random 3-D velocities (u along the layer included): the periodic faces cancel.
TEST(SelfPeriodic, SkippingTheFacesLeavesTheResidualUnchanged) {
  CaseSetup s = small_duct(1, {"flow.viscous=\"full\""});
  std::mt19937 rng(11);
  std::uniform_real_distribution<Real> u(-0.5, 0.5);
  for_each_cell(s.g.blocks[0], [&](int i, int j, int k) { s.f.Q[0](i, j, k) << u(rng), 1 + u(rng), u(rng), u(rng); });
  fill_ghosts(s.g, s.f, s.fp);
  std::vector<GhostArray<State>> full, skipped;
  compute_residual(s.g, s.f, s.fp, full);
  ASSERT_FALSE(mark_invariant_directions(s.g, s.f, s.fp).empty());
  fill_ghosts(s.g, s.f, s.fp);
  compute_residual(s.g, s.f, s.fp, skipped);
  Real scale = 0.0, diff = 0.0;
  for_each_cell(s.g.blocks[0], [&](int i, int j, int k) {
    scale = std::max(scale, full[0](i, j, k).cwiseAbs().maxCoeff());
    diff = std::max(diff, (full[0](i, j, k) - skipped[0](i, j, k)).cwiseAbs().maxCoeff());
  });
  EXPECT_GT(scale, 1e-3);
  EXPECT_LE(diff, 1e-13 * scale) << "the periodic faces do not cancel";
}

// The converged duct (two cells, no shortcut: the reference) against one cell with it.
TEST(SelfPeriodic, SameConvergedWallForceAsTheTwoCellDuct) {
  std::map<std::string, Real> force;
  for (const auto& [name, cells] : {std::pair<std::string, int>{"two", 2}, {"one", 1}}) {
    const CaseConfig c = load_case(test::source_path(kDuctCase),
                                   {"grid.x=[0.0, 0.2, " + std::to_string(cells) + "]", "grid.y=[-1.0, 1.0, 12]",
                                    "grid.z=[-1.0, 1.0, 12]", "solver.multigrid_levels=2"});
    const std::string out = test::fresh_temp_dir("narwhal_self_periodic_" + name).string();
    std::filesystem::remove_all(out);
    RunOptions opt;
    opt.out_dir = out;
    const RunSummary r = run_case(c, opt);
    ASSERT_EQ(r.status, RunStatus::Converged) << r.message;
    force[name] = test::read_csv(out + "/history.csv").at("jmin_cfx").back();
  }
  EXPECT_NEAR(force["one"] / force["two"], 1.0, 1e-8);
}

}  // namespace
}  // namespace narwhal
