// Rigid grid motion (NUMERICS §2.4, §1.5): swept volumes, the discrete GCL in every
// cell, and free-stream preservation on a moving, rotating, perturbed multiblock grid,
// also while it deforms (§12.1 item 3's smooth deformation, MovingGrid::reshape).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "app/dual_time.hpp"
#include "core/error.hpp"
#include "config/case_config.hpp"
#include "implicit/newton.hpp"
#include "mesh/generators.hpp"
#include "mesh/setup.hpp"
#include "motion/attitude.hpp"
#include "motion/grid_motion.hpp"
#include "multigrid/fas.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

std::array<Vec3, 8> unit_cube() {
  std::array<Vec3, 8> n;
  for (int r = 0; r < 2; ++r)
    for (int q = 0; q < 2; ++q)
      for (int p = 0; p < 2; ++p) n[p + 2 * q + 4 * r] = Vec3(p, q, r);
  return n;
}

TEST(GridMotion, HexahedronVolumeIsExactForAffineCellsAndSignedByHandedness) {
  const Mat3 A = (Mat3() << 1.2, 0.3, -0.1, 0.2, 0.9, 0.4, -0.3, 0.1, 1.1).finished();
  std::array<Vec3, 8> n = unit_cube();
  for (auto& x : n) x = A * x + Vec3(3, -1, 2);
  EXPECT_NEAR(hexahedron_volume(n), A.determinant(), 1e-14);
  std::swap(n[0], n[1]), std::swap(n[2], n[3]), std::swap(n[4], n[5]), std::swap(n[6], n[7]);  // mirrored
  EXPECT_NEAR(hexahedron_volume(n), -A.determinant(), 1e-14);
}

// A perturbed box's nodes moved by `pose` about its centre.
Block moved_copy(const Block& b, const RigidPose& pose) {
  Block m = b;
  for (auto& x : m.x.raw()) x = pose.apply(x, Vec3(0.5, 0.5, 0.5));
  compute_metrics(m);
  return m;
}

RigidPose pose_at(Real t) {
  RigidPose p;
  p.rotation = rotation_matrix(quaternion_from_euler({0.4 * std::sin(3 * t), 0.3 * t, -0.5 * t * t}));
  p.displacement = Vec3(0.2 * t, -0.1 * std::sin(2 * t), 0.05 * t * t);
  return p;
}

TEST(GridMotion, SweptVolumesOfACellsFacesAddUpToItsChangeOfVolume) {
  Grid g;
  g.blocks.push_back(make_perturbed_box("box", 4, 0.05));
  randomly_perturb(g.blocks[0], 0.2, 7, false);
  prepare_geometry(g);
  const Block a = g.blocks[0];
  Block b = moved_copy(a, pose_at(0.3));
  randomly_perturb(b, 0.2, 11, true);  // a deformation on top: the sum still telescopes
  compute_metrics(b);
  for_each_cell(a, [&](int i, int j, int k) {
    const Index3 c{i, j, k};
    Real sum = 0.0;
    for (int d = 0; d < 3; ++d)
      sum += swept_volume(a.x, b.x, d, add(c, unit(d))) - swept_volume(a.x, b.x, d, c);
    EXPECT_NEAR(sum, b.vol(c) - a.vol(c), 1e-15) << i << " " << j << " " << k;
  });
  // a pure translation along x sweeps the i-faces' volume S_x dx
  const Block t = moved_copy(a, RigidPose{Mat3::Identity(), Vec3(1e-3, 0, 0)});
  const Index3 f{2, 1, 1};
  EXPECT_NEAR(swept_volume(a.x, t.x, 0, f), a.S[0](f)[0] * 1e-3, 1e-17);
}

// Under rigid motion every cell keeps its volume, so the GCL alone does not see the
// BDF2 face speed's second term; its accuracy does: k_t against the rate at which the
// face sweeps volume at t^{n+1} (a centred difference of the swept volume, exact to
// 1e-10), first order with BDF1, second with BDF2.
Real face_speed_error(TimeConfig::Scheme scheme, Real dt) {
  const Real T = 0.4, h = 1e-5;
  const Vec3 pivot(0.5, 0.5, 0.5);
  Grid g;
  g.blocks.push_back(make_perturbed_box("box", 4, 0.05));
  prepare_geometry(g);
  const Block reference = g.blocks[0];
  MovingGrid moving(g, pivot);
  const int steps = static_cast<int>(std::lround(T / dt));
  for (int s = 1; s <= steps; ++s) {
    const bool bdf2 = scheme == TimeConfig::Scheme::Bdf2 && s > 1;
    moving.move_to(RigidMotionSample{pose_at(s * dt)}, dt, bdf2 ? BdfCoefficients::bdf2(1.0) : BdfCoefficients::bdf1());
  }
  const Block before = moved_copy(reference, pose_at(T - h)), after = moved_copy(reference, pose_at(T + h));
  Real worst = 0.0;
  const Block& b = g.blocks[0];
  for (int d = 0; d < 3; ++d)
    for_each_cell(b, [&](int i, int j, int k) {
      const Index3 f{i, j, k};
      const Real rate = swept_volume(before.x, after.x, d, f) / (2 * h);
      worst = std::max(worst, std::abs(b.kt[d](f) + rate) / b.S[d](f).norm());
    });
  return worst;
}

TEST(GridMotion, FaceSpeedsApproximateTheSweptVolumeRateAtTheSchemesOrder) {
  for (auto [scheme, order] : {std::pair{TimeConfig::Scheme::Bdf1, 1.0}, {TimeConfig::Scheme::Bdf2, 2.0}}) {
    const Real e1 = face_speed_error(scheme, 0.02), e2 = face_speed_error(scheme, 0.01);
    EXPECT_NEAR(std::log2(e1 / e2), order, 0.15) << e1 << " " << e2;
  }
}

// Cases of this file: a perturbed box cut into four blocks (two of them with rotated
// index orientations), a uniform stream on every side.
CaseConfig uniform_stream_case() {
  std::string text = R"(
[case]
title = "free stream on a moving grid"
[grid]
type = "perturbed_box"
cells = 8
amplitude = 0.06
split = [2, 2, 1]
split_rotate = true
[flow]
reynolds = 50.0
initial_velocity = [0.6, -0.3, 0.2]
)";
  for (const char* side : {"imin", "imax", "jmin", "jmax", "kmin", "kmax"})
    text += std::string("[bc.") + side + "]\ntype = \"farfield\"\nvelocity = [0.6, -0.3, 0.2]\n";
  return parse_case(text, "uniform.toml", ".");
}

// §12.1 item 3: the nodes as built X deformed to X + 0.05 sin(2 pi X) sin(2 pi Y)
// sin(2 pi Z) sin(omega t) (1, 1, 1), ghost nodes alike (a function of X: nodes that
// coincide stay so).
std::vector<GhostArray<Vec3>> deformed(const std::vector<GhostArray<Vec3>>& as_built, Real t) {
  std::vector<GhostArray<Vec3>> out = as_built;
  const Real pi = std::acos(-1.0), a = 0.05 * std::sin(5.0 * t);
  for (auto& block : out)
    for (Vec3& x : block.raw())
      x += a * std::sin(2 * pi * x[0]) * std::sin(2 * pi * x[1]) * std::sin(2 * pi * x[2]) * Vec3::Ones();
  return out;
}

struct GclMeasure {
  Real worst = 0.0;         // max over cells and steps of |dV/dt + sum_f s k_t| / V
  Real volume_change = 0.0;  // the largest relative change of a cell's volume in a step
};

// Four BDF2 steps of pose_at's motion (and of `deformed`'s deformation on top): the
// discrete GCL's error in every cell.
GclMeasure gcl_over_four_steps(bool deforming) {
  CaseConfig c = uniform_stream_case();
  Grid g = build_grid(c);
  MovingGrid moving(g, Vec3(0.5, 0.5, 0.5));
  const std::vector<GhostArray<Vec3>> as_built = moving.reference();
  const TimeConfig tc = test::time_config(TimeConfig::Scheme::Bdf2, 0.1, 4);
  DualTime time(g, tc);
  FlowField f;
  f.allocate(g, FlowParams{}, State::Zero());
  auto volumes_now = [&] {
    std::vector<Real> v;
    for (const Block& b : g.blocks) for_each_cell(b, [&](int i, int j, int k) { v.push_back(b.vol(i, j, k)); });
    return v;
  };
  std::vector<Real> v_nm1, v_n = volumes_now();
  GclMeasure m;
  for (int s = 1; s <= 4; ++s) {
    time.begin_step(g, f);
    const BdfCoefficients& bdf = time.term().coefficients();
    if (deforming) moving.reshape(deformed(as_built, s * tc.step));
    moving.move_to(RigidMotionSample{pose_at(s * tc.step)}, tc.step, bdf);
    std::size_t n = 0;
    for (const Block& b : g.blocks)
      for_each_cell(b, [&](int i, int j, int k) {
        const Index3 cc{i, j, k};
        Real flux = 0.0;
        for (int d = 0; d < 3; ++d) flux += b.kt[d](add(cc, unit(d))) - b.kt[d](cc);
        const Real dvdt = (bdf.c0 * b.vol(cc) + bdf.c1 * v_n[n] + (s > 1 ? bdf.c2 * v_nm1[n] : 0.0)) / tc.step;
        m.worst = std::max(m.worst, std::abs(dvdt + flux) / b.vol(cc));
        m.volume_change = std::max(m.volume_change, std::abs(b.vol(cc) - v_n[n]) / b.vol(cc));
        ++n;
      });
    v_nm1 = v_n;
    v_n = volumes_now();
  }
  return m;
}

TEST(GridMotion, DiscreteGclHoldsInEveryCellWithBdf2) { EXPECT_LT(gcl_over_four_steps(false).worst, 1e-12); }

TEST(GridMotion, DiscreteGclHoldsInEveryCellWhileTheGridDeformsAsItMoves) {
  const GclMeasure m = gcl_over_four_steps(true);
  EXPECT_GT(m.volume_change, 1e-2);  // the cells do change volume: the deformation is seen
  EXPECT_LT(m.worst, 1e-12);
}

TEST(GridMotion, ANewShapeMustKeepTheGridsLayout) {
  CaseConfig c = uniform_stream_case();
  Grid g = build_grid(c);
  MovingGrid moving(g, Vec3::Zero());
  std::vector<GhostArray<Vec3>> fewer = moving.reference();
  fewer.pop_back();
  EXPECT_THROW(moving.reshape(fewer), Error);
}

// The residual R* of the uniform stream after each move, and the state after the
// step's iterations: both stay at round-off.
void expect_free_stream_preserved(int multigrid_levels, bool deforming = false) {
  CaseConfig c = uniform_stream_case();
  Grid g = build_grid(c);
  FlowParams fp = c.flow;
  FlowField f;
  f.allocate(g, fp, c.initial);
  const TimeConfig tc = test::time_config(TimeConfig::Scheme::Bdf2, 0.05, 5);
  DualTime time(g, tc);
  NewtonSettings ns;
  std::unique_ptr<NewtonSolver> single;
  std::unique_ptr<Multigrid> mg;
  std::vector<std::unique_ptr<MovingGrid>> moving;
  if (multigrid_levels > 1) {
    MultigridSettings ms;
    ms.levels = multigrid_levels;
    mg = std::make_unique<Multigrid>(g, f, fp, ns, ms, Communicator::world());
    ASSERT_EQ(mg->levels(), multigrid_levels);
    mg->use_physical_time(&time.term());
    for (int l = 0; l < mg->levels(); ++l) moving.push_back(std::make_unique<MovingGrid>(mg->grid(l), Vec3(0.5, 0.5, 0.5)));
  } else {
    single = std::make_unique<NewtonSolver>(g, f, fp, ns, Communicator::world());
    single->set_physical_time(&time.term());
    moving.push_back(std::make_unique<MovingGrid>(g, Vec3(0.5, 0.5, 0.5)));
  }
  NewtonSolver& top = mg ? mg->finest() : *single;
  const Real inf = std::numeric_limits<Real>::infinity();
  std::vector<std::vector<GhostArray<Vec3>>> as_built;
  for (auto& m : moving) as_built.push_back(m->reference());
  for (int s = 1; s <= tc.steps; ++s) {
    time.begin_step(g, f);
    for (std::size_t l = 0; deforming && l < moving.size(); ++l) moving[l]->reshape(deformed(as_built[l], s * tc.step));
    for (auto& m : moving) m->move_to(RigidMotionSample{pose_at(s * tc.step)}, tc.step, time.term().coefficients());
    EXPECT_LT(top.evaluate_residual().total, 1e-12) << "step " << s;
    for (int m = 0; m < 3; ++m) mg ? mg->cycle_with_cfl(inf) : single->iterate_with_cfl(inf);
    Real change = 0.0;
    for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
      for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
        change = std::max(change, (f.Q[ib](i, j, k) - c.initial).cwiseAbs().maxCoeff());
      });
    EXPECT_LT(change, 1e-12) << "step " << s;
  }
}

TEST(GridMotion, FreeStreamIsPreservedOnAMovingRotatingPerturbedMultiblockGrid) { expect_free_stream_preserved(1); }

TEST(GridMotion, FreeStreamIsPreservedOnEveryMultigridLevel) { expect_free_stream_preserved(2); }

TEST(GridMotion, FreeStreamIsPreservedOnADeformingGridAndItsLevels) {
  expect_free_stream_preserved(1, true);
  expect_free_stream_preserved(2, true);
}

}  // namespace
}  // namespace narwhal
