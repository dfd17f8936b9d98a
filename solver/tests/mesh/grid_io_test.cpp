// Grids in and out (issue 16 bar 6): CGNS written by Narwhal reads back bit for bit
// and reproduces a run exactly; a Plot3D grid converted by the CGNS tools reads; the
// quality measures of `narwhal grid` on grids whose answers are known.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "app/driver.hpp"
#include "io/cgns_reader.hpp"
#include "io/cgns_writer.hpp"
#include "io/openfoam_writer.hpp"
#include "mesh/body_of_revolution.hpp"
#include "mesh/grid_quality.hpp"
#include "mesh/plot3d.hpp"
#include "mesh/setup.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

namespace fs = std::filesystem;

Grid small_body_grid() {
  BodyGridSpec s;
  s.profile = spheroid_profile(1.0, 4.0);
  s.cells_along = 12;
  s.cells_around = 4;
  s.cells_normal = 6;
  s.first_spacing = 1e-3;
  s.far_field = 16.0;
  Grid g = make_body_of_revolution(s);
  assign_bc(g, "body", {BcType::Wall});
  assign_bc(g, "farfield", {BcType::Farfield});
  finalize_grid(g);
  return g;
}

void expect_same_nodes(const Block& a, const Block& b) {
  ASSERT_EQ(a.dims(), b.dims()) << a.name;
  for (int k = 0; k <= a.nk; ++k)
    for (int j = 0; j <= a.nj; ++j)
      for (int i = 0; i <= a.ni; ++i) ASSERT_EQ(a.x(i, j, k), b.x(i, j, k)) << a.name << " node " << i << "," << j << "," << k;
}

TEST(CgnsGrid, WrittenGridReadsBackBitForBitWithItsPatchLabels) {
  const Grid g = small_body_grid();
  const fs::path dir = test::fresh_temp_dir("cgns_grid");
  write_cgns_grid((dir / "grid.cgns").string(), g);
  const std::vector<Block> back = read_cgns_grid((dir / "grid.cgns").string());
  ASSERT_EQ(back.size(), g.blocks.size());
  for (std::size_t ib = 0; ib < back.size(); ++ib) {
    const Block& a = g.blocks[ib];
    const Block& b = back[ib];
    EXPECT_EQ(a.name, b.name);
    expect_same_nodes(a, b);
    // Physical patches come back with their labels; interfaces are re-derived.
    std::vector<const Patch*> physical;
    for (const Patch& p : a.patches)
      if (p.type != BcType::Interface) physical.push_back(&p);
    ASSERT_EQ(b.patches.size(), physical.size()) << a.name;
    for (std::size_t n = 0; n < physical.size(); ++n) {
      EXPECT_EQ(b.patches[n].label, physical[n]->label);
      EXPECT_EQ(b.patches[n].side, physical[n]->side);
      for (int t = 0; t < 3; ++t) {
        if (t == side_dir(physical[n]->side)) continue;  // the normal entry is unused
        EXPECT_EQ(b.patches[n].lo[t], physical[n]->lo[t]);
        EXPECT_EQ(b.patches[n].hi[t], physical[n]->hi[t]);
      }
    }
  }
}

// The same case run on the generated grid and on that grid read back from CGNS:
// identical histories (every residual and force, to the last digit).
TEST(CgnsGrid, RunOnTheWrittenGridReproducesTheGeneratedOne) {
  const fs::path dir = test::fresh_temp_dir("cgns_run");
  const std::string text = test::read_text(test::source_path("validation/cases/mms_bodies/sphere.toml"));
  const std::vector<std::string> coarse = {"grid.coarsen=2", "solver.max_iterations=6", "solver.multigrid_levels=2"};
  const CaseConfig generated = parse_case(text, "sphere.toml", ".", coarse);
  write_cgns_grid((dir / "sphere.cgns").string(), build_grid(generated));
  RunOptions o;
  o.out_dir = (dir / "generated").string();
  run_case(generated, o);

  const auto grid_begin = text.find("[grid]"), grid_end = text.find("\n[", grid_begin + 1);
  ASSERT_NE(grid_end, std::string::npos);
  const std::string imported_text = text.substr(0, grid_begin) + "[grid]\ntype = \"cgns\"\nfile = \"sphere.cgns\"\n" +
                                    text.substr(grid_end);
  const CaseConfig imported = parse_case(imported_text, (dir / "imported.toml").string(), dir.string(),
                                         {"solver.max_iterations=6", "solver.multigrid_levels=2"});
  o.out_dir = (dir / "imported").string();
  run_case(imported, o);
  const auto a = test::history_rows((dir / "generated" / "history.csv").string());
  const auto b = test::history_rows((dir / "imported" / "history.csv").string());
  ASSERT_EQ(a.size(), 6u);
  EXPECT_EQ(a, b);
}

// A Plot3D grid converted by the CGNS library's own tool (Debian cgns-convert).
TEST(CgnsGrid, Plot3dConvertedByTheCgnsToolsReads) {
  if (std::system("command -v plot3d_to_cgns > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "plot3d_to_cgns (Debian package cgns-convert) is not installed";
  const Grid g = small_body_grid();
  const fs::path dir = test::fresh_temp_dir("cgns_convert");
  write_plot3d_fortran((dir / "grid.xyz").string(), g.blocks);
  const std::string cmd = fmt::format("plot3d_to_cgns -u -d '{}' '{}' > '{}' 2>&1", (dir / "grid.xyz").string(),
                                      (dir / "grid.cgns").string(), (dir / "convert.log").string());
  ASSERT_EQ(std::system(cmd.c_str()), 0) << test::read_text((dir / "convert.log").string());
  const std::vector<Block> back = read_cgns_grid((dir / "grid.cgns").string());
  ASSERT_EQ(back.size(), g.blocks.size());
  for (std::size_t ib = 0; ib < back.size(); ++ib) {
    expect_same_nodes(g.blocks[ib], back[ib]);
    EXPECT_TRUE(back[ib].patches.empty());  // Plot3D carries no patches: the case's grid.patch list supplies them
  }
}

TEST(CgnsGrid, MissingAndForeignFilesAreNamed) {
  const fs::path dir = test::fresh_temp_dir("cgns_bad");
  try {
    read_cgns_grid((dir / "none.cgns").string());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("none.cgns"), std::string::npos) << e.what();
  }
  test::write_text((dir / "text.cgns").string(), "not a CGNS file\n");
  try {
    read_cgns_grid((dir / "text.cgns").string());
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("text.cgns"), std::string::npos) << e.what();
  }
}

Grid single_box(const std::vector<Real>& xs, const std::vector<Real>& ys, const std::vector<Real>& zs) {
  Grid g;
  g.blocks.push_back(make_box("box", xs, ys, zs));
  for (const char* side : {"imin", "imax", "jmin", "jmax", "kmax"}) assign_bc(g, side, {BcType::Farfield});
  assign_bc(g, "kmin", {BcType::Wall});
  finalize_grid(g);
  return g;
}

// The entries of an OpenFOAM list file this writer made: after the header, a count,
// then one entry per line between "(" and ")".
std::vector<std::string> foam_entries(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line) && line != "(") {
  }
  std::vector<std::string> out;
  while (std::getline(in, line) && line != ")") out.push_back(line);
  return out;
}

// The six-block body grid as an OpenFOAM mesh: every cell closed by exactly six faces
// whose area vectors (oriented out of the cell) sum to zero, the volumes by the
// divergence theorem equal to Narwhal's, internal faces in upper-triangular order and
// pointing from owner to neighbour, the wall faces in a `wall` patch.
TEST(OpenFoamMesh, BodyGridClosesEveryCellAndKeepsTheVolumesAndPatches) {
  const Grid g = small_body_grid();
  const fs::path dir = test::fresh_temp_dir("openfoam_mesh");
  const OpenFoamMeshCounts n = write_openfoam_mesh(dir.string(), g);
  const fs::path mesh = dir / "constant" / "polyMesh";
  std::vector<Vec3> points;
  for (const std::string& e : foam_entries(mesh / "points")) {
    std::istringstream ss(e.substr(1));
    Vec3 x;
    ss >> x[0] >> x[1] >> x[2];
    points.push_back(x);
  }
  std::vector<std::array<int, 4>> faces;
  for (const std::string& e : foam_entries(mesh / "faces")) {
    ASSERT_EQ(e.substr(0, 2), "4(");
    std::istringstream ss(e.substr(2));
    std::array<int, 4> q{};
    ss >> q[0] >> q[1] >> q[2] >> q[3];
    faces.push_back(q);
  }
  std::vector<int> owner, neighbour;
  for (const std::string& e : foam_entries(mesh / "owner")) owner.push_back(std::stoi(e));
  for (const std::string& e : foam_entries(mesh / "neighbour")) neighbour.push_back(std::stoi(e));
  ASSERT_EQ(points.size(), n.points);
  ASSERT_EQ(faces.size(), n.faces);
  ASSERT_EQ(owner.size(), n.faces);
  ASSERT_EQ(neighbour.size(), n.internal_faces);
  ASSERT_EQ(n.cells, g.cells());
  // Shared nodes are one point each: (nodes of all blocks) minus duplicates.
  std::size_t block_nodes = 0;
  for (const Block& b : g.blocks) block_nodes += static_cast<std::size_t>(b.ni + 1) * (b.nj + 1) * (b.nk + 1);
  EXPECT_LT(points.size(), block_nodes);

  std::vector<int> count(n.cells, 0);
  std::vector<Vec3> closure(n.cells, Vec3::Zero());
  std::vector<Real> volume(n.cells, 0.0);
  std::vector<Vec3> centre(n.cells, Vec3::Zero());
  auto area = [&](const std::array<int, 4>& q) {
    const Vec3 d1 = points[q[2]] - points[q[0]], d2 = points[q[3]] - points[q[1]];
    return Vec3(0.5 * d1.cross(d2));
  };
  auto middle = [&](const std::array<int, 4>& q) {
    return Vec3(0.25 * (points[q[0]] + points[q[1]] + points[q[2]] + points[q[3]]));
  };
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const Vec3 S = area(faces[f]), xm = middle(faces[f]);
    ++count[owner[f]];
    closure[owner[f]] += S;
    volume[owner[f]] += xm.dot(S) / 3.0;
    centre[owner[f]] += xm / 6.0;
    if (f < neighbour.size()) {
      ASSERT_LT(owner[f], neighbour[f]);
      if (f > 0) {
        ASSERT_TRUE(owner[f - 1] < owner[f] || (owner[f - 1] == owner[f] && neighbour[f - 1] < neighbour[f]));
      }
      ++count[neighbour[f]];
      closure[neighbour[f]] -= S;
      volume[neighbour[f]] -= xm.dot(S) / 3.0;
      centre[neighbour[f]] += xm / 6.0;
    }
  }
  std::size_t cell = 0;
  for (const Block& b : g.blocks)
    for_each_cell(b, [&](int i, int j, int k) {
      EXPECT_EQ(count[cell], 6) << b.name;
      EXPECT_LT(closure[cell].norm(), 1e-12 * std::cbrt(b.vol(i, j, k) * b.vol(i, j, k))) << b.name;
      EXPECT_NEAR(volume[cell], b.vol(i, j, k), 1e-9 * b.vol(i, j, k)) << b.name << " " << i << "," << j << "," << k;
      ++cell;
    });
  for (std::size_t f = 0; f < neighbour.size(); ++f)
    EXPECT_GT(area(faces[f]).dot(centre[neighbour[f]] - centre[owner[f]]), 0.0) << "face " << f;

  const std::string boundary = test::read_text((mesh / "boundary").string());
  std::size_t wall_faces = 0;
  for (const Block& b : g.blocks)
    for (const Patch& p : b.patches)
      if (p.label == "body") wall_faces += static_cast<std::size_t>(b.n((side_dir(p.side) + 1) % 3)) * b.n((side_dir(p.side) + 2) % 3);
  EXPECT_NE(boundary.find("body\n    {\n        type wall;"), std::string::npos) << boundary;
  EXPECT_NE(boundary.find(fmt::format("nFaces {};\n        startFace {};", wall_faces, n.internal_faces)),
            std::string::npos)
      << boundary;
  EXPECT_NE(boundary.find("farfield\n    {\n        type patch;"), std::string::npos) << boundary;
  fs::remove_all(dir);
}

TEST(GridQuality, MeasuresOfAStretchedBoxAreItsSpacings) {
  // x: 1, 1, 1; y: 1, 2, 4 (ratio 2); z: 0.1, 0.2 from the wall.
  const Grid g = single_box({0, 1, 2, 3}, {0, 1, 3, 7}, {0, 0.1, 0.3});
  const GridQuality q = measure_grid_quality(g, {"kmin"}, 1.0e6);
  EXPECT_EQ(q.cells, 18u);
  EXPECT_NEAR(q.min_corner_jacobian.value, 1.0, 1e-14);
  EXPECT_EQ(q.folded_cells, 0u);
  EXPECT_NEAR(q.max_stretching.value, 2.0, 1e-14);
  EXPECT_NEAR(q.max_aspect_ratio.value, 40.0, 1e-12);  // 4 / 0.1
  EXPECT_NEAR(q.min_wall_orthogonality_deg.value, 90.0, 1e-12);
  EXPECT_NEAR(q.max_first_cell_height.value, 0.05, 1e-15);
  // y+ = h Re sqrt(Cf / 2), Cf from the wall's length 3 at Re = 1e6 per unit length.
  EXPECT_NEAR(q.max_y_plus.value, 0.05 * 1e6 * std::sqrt(0.5 * flat_plate_friction_estimate(3e6)), 1e-9);
}

TEST(GridQuality, SkewedWallLinesAndAFoldedCellAreFound) {
  Grid g = single_box({0, 1, 2}, {0, 1}, {0, 1, 2});
  Block& b = g.blocks[0];
  // Lean the first line off the wall by 30 degrees at i = 1: the wall faces on either
  // side see it through their opposite faces' centroids.
  b.x(1, 0, 1) += Vec3(std::tan(M_PI / 6.0), 0, 0);
  b.x(1, 1, 1) += Vec3(std::tan(M_PI / 6.0), 0, 0);
  prepare_geometry(g);
  GridQuality q = measure_grid_quality(g, {"kmin"}, 0.0);
  EXPECT_LT(q.min_wall_orthogonality_deg.value, 90.0 - 5.0);
  EXPECT_EQ(q.folded_cells, 0u);
  EXPECT_NO_THROW(require_unfolded(q, "case.toml"));
  // Push a node through the opposite face: the cell folds while staying listed by name.
  b.x(2, 1, 2) += Vec3(-1.6, 0, 0);
  prepare_geometry(g);
  q = measure_grid_quality(g, {"kmin"}, 0.0);
  EXPECT_GT(q.folded_cells, 0u);
  try {
    require_unfolded(q, "case.toml");
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("case.toml"), std::string::npos) << m;
    EXPECT_NE(m.find("block 'box' cell (1, 0, 1)"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace narwhal
