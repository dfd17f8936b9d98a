#include "bc/boundary.hpp"

#include "mesh/ghost_sweep.hpp"
#include "parallel/halo.hpp"

namespace narwhal {

Index3 boundary_face_index(const Block& b, int side, Index3 c) {
  const int d = side_dir(side);
  c[d] = side_high(side) ? b.n(d) : 0;
  return c;
}

FaceGeom outward_face(const Block& b, int side, const Index3& c) {
  const int d = side_dir(side);
  const Index3 f = boundary_face_index(b, side, c);
  const Real s = side_high(side) ? 1.0 : -1.0;
  return FaceGeom{s * b.S[d](f), s * b.kt[d](f)};
}

State boundary_state(const Patch& p, const State& q1, const FaceGeom& o, const Vec3& xface, const FlowParams& fp) {
  const Real beta = fp.beta;
  switch (p.type) {
    case BcType::Farfield: {
      // §5.2: outgoing characteristics from the interior, incoming from the free stream.
      State qinf;
      qinf << 0.0, p.velocity;
      const auto P = acoustic_projectors(q1, o, beta);
      Mat4 Pout = P.Pp;
      if (P.theta > 0.0) Pout += Mat4::Identity() - P.Pp - P.Pm;
      return qinf + Pout * (q1 - qinf);
    }
    case BcType::Inflow: {
      // §5.3: velocity prescribed; l_+ (Q_b - Q_1) = 0 fixes the pressure.
      const auto a = acoustic_data(q1[1], q1[2], q1[3], o, beta);
      State qb;
      qb[0] = q1[0] - a.lp * o.S.dot(p.velocity - q1.tail<3>()) / a.S2;
      qb.tail<3>() = p.velocity;
      return qb;
    }
    case BcType::Outflow: {
      // §5.3: pressure prescribed; only the incoming r_- component changes.
      const auto a = acoustic_data(q1[1], q1[2], q1[3], o, beta);
      const Real gamma = (p.pressure - q1[0]) / (beta * (a.lm - a.theta));
      State qb;
      qb[0] = p.pressure;
      qb.tail<3>() = q1.tail<3>() + gamma * (beta * o.S + a.lm * q1.tail<3>());
      return qb;
    }
    case BcType::Dirichlet:
      return fp.exact(xface);
    default:
      return q1;
  }
}

Vec3 wall_velocity(const Block& b, const Patch& p, const Index3& f) {
  if (!b.motion.moving) return p.velocity;
  const int d = side_dir(p.side);
  const Vec3& S = b.S[d](f);
  const Vec3 u = p.velocity + b.motion.at(b.xf[d](f));
  return u - ((S.dot(u) + b.kt[d](f)) / S.squaredNorm()) * S;
}

State ghost_value(const Patch& p, const State& qm, const State& qb, const Vec3& n, const Vec3& u_wall) {
  State g = qm;
  switch (p.type) {
    case BcType::Wall:  // §5.1: u_g = 2 u_w - u_m, p_g = p_m
      g.tail<3>() = 2.0 * u_wall - qm.tail<3>();
      break;
    case BcType::Symmetry:  // §5.4: mirror the velocity relative to the plane's, even pressure
      g.tail<3>() = qm.tail<3>() - 2.0 * n.dot(qm.tail<3>() - u_wall) * n;
      break;
    default:
      if (is_state_bc(p.type)) g = 2.0 * qb - qm;
      break;
  }
  return g;
}

State wall_flux(const Vec3& u_wall, const State& q1, const FaceGeom& face, bool high_side, Real d_wall, Real nu_wall,
                Real beta) {
  // §5.1 with §4.5: n points into the fluid; S.u_w := -k_t keeps theta_w = 0 (GCL).
  const Real Snorm = face.S.norm();
  const Real Sn = high_side ? -Snorm : Snorm;  // S . n_into_fluid
  State F;
  F[0] = -beta * face.kt;
  F.tail<3>() = q1[0] * face.S - (nu_wall * Sn / d_wall) * (q1.tail<3>() - u_wall);
  return F;
}

void fill_ghosts(Grid& g, FlowField& f, const FlowParams& fp) {
  auto physical = [&](int ib, const Patch& p, int m) {
    const Block& b = g.blocks[ib];
    auto& Q = f.Q[ib];
    auto& nu = f.nu[ib];
    const PatchRange r = extended_cell_range(b, p);
    const int d = side_dir(p.side);
    if (d == b.invariant_dir) {  // the mirror of an in-plane state is the state itself (physics/invariant_direction.hpp)
      for_each_in(r, [&](Index3 c) {
        Q(ghost_cell(b, p.side, c, m)) = Q(interior_cell(b, p.side, c, m));
        nu(ghost_cell(b, p.side, c, m)) = nu(interior_cell(b, p.side, c, m));
      });
      return;
    }
    const bool characteristic = is_characteristic_bc(p.type);
    for_each_in(r, [&](Index3 c) {
      // Normals only where the BC uses them (symmetry, characteristic states).
      const FaceGeom o = (characteristic || p.type == BcType::Symmetry) ? outward_face(b, p.side, c) : FaceGeom{};
      const Vec3 n = p.type == BcType::Symmetry ? Vec3(o.S.normalized()) : Vec3::Zero();
      const Index3 c1 = interior_cell(b, p.side, c, 1);
      State qb = Q(c1);
      if (characteristic) qb = boundary_state(p, Q(c1), o, b.xf[d](boundary_face_index(b, p.side, c)), fp);
      const Index3 cm = interior_cell(b, p.side, c, m);
      const Index3 gc = ghost_cell(b, p.side, c, m);
      // Dirichlet (verification) ghosts take the exact solution at the ghost
      // centre: the extrapolated 2 Q_b - Q_m would make the boundary viscous
      // gradient one-sided and cost accuracy in the boundary cells.
      // A slip wall (a body's surface) moving with the grid: its normal speed -k_t,o / |S|
      // (§2.4). A symmetry plane stays a mirror of the absolute velocity.
      const bool moving_slip_wall = p.type == BcType::Symmetry && p.body_surface && b.motion.moving;
      const Vec3 u_wall = p.type == BcType::Wall ? wall_velocity(b, p, boundary_face_index(b, p.side, c))
                          : moving_slip_wall     ? Vec3((-o.kt / o.S.norm()) * n)
                                                 : Vec3::Zero();
      Q(gc) = p.type == BcType::Dirichlet ? fp.exact(b.xc(gc)) : ghost_value(p, Q(cm), qb, n, u_wall);
      nu(gc) = nu(cm);
    });
  };
  owned_ghost_sweep(g, physical, [&](const ExchangePlan& plan) {
    exchange(g, plan, f.Q, RotateVelocity{});
    exchange(g, plan, f.nu, Unrotated{});
  });
  if (!f.tau_nl.empty()) fill_tensor_ghosts(g, f.tau_nl);
}

void fill_tensor_ghosts(const Grid& g, std::vector<GhostArray<Mat3>>& T) {
  // A Cartesian tensor: interfaces rotate it with the velocity's R (R T R^T),
  // symmetry planes mirror it (M T M, M = I - 2 n n^T), every other boundary copies
  // the interior (walls do not use it: their flux is §4.5's, and tau_NL = 0 there).
  auto physical = [&](int ib, const Patch& p, int m) {
    const Block& b = g.blocks[ib];
    auto& Tb = T[ib];
    const PatchRange r = extended_cell_range(b, p);
    const bool mirror = p.type == BcType::Symmetry && side_dir(p.side) != b.invariant_dir;
    for_each_in(r, [&](Index3 c) {
      const Mat3& Tm = Tb(interior_cell(b, p.side, c, m));
      if (mirror) {
        const Vec3 n = outward_face(b, p.side, c).S.normalized();
        const Mat3 M = Mat3::Identity() - 2.0 * n * n.transpose();
        Tb(ghost_cell(b, p.side, c, m)) = M * Tm * M;
      } else {
        Tb(ghost_cell(b, p.side, c, m)) = Tm;
      }
    });
  };
  owned_ghost_sweep(g, physical, [&](const ExchangePlan& plan) { exchange(g, plan, T, RotateTensor{}); });
}

void exchange_interfaces(const Grid& g, std::vector<GhostArray<State>>& field) {
  if (!g.interfaces.empty()) exchange(g, halo_plans(g).faces, field, RotateVelocity{});
}

}  // namespace narwhal
