// Boundary conditions (NUMERICS §5): ghost values of every patch type, and global
// conservation: the sum of all cell residuals equals the sum of the physical
// boundary fluxes (interface fluxes cancel between blocks).
#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

#include "mesh/ghost_sweep.hpp"
#include "physics/residual.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

constexpr Real kBeta = 5.0;

// A 4x4x4 box whose imin side carries `bc`; the other sides are symmetry planes.
struct BoxCase {
  Grid g;
  FlowField f;
  FlowParams fp;
};

BoxCase box_with(const PatchBc& bc, std::uint64_t seed) {
  BoxCase c;
  Block b = make_perturbed_box("b", 4, 0.03);
  c.g.blocks.push_back(b);
  assign_bc(c.g, "imin", bc);
  for (auto s : {"imax", "jmin", "jmax", "kmin", "kmax"}) assign_bc(c.g, s, {BcType::Symmetry});
  finalize_grid(c.g);
  c.fp.beta = kBeta;
  c.fp.reynolds = 50.0;
  c.fp.exact = [](const Vec3& x) { return State(x[0], 1.0 + x[1], x[2] * x[0], -0.5 * x[1]); };
  State init = State::Zero();
  c.f.allocate(c.g, c.fp, init);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> U(-1.0, 1.0);
  const Block& B = c.g.blocks[0];
  for (int k = 0; k < B.nk; ++k)
    for (int j = 0; j < B.nj; ++j)
      for (int i = 0; i < B.ni; ++i) c.f.Q[0](i, j, k) = State(0.2 * U(rng), 1.0 + 0.3 * U(rng), 0.3 * U(rng), 0.3 * U(rng));
  fill_ghosts(c.g, c.f, c.fp);
  return c;
}

template <class F>
void for_imin_faces(const Block& b, F&& f) {
  for (int k = 0; k < b.nk; ++k)
    for (int j = 0; j < b.nj; ++j) f(Index3{0, j, k});
}

TEST(BoundaryGhosts, NoSlipWallReflectsVelocityAboutTheWallSpeed) {
  const Vec3 uw(0.4, 0.0, -0.1);
  auto c = box_with({BcType::Wall, uw, 0.0}, 1);
  const auto& Q = c.f.Q[0];
  for_imin_faces(c.g.blocks[0], [&](Index3 f) {
    for (int m = 1; m <= 2; ++m) {
      const State qi = Q(m - 1, f[1], f[2]), qg = Q(-m, f[1], f[2]);
      EXPECT_NEAR(qg[0], qi[0], 1e-15);
      EXPECT_LT((qg.tail<3>() - (2.0 * uw - qi.tail<3>())).norm(), 1e-15);
    }
  });
}

TEST(BoundaryGhosts, SymmetryMirrorsTheVelocity) {
  auto c = box_with({BcType::Symmetry}, 2);
  const Block& b = c.g.blocks[0];
  const auto& Q = c.f.Q[0];
  for_imin_faces(b, [&](Index3 f) {
    const Vec3 n = b.S[0](0, f[1], f[2]).normalized();
    for (int m = 1; m <= 2; ++m) {
      const State qi = Q(m - 1, f[1], f[2]), qg = Q(-m, f[1], f[2]);
      EXPECT_NEAR(qg[0], qi[0], 1e-15);
      EXPECT_NEAR(n.dot(qg.tail<3>()), -n.dot(qi.tail<3>()), 1e-14);
      EXPECT_LT(((qg.tail<3>() - n * n.dot(qg.tail<3>())) - (qi.tail<3>() - n * n.dot(qi.tail<3>()))).norm(), 1e-14);
    }
  });
}

// Characteristic amplitudes l_pm . Q with the outward normal (§3.4).
State acoustic_amplitudes(const State& qbar, const State& q, const FaceGeom& o) {
  const auto a = acoustic_data(qbar[1], qbar[2], qbar[3], o, kBeta);
  State r;
  r[0] = (a.S2 * q[0] + a.lp * o.S.dot(q.tail<3>())) / a.Np;
  r[1] = (a.S2 * q[0] + a.lm * o.S.dot(q.tail<3>())) / a.Nm;
  r[2] = a.theta;
  r[3] = 0;
  return r;
}

TEST(BoundaryGhosts, FarfieldTakesOutgoingWavesFromInsideAndIncomingFromFreeStream) {
  for (Real ux : {1.0, -1.0}) {  // imin side: ux > 0 is inflow, ux < 0 outflow
    const Vec3 uinf(ux, 0.1, 0.0);
    auto c = box_with({BcType::Farfield, uinf, 0.0}, 3);
    const Block& b = c.g.blocks[0];
    const auto& Q = c.f.Q[0];
    for_imin_faces(b, [&](Index3 f) {
      const FaceGeom o = outward_face(b, 0, f);
      const State q1 = Q(0, f[1], f[2]);
      const State qb = 0.5 * (Q(-1, f[1], f[2]) + q1);  // ghost = 2 Q_b - Q_1
      const State qinf(0.0, uinf[0], uinf[1], uinf[2]);
      const State a_b = acoustic_amplitudes(q1, qb, o), a_1 = acoustic_amplitudes(q1, q1, o),
                  a_inf = acoustic_amplitudes(q1, qinf, o);
      EXPECT_NEAR(a_b[0], a_1[0], 1e-12);    // lambda_+ > 0: outgoing, from the interior
      EXPECT_NEAR(a_b[1], a_inf[1], 1e-12);  // lambda_- < 0: incoming, from the free stream
      // The double theta wave (P0 component): from the interior on outflow (theta > 0
      // w.r.t. the outward normal), from the free stream on inflow.
      const auto P = acoustic_projectors(q1, o, kBeta);
      const Mat4 P0 = Mat4::Identity() - P.Pp - P.Pm;
      const State want = P.theta > 0 ? State(P0 * q1) : State(P0 * qinf);
      EXPECT_LT((P0 * qb - want).norm(), 1e-12);
    });
  }
}

TEST(BoundaryGhosts, InflowFixesVelocityAndKeepsTheOutgoingCharacteristic) {
  const Vec3 uin(1.0, 0.2, -0.1);
  auto c = box_with({BcType::Inflow, uin, 0.0}, 4);
  const Block& b = c.g.blocks[0];
  for_imin_faces(b, [&](Index3 f) {
    const FaceGeom o = outward_face(b, 0, f);
    const State q1 = c.f.Q[0](0, f[1], f[2]);
    const State qb = 0.5 * (c.f.Q[0](-1, f[1], f[2]) + q1);
    EXPECT_LT((qb.tail<3>() - uin).norm(), 1e-14);
    EXPECT_NEAR(acoustic_amplitudes(q1, qb - q1, o)[0], 0.0, 1e-12);  // l_+ (Q_b - Q_1) = 0
  });
}

TEST(BoundaryGhosts, OutflowFixesPressureAndChangesOnlyTheIncomingWave) {
  auto c = box_with({BcType::Outflow, Vec3::Zero(), 0.25}, 5);
  const Block& b = c.g.blocks[0];
  for_imin_faces(b, [&](Index3 f) {
    const FaceGeom o = outward_face(b, 0, f);
    const State q1 = c.f.Q[0](0, f[1], f[2]);
    const State qb = 0.5 * (c.f.Q[0](-1, f[1], f[2]) + q1);
    EXPECT_NEAR(qb[0], 0.25, 1e-14);
    const auto a = acoustic_data(q1[1], q1[2], q1[3], o, kBeta);
    State rm;
    rm << kBeta * (a.lm - a.theta), kBeta * o.S + a.lm * q1.tail<3>();
    const State d = qb - q1;
    EXPECT_LT((d - rm * (d[0] / rm[0])).norm(), 1e-13);  // Q_b - Q_1 parallel to r_-
  });
}

TEST(BoundaryGhosts, DirichletGhostsHoldTheExactSolutionAtGhostCentres) {
  auto c = box_with({BcType::Dirichlet}, 6);
  const Block& b = c.g.blocks[0];
  for_imin_faces(b, [&](Index3 f) {
    for (int m = 1; m <= 2; ++m)
      EXPECT_LT((c.f.Q[0](-m, f[1], f[2]) - c.fp.exact(b.xc(-m, f[1], f[2]))).norm(), 1e-15);
  });
}

TEST(BoundaryGhosts, InterfaceAndPeriodicGhostsCopyTheDonorCells) {
  // Periodic in i on one block; then a rotated 4-block split with interfaces.
  Grid g;
  g.blocks.push_back(make_box("b", uniform_nodes(0, 1, 4), uniform_nodes(0, 1, 3), uniform_nodes(0, 1, 2)));
  for (auto s : {"jmin", "jmax", "kmin", "kmax"}) assign_bc(g, s, {BcType::Symmetry});
  connect_periodic(g, "imin", "imax", Mat3::Identity(), std::nullopt);
  finalize_grid(g);
  FlowParams fp;
  FlowField f;
  f.allocate(g, fp, State::Zero());
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) f.Q[0](i, j, k) = State(i, j, k, i * j + k);
  fill_ghosts(g, f, fp);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(f.Q[0](-1, j, k), f.Q[0](3, j, k));
      EXPECT_EQ(f.Q[0](-2, j, k), f.Q[0](2, j, k));
      EXPECT_EQ(f.Q[0](4, j, k), f.Q[0](0, j, k));
      EXPECT_EQ(f.Q[0](5, j, k), f.Q[0](1, j, k));
    }
  // Ghost-node geometry of the periodic pair is the translated donor.
  EXPECT_NEAR(g.blocks[0].xc(-1, 1, 1).x(), -0.125, 1e-15);
}

TEST(BoundaryGhosts, RotationalPeriodicGhostsAreTheRotatedDonor) {
  // A 30-degree sector of an annulus about the x axis; solid-body swirl is
  // rotationally periodic, so every ghost must equal the field at its centre.
  const Real angle = 30.0 * M_PI / 180.0;
  const int nr = 3, nt = 4, nx = 2;
  Block b("sector", nx, nr, nt);
  for (int k = 0; k <= nt; ++k)
    for (int j = 0; j <= nr; ++j)
      for (int i = 0; i <= nx; ++i) {
        const Real r = 1.0 + Real(j) / nr, th = angle * k / nt;
        b.x(i, j, k) = Vec3(Real(i) / nx, r * std::cos(th), r * std::sin(th));
      }
  for (int s2 = 0; s2 < 6; ++s2) {
    Patch p;
    p.side = s2;
    p.hi = b.dims();
    p.label = side_name(s2);
    b.patches.push_back(p);
  }
  Grid g;
  g.blocks.push_back(b);
  for (auto s2 : {"imin", "imax", "jmin", "jmax"}) assign_bc(g, s2, {BcType::Symmetry});
  const Mat3 R = Eigen::AngleAxisd(angle, Vec3::UnitX()).toRotationMatrix();
  connect_periodic(g, "kmax", "kmin", R, Vec3::Zero());
  finalize_grid(g);
  auto swirl = [](const Vec3& x) { return State(0.1 * x[0], 0.3, -0.7 * x[2], 0.7 * x[1]); };
  FlowParams fp;
  FlowField f;
  f.allocate(g, fp, State::Zero());
  const Block& B = g.blocks[0];
  for (int k = 0; k < nt; ++k)
    for (int j = 0; j < nr; ++j)
      for (int i = 0; i < nx; ++i) f.Q[0](i, j, k) = swirl(B.xc(i, j, k));
  fill_ghosts(g, f, fp);
  for (int j = 0; j < nr; ++j)
    for (int i = 0; i < nx; ++i)
      for (int k : {-2, -1, nt, nt + 1}) {
        EXPECT_LT((f.Q[0](i, j, k) - swirl(B.xc(i, j, k))).norm(), 1e-13) << i << " " << j << " " << k;
        EXPECT_GT(B.vol(i, j, k), 0.0);
      }
}

TEST(Conservation, CellResidualsSumToTheBoundaryFluxes) {
  Grid single;
  single.blocks.push_back(make_perturbed_box("b", 8, 0.04));
  randomly_perturb(single.blocks[0], 0.15, 5, false);
  Grid g = split_blocks(single, {2, 2, 1}, true);
  assign_bc(g, "imin", {BcType::Farfield, Vec3(1, 0, 0), 0.0});
  assign_bc(g, "imax", {BcType::Outflow, Vec3::Zero(), 0.1});
  assign_bc(g, "jmin", {BcType::Wall, Vec3(0.2, 0, 0), 0.0});
  assign_bc(g, "jmax", {BcType::Inflow, Vec3(1, 0.1, 0), 0.0});
  assign_bc(g, "kmin", {BcType::Symmetry});
  assign_bc(g, "kmax", {BcType::Symmetry});
  finalize_grid(g);
  FlowParams fp;
  fp.reynolds = 20.0;
  FlowField f;
  f.allocate(g, fp, State::Zero());
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<Real> U(-1.0, 1.0);
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for (auto& q : f.Q[ib].raw()) q = State(0.1 * U(rng), 1.0 + 0.2 * U(rng), 0.2 * U(rng), 0.2 * U(rng));
  fill_ghosts(g, f, fp);
  std::vector<GhostArray<State>> R;
  compute_residual(g, f, fp, R);
  State sum_cells = State::Zero(), sum_boundary = State::Zero(), scale = State::Zero();
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i) sum_cells += R[ib](i, j, k);
    for (const Patch& p : b.patches) {
      if (p.type == BcType::Interface) continue;
      const PatchRange r = face_range(p);
      for_each_in(r, [&](Index3 c) {
        const State F = boundary_face_flux(b, p, f.Q[ib], f.nu[ib], c, fp);
        sum_boundary += side_high(p.side) ? F : State(-F);
        scale += F.cwiseAbs();
      });
    }
  }
  for (int m = 0; m < kNumEq; ++m) EXPECT_LT(std::abs(sum_cells[m] - sum_boundary[m]), 1e-13 * scale[m]) << m;
}

}  // namespace
}  // namespace narwhal
