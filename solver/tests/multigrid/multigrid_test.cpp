// FAS multigrid (NUMERICS §7): coarse grids of rotated multiblock grids keep
// their connectivity, multigrid converges to the single-grid answer on multiblock
// grids, restarts stay exact with cycles, and level limits are explained.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "app/driver.hpp"
#include "multigrid/coarsen.hpp"
#include "multigrid/fas.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

Grid rotated_split_box(int n) {
  Grid single;
  single.blocks.push_back(make_perturbed_box("b", n, 0.04));
  Grid g = split_blocks(single, {2, 2, 1}, true);
  for (auto s : {"imin", "imax", "jmin", "jmax", "kmin", "kmax"}) assign_bc(g, s, {BcType::Dirichlet});
  finalize_grid(g);
  return g;
}

TEST(Coarsening, RotatedMultiblockGridKeepsPatchesAndInterfaces) {
  Grid g = rotated_split_box(16);
  Grid c = coarsen(g);
  ASSERT_EQ(c.blocks.size(), g.blocks.size());
  EXPECT_EQ(c.interfaces.size(), g.interfaces.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    EXPECT_EQ(c.blocks[ib].cells() * 8, g.blocks[ib].cells());
    EXPECT_EQ(c.blocks[ib].patches.size(), g.blocks[ib].patches.size());
  }
  // Coarse ghost nodes across interfaces coincide with the donor's coarse nodes,
  // and the coarse volumes tile the same domain.
  EXPECT_LT(test::interface_ghost_node_mismatch(c, 1), 1e-14);
  Real vf = 0.0, vc = 0.0;
  for (const auto& b : g.blocks)
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i) vf += b.vol(i, j, k);
  for (const auto& b : c.blocks)
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i) vc += b.vol(i, j, k);
  EXPECT_NEAR(vf, vc, 1e-12);
}

TEST(Coarsening, SingleCellDirectionsAreKeptAndOddCountsExplained) {
  FlatPlateSpec s;
  s.n_runup = 8;
  s.n_plate = 24;
  s.n_normal = 16;
  Grid g = make_flat_plate(s);
  for (auto l : {"inlet", "outlet", "top"}) assign_bc(g, l, {BcType::Farfield, Vec3(1, 0, 0)});
  for (auto l : {"runup", "side_lo", "side_hi"}) assign_bc(g, l, {BcType::Symmetry});
  assign_bc(g, "plate", {BcType::Wall});
  finalize_grid(g);
  EXPECT_EQ(coarsening_factors(g.blocks[0]), (Index3{2, 2, 1}));
  Grid c1 = coarsen(g);
  EXPECT_EQ(c1.blocks[0].nk, 1);
  Grid c2 = coarsen(c1);
  Grid c3 = coarsen(c2);  // 4 x 2 cells: the run-up/plate split is now at i = 1
  EXPECT_NE(why_not_coarsenable(c3).find("odd"), std::string::npos) << why_not_coarsenable(c3);
}

// A level whose blocks would keep fewer than min_cells cells in a halved direction is not
// built; the note says which block stopped it.
TEST(Multigrid, LevelsStopWhereABlockWouldKeepTooFewCells) {
  Grid g = rotated_split_box(16);  // blocks of 8 x 8 x 16 cells
  EXPECT_EQ(why_not_coarsenable(g, 4), "");
  const Grid c = coarsen(g);       // 4 x 4 x 8: halving again would keep 2
  EXPECT_NE(why_not_coarsenable(c, 4).find("would keep 2 cell(s) in direction i (fewer than 4)"), std::string::npos)
      << why_not_coarsenable(c, 4);
  EXPECT_EQ(why_not_coarsenable(c), "");
  CaseConfig cc = load_case(test::source_path("validation/cases/mms/mms.toml"));
  const FlowParams fp = flow_params(cc);
  for (const int min_cells : {1, 4}) {
    Grid grid = rotated_split_box(16);
    FlowField f;
    f.allocate(grid, fp, cc.initial);
    MultigridSettings ms;
    ms.levels = 4;
    ms.min_cells = min_cells;
    Multigrid mg(grid, f, fp, cc.solver.newton, ms, Communicator::world());
    EXPECT_EQ(mg.levels(), min_cells == 1 ? 4 : 2);
    if (min_cells == 4) {
      EXPECT_NE(mg.level_note().find("fewer than 4"), std::string::npos) << mg.level_note();
    }
  }
}

TEST(Multigrid, MultiblockMultigridConvergesToTheSingleGridAnswer) {
  CaseConfig c = load_case(test::source_path("validation/cases/mms/mms.toml"));
  c.grid.perturbed_cells = 16;
  Grid g1 = build_grid(c);
  const FlowParams fp = flow_params(c);
  FlowField f1;
  f1.allocate(g1, fp, c.initial);
  NewtonSolver single(g1, f1, fp, c.solver.newton, Communicator::world());
  ASSERT_LT(test::converge(single, 1e-12, 3000), 1e-12);

  c.grid.split = {2, 2, 1};
  c.grid.split_rotate = true;
  Grid g4 = build_grid(c);
  FlowField f4;
  f4.allocate(g4, fp, c.initial);
  MultigridSettings ms;
  ms.levels = 3;
  ms.gamma = 1;
  Multigrid mg(g4, f4, fp, c.solver.newton, ms, Communicator::world());
  EXPECT_EQ(mg.levels(), 3);
  Real first = -1.0, last = 1.0;
  int cycles = 0;
  for (; cycles < 100 && last > 1e-12 * first; ++cycles) {
    const auto n = mg.cycle();
    if (first < 0) first = n.total;
    last = n.total;
  }
  std::printf("multiblock multigrid: %d V-cycles to a residual drop of %.2e\n", cycles, last / first);
  ASSERT_LE(last, 1e-12 * first);
  std::map<std::array<long long, 3>, State> ref;
  auto key = [](const Vec3& x) {
    return std::array<long long, 3>{std::llround(x[0] * 1e9), std::llround(x[1] * 1e9), std::llround(x[2] * 1e9)};
  };
  const Block& b1 = g1.blocks[0];
  for (int k = 0; k < b1.nk; ++k)
    for (int j = 0; j < b1.nj; ++j)
      for (int i = 0; i < b1.ni; ++i) ref[key(b1.xc(i, j, k))] = f1.Q[0](i, j, k);
  Real worst = 0.0;
  for (std::size_t ib = 0; ib < g4.blocks.size(); ++ib) {
    const Block& b = g4.blocks[ib];
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i)
          worst = std::max(worst, (f4.Q[ib](i, j, k) - ref.at(key(b.xc(i, j, k)))).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-10);
}

TEST(Multigrid, RestartWithCyclesReproducesTheUninterruptedHistory) {
  std::ifstream in(test::source_path("validation/cases/flat_plate_laminar/flat_plate.toml"));
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::vector<std::string> sets = {"grid.cells_runup=8", "grid.cells_plate=24", "grid.cells_normal=24",
                                         "grid.dx_leading_edge=1.0e-2", "grid.dy_wall=1.0e-3",
                                         "solver.multigrid_levels=3", "solver.multigrid_cycle=\"W\""};
  const CaseConfig c = parse_case(text, "mg.toml", ".", sets);
  namespace fs = std::filesystem;
  const fs::path dir = test::fresh_temp_dir("narwhal_mg_restart");
  fs::remove_all(dir);
  RunOptions a;
  a.out_dir = (dir / "a").string();
  a.max_iterations = 12;
  run_case(c, a);
  RunOptions b = a;
  b.out_dir = (dir / "b").string();
  b.max_iterations = 6;
  run_case(c, b);
  fs::copy_file(dir / "b" / "restart.h5", dir / "r6.h5");
  b.restart = (dir / "r6.h5").string();
  b.max_iterations = 12;
  run_case(c, b);
  const auto ra = test::history_rows((dir / "a" / "history.csv").string());
  const auto rb = test::history_rows((dir / "b" / "history.csv").string());
  ASSERT_EQ(ra.size(), 12u);
  ASSERT_EQ(rb.size(), 12u);
  for (std::size_t i = 0; i < ra.size(); ++i) EXPECT_EQ(ra[i], rb[i]) << "row " << i;
}

}  // namespace
}  // namespace narwhal
