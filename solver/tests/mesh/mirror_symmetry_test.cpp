// The discretization on the appended SUBOFF grid commutes with the mirror y -> -y: a
// mirror-symmetric state has a mirror-symmetric residual, wall distance and turbulence
// update. Issue 18 asks for side forces odd in the drift angle to 1e-6 and none at
// beta = 0, which needs exactly this (a converged solution that breaks the symmetry
// means an operator that does).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include <fmt/format.h>

#include "bc/boundary.hpp"
#include "mesh/appended_suboff.hpp"
#include "mesh/setup.hpp"
#include "physics/residual.hpp"
#include "test_support.hpp"
#include "turbulence/model.hpp"
#include "turbulence/wall_distance.hpp"

namespace narwhal {
namespace {

struct CellId {
  int block = -1, i = 0, j = 0, k = 0;
};

// Each cell's mirror cell (centre reflected in y = 0), matched on centres rounded to `tol`
// (the fins' section grids are mirror images to about 1e-9 L, not to round-off).
std::vector<std::vector<CellId>> mirror_cells(const Grid& g, Real tol) {
  using Key = std::array<long long, 3>;
  auto key = [tol](const Vec3& x) {
    return Key{std::llround(x[0] / tol), std::llround(x[1] / tol), std::llround(x[2] / tol)};
  };
  std::map<Key, CellId> at;
  for (int ib = 0; ib < static_cast<int>(g.blocks.size()); ++ib)
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) { at[key(g.blocks[ib].xc(i, j, k))] = {ib, i, j, k}; });
  std::vector<std::vector<CellId>> mirror(g.blocks.size());
  for (int ib = 0; ib < static_cast<int>(g.blocks.size()); ++ib)
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
      Vec3 m = g.blocks[ib].xc(i, j, k);
      m[1] = -m[1];
      const auto it = at.find(key(m));
      mirror[ib].push_back(it == at.end() ? CellId{} : it->second);
    });
  return mirror;
}

struct Asymmetry {
  Real worst = 0.0;  // max |a(c) - sign a(mirror c)|, relative to max |a| unless said otherwise
  std::string where;
};

// `value(ib, i, j, k)` returns an Eigen vector; `sign` its components' parity under the mirror.
template <class Value, class Sign>
Asymmetry mirror_asymmetry(const Grid& g, const std::vector<std::vector<CellId>>& mirror, Value value,
                           const Sign& sign, bool relative = true) {
  Real scale = 0.0;
  for (int ib = 0; ib < static_cast<int>(g.blocks.size()); ++ib)
    for_each_cell(g.blocks[ib],
                  [&](int i, int j, int k) { scale = std::max(scale, Real(value(ib, i, j, k).cwiseAbs().maxCoeff())); });
  if (!relative) scale = 1.0;
  Asymmetry a;
  for (int ib = 0; ib < static_cast<int>(g.blocks.size()); ++ib) {
    const Block& b = g.blocks[ib];
    std::size_t n = 0;
    for_each_cell(b, [&](int i, int j, int k) {
      const CellId m = mirror[static_cast<std::size_t>(ib)][n++];
      if (m.block < 0) {
        a.worst = std::numeric_limits<Real>::infinity();
        a.where = fmt::format("{} ({}, {}, {}) has no mirror cell", b.name, i, j, k);
        return;
      }
      const Real d =
          (value(ib, i, j, k) - sign.cwiseProduct(value(m.block, m.i, m.j, m.k))).cwiseAbs().maxCoeff() / scale;
      if (d > a.worst) {
        a.worst = d;
        a.where = fmt::format("{} ({}, {}, {}) of {}x{}x{} vs {} ({}, {}, {})", b.name, i, j, k, b.ni, b.nj, b.nk,
                              g.blocks[static_cast<std::size_t>(m.block)].name, m.i, m.j, m.k);
      }
    });
  }
  return a;
}

using Scalar1 = Eigen::Matrix<Real, 1, 1>;

// A smooth state: p, u, w even in y, v odd.
State symmetric_state(const Vec3& x) {
  const Real y2 = x[1] * x[1];
  State q;
  q << 0.1 * std::sin(3.0 * x[0]) + 0.2 * x[2] + 5.0 * y2, 1.0 + 0.3 * std::cos(2.0 * x[0] + 4.0 * x[2]) + 8.0 * y2,
      x[1] * (0.5 + 2.0 * x[0] * x[2]), 0.2 * std::sin(5.0 * x[0]) + 3.0 * y2 * x[2];
  return q;
}

// k and omega, positive and even in y.
TurbState symmetric_turbulence(const Vec3& x) {
  return {1e-4 * (1.5 + std::sin(3.0 * x[0]) + 30.0 * x[1] * x[1] + x[2]),
          50.0 * (1.5 + std::cos(2.0 * x[0]) + 20.0 * x[1] * x[1] - x[2])};
}

const State kStateParity = (State() << 1.0, 1.0, -1.0, 1.0).finished();

Grid appended_grid(BcType wall, BcType farfield) {
  Grid g = make_appended_suboff(test::small_appended_spec("sail_stern4"));
  assign_bc(g, "body", {wall});
  for (const auto& label : test::kAppendageLabels) assign_bc(g, label, {wall});
  assign_bc(g, "farfield", {farfield});
  finalize_grid(g);
  return g;
}

// The largest distance between a cell centre and its mirror cell's reflected centre.
Real grid_mirror_mismatch(const Grid& g, const std::vector<std::vector<CellId>>& mirror) {
  Real worst = 0.0;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    std::size_t n = 0;
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
      const CellId m = mirror[ib][n++];
      Vec3 x = g.blocks[static_cast<std::size_t>(m.block)].xc(m.i, m.j, m.k);
      x[1] = -x[1];
      worst = std::max(worst, (x - g.blocks[ib].xc(i, j, k)).norm());
    });
  }
  return worst;
}

void expect_mirror_symmetric_residual(BcType wall) {
  Grid g = appended_grid(wall, BcType::Dirichlet);
  FlowParams fp;
  fp.reynolds = 100.0;
  fp.exact = symmetric_state;
  FlowField f;
  f.allocate(g, fp, symmetric_state(Vec3::Zero()));
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) { f.Q[ib](i, j, k) = symmetric_state(g.blocks[ib].xc(i, j, k)); });
  fill_ghosts(g, f, fp);
  std::vector<GhostArray<State>> R;
  compute_residual(g, f, fp, R);
  const auto mirror = mirror_cells(g, 1e-7);
  const Asymmetry a = mirror_asymmetry(
      g, mirror, [&](int ib, int i, int j, int k) { return R[static_cast<std::size_t>(ib)](i, j, k); }, kStateParity);
  // Measured 2.7e-11 (round-off); a wrong interface orientation or face gives order one.
  EXPECT_LT(a.worst, 1e-10) << "worst at " << a.where;
}

TEST(MirrorSymmetry, MeanFlowResidualOfASymmetricStateIsSymmetricWithDirichletWalls) {
  expect_mirror_symmetric_residual(BcType::Dirichlet);
}

TEST(MirrorSymmetry, MeanFlowResidualOfASymmetricStateIsSymmetricWithNoSlipWalls) {
  expect_mirror_symmetric_residual(BcType::Wall);
}

// Wall faces are warped quadrilaterals; a mirrored block numbers its corners the other way
// round, so a distance to one fixed triangulation differed between mirror cells by the
// warp (4e-5 of the SST update at the sail's tip on this grid).
TEST(MirrorSymmetry, WallDistanceIsSymmetricToTheGridsOwnMismatch) {
  const Grid g = appended_grid(BcType::Wall, BcType::Farfield);
  const auto mirror = mirror_cells(g, 1e-7);
  const Real mismatch = grid_mirror_mismatch(g, mirror);
  RecordProperty("grid_mirror_mismatch", fmt::format("{:.2e}", mismatch));
  const WallDistance w = compute_wall_distance(g);
  const Asymmetry a = mirror_asymmetry(
      g, mirror, [&](int ib, int i, int j, int k) { return Scalar1(w.d[static_cast<std::size_t>(ib)](i, j, k)); },
      Scalar1(1.0), false);
  // A centre and a wall node each off by at most `mismatch`.
  EXPECT_LE(a.worst, 2.0 * mismatch + 1e-15) << "worst at " << a.where << " (grid mismatch " << mismatch << ")";
}

TEST(MirrorSymmetry, SstUpdateOfASymmetricStateIsSymmetric) {
  Grid g = appended_grid(BcType::Wall, BcType::Farfield);
  FlowParams fp;
  fp.reynolds = 1e6;
  FlowField f;
  f.allocate(g, fp, symmetric_state(Vec3::Zero()));
  TurbulenceSettings ts;
  ts.model = "sst";
  ts.smoother = "points";
  ts.sgs_iterations = 100;  // converged within each block: the step is then the sweeps' fixed point
  auto model = make_turbulence_model(ts, g, Communicator::world());
  model->initialize(g, f, fp, false);
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
      const Vec3 x = g.blocks[ib].xc(i, j, k);
      f.Q[ib](i, j, k) = symmetric_state(x);
      f.turb[ib](i, j, k) = symmetric_turbulence(x);
    });
  fill_ghosts(g, f, fp);
  model->update_viscosity(g, f, fp);
  const auto mirror = mirror_cells(g, 1e-7);
  const Asymmetry nu = mirror_asymmetry(
      g, mirror, [&](int ib, int i, int j, int k) { return Scalar1(f.nu[static_cast<std::size_t>(ib)](i, j, k)); },
      Scalar1(1.0));
  EXPECT_LT(nu.worst, 1e-10) << "eddy viscosity: worst at " << nu.where;

  // One step with the linear equations relaxed to convergence within each block (the
  // interfaces lag, which a symmetric block layout keeps symmetric).
  model->set_update(1.0, 1);
  const auto before = f.turb;
  model->advance(g, f, fp, 10.0);
  const Asymmetry step = mirror_asymmetry(
      g, mirror,
      [&](int ib, int i, int j, int k) -> TurbState {
        const auto b = static_cast<std::size_t>(ib);
        return f.turb[b](i, j, k) - before[b](i, j, k);
      },
      TurbState(1.0, 1.0));
  // Measured 1.3e-7, at the stern planes' leading edges: the fins' section grids are mirror
  // images to 7e-10 L (the wall-distance test records it), seen through cells 1e-4 L wide.
  EXPECT_LT(step.worst, 1e-6) << "SST update: worst at " << step.where;
}

}  // namespace
}  // namespace narwhal
