// Planar slabs (physics/planar.hpp): detection, and that skipping the symmetry
// planes changes neither the residual nor the converged answer.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "app/driver.hpp"
#include "physics/planar.hpp"
#include "physics/residual.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

const std::string kPlateCase = "validation/cases/flat_plate_laminar/flat_plate.toml";
const std::vector<std::string> kSmallPlate = {"grid.cells_runup=8", "grid.cells_plate=24", "grid.cells_normal=24",
                                              "grid.dx_leading_edge=8e-3", "grid.dy_wall=4e-4"};

struct PlateSetup {
  CaseConfig c;
  Grid g;
  FlowParams fp;
  FlowField f;
};

PlateSetup small_plate(std::vector<std::string> extra = {}) {
  auto overrides = kSmallPlate;
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  PlateSetup s{load_case(test::source_path(kPlateCase), overrides), {}, {}, {}};
  s.g = build_grid(s.c);
  s.fp = flow_params(s.c);
  s.f.allocate(s.g, s.fp, s.c.initial);
  return s;
}

// A non-uniform in-plane state: every face carries a different flux.
void randomize_in_plane(PlateSetup& s, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(-0.5, 0.5);
  for (std::size_t ib = 0; ib < s.g.blocks.size(); ++ib)
    for_each_cell(s.g.blocks[ib], [&](int i, int j, int k) { s.f.Q[ib](i, j, k) << u(rng), 1 + u(rng), u(rng), 0.0; });
}

TEST(Planar, FlatPlateIsASlabInK) {
  PlateSetup s = small_plate();
  Vec3 n;
  EXPECT_EQ(planar_slab_direction(s.g.blocks[0], n), 2);
  EXPECT_NEAR(std::abs(n[2]), 1.0, 1e-15);
  EXPECT_FALSE(mark_planar_blocks(s.g, s.f, s.fp).empty());
  EXPECT_EQ(s.g.blocks[0].planar_dir, 2);
}

TEST(Planar, NotASlabWhenThickerOrNotSymmetricOrTilted) {
  {  // two cells across
    Grid g;
    g.blocks.push_back(make_box("b", {0, 1, 2}, {0, 1, 2}, {0, 0.5, 1}));
    for (auto& p : g.blocks[0].patches) p.type = BcType::Symmetry;
    finalize_grid(g);
    Vec3 n;
    EXPECT_EQ(planar_slab_direction(g.blocks[0], n), -1);
  }
  {  // a wall on one of the planes
    PlateSetup s = small_plate({"bc.side_hi.type=\"wall\""});
    Vec3 n;
    EXPECT_EQ(planar_slab_direction(s.g.blocks[0], n), -1);
  }
  {  // planes not parallel: one node of the upper plane lifted
    PlateSetup s = small_plate();
    Block& b = s.g.blocks[0];
    b.x(3, 3, 1)[2] += 0.01;
    prepare_geometry(s.g);
    Vec3 n;
    EXPECT_EQ(planar_slab_direction(b, n), -1);
  }
}

TEST(Planar, FlowAcrossThePlaneKeepsTheFullTreatment) {
  PlateSetup s = small_plate();
  s.f.Q[0](5, 5, 0)[3] = 1e-3;
  const std::string why = mark_planar_blocks(s.g, s.f, s.fp);
  EXPECT_NE(why.find("not planar"), std::string::npos) << why;
  EXPECT_EQ(s.g.blocks[0].planar_dir, -1);
  PlateSetup t = small_plate({"flow.initial_velocity=[1.0, 0.0, 0.1]"});
  EXPECT_NE(mark_planar_blocks(t.g, t.f, t.fp).find("not planar"), std::string::npos);
  EXPECT_EQ(t.g.blocks[0].planar_dir, -1);
}

TEST(Planar, SkippingThePlanesLeavesTheResidualUnchanged) {
  PlateSetup s = small_plate();
  randomize_in_plane(s, 7);
  fill_ghosts(s.g, s.f, s.fp);
  std::vector<GhostArray<State>> full, planar;
  compute_residual(s.g, s.f, s.fp, full);
  ASSERT_FALSE(mark_planar_blocks(s.g, s.f, s.fp).empty());
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
    overrides.push_back(std::string("solver.planar_shortcut=") + on);
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

}  // namespace
}  // namespace narwhal
