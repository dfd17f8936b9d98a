#include "physics/residual.hpp"

#include "bc/boundary.hpp"
#include "mesh/ghost_sweep.hpp"

namespace narwhal {

namespace {

// §4.1: the non-linear Reynolds stress's share of the viscous flux, tau_NL_f S_f with
// the face average of the cell values, explicit. Wall faces carry none (k = 0 there).
void add_nonlinear_stress_flux(const Block& b, const GhostArray<Mat3>& T, GhostArray<State>& Rb) {
  auto flux = [&](int d, const Index3& f) { return Vec3(0.5 * (T(add(f, unit(d), -1)) + T(f)) * b.S[d](f)); };
  for (int d = 0; d < 3; ++d) {
    if (d == b.invariant_dir) continue;  // its two faces cancel (physics/invariant_direction.hpp)
    for_each_interior_face(b, d, [&](const Index3& f) {
      const Vec3 F = flux(d, f);
      Rb(add(f, unit(d), -1)).tail<3>() -= F;
      Rb(f).tail<3>() += F;
    });
  }
  for (const Patch& p : b.patches) {
    if (p.type == BcType::Wall || side_dir(p.side) == b.invariant_dir) continue;
    const int d = side_dir(p.side);
    for_each_in(face_range(p), [&](Index3 c) {
      const Vec3 F = flux(d, boundary_face_index(b, p.side, c));
      const Index3 c1 = interior_cell(b, p.side, c, 1);
      if (side_high(p.side))
        Rb(c1).tail<3>() -= F;
      else
        Rb(c1).tail<3>() += F;
    });
  }
}

}  // namespace

Real thin_layer_coefficient(const Block& b, const GhostArray<Real>& nu, int d, const Index3& f) {
  const Index3 cR = f, cL = add(f, unit(d), -1);
  const Real Vf = 0.5 * (b.vol(cL) + b.vol(cR));
  const Real nuf = 0.5 * (nu(cL) + nu(cR));
  return nuf * b.S[d](f).squaredNorm() / Vf;
}

State viscous_face_flux(const Block& b, const GhostArray<State>& Q, const GhostArray<Real>& nu, int d,
                        const Index3& f, ViscousForm form) {
  State Fv = State::Zero();
  if (form == ViscousForm::Inviscid) return Fv;
  const Index3 e = unit(d);
  const Index3 cR = f, cL = add(f, e, -1);
  if (form == ViscousForm::ThinLayer) {
    Fv.tail<3>() = thin_layer_coefficient(b, nu, d, f) * (Q(cR).tail<3>() - Q(cL).tail<3>());
    return Fv;
  }
  // §4.2: grad u at the face by the chain rule in computational space,
  //   G = (du_n S^T + du_t1 Sbar_t1^T + du_t2 Sbar_t2^T) / V_f,
  // and tau S = nu (G + G^T) S expanded into dot products (no 3x3 tensors).
  const Vec3& S = b.S[d](f);
  const Real Vf = 0.5 * (b.vol(cL) + b.vol(cR));
  const Vec3 dun = Q(cR).tail<3>() - Q(cL).tail<3>();
  Vec3 GS = dun * S.squaredNorm();
  Vec3 GtS = S * dun.dot(S);
  for (int t : {(d + 1) % 3, (d + 2) % 3}) {
    if (t == b.invariant_dir) continue;  // nothing varies along it: the term is exactly zero (physics/invariant_direction.hpp)
    const Index3 et = unit(t);
    const Vec3 du = 0.25 * (Q(add(cL, et)).tail<3>() + Q(add(cR, et)).tail<3>() - Q(add(cL, et, -1)).tail<3>() -
                            Q(add(cR, et, -1)).tail<3>());
    const Vec3 Sbar = 0.25 * (b.S[t](cL) + b.S[t](add(cL, et)) + b.S[t](cR) + b.S[t](add(cR, et)));
    GS += du * Sbar.dot(S);
    GtS += Sbar * du.dot(S);
  }
  const Real nuf = 0.5 * (nu(cL) + nu(cR));
  Fv.tail<3>() = (nuf / Vf) * (GS + GtS);
  return Fv;
}

Real wall_distance(const Block& b, int side, const Index3& c, Vec3* n_out) {
  const int d = side_dir(side);
  const Index3 f = boundary_face_index(b, side, c);
  Vec3 n = b.S[d](f).normalized();
  if (side_high(side)) n = -n;
  if (n_out) *n_out = n;
  return n.dot(b.xc(interior_cell(b, side, c, 1)) - b.xf[d](f));
}

State inviscid_face_flux(const Block& b, const GhostArray<State>& Q, int d, const Index3& f, const FlowParams& fp) {
  const Index3 e = unit(d);
  const Index3 cR = f, cL = add(f, e, -1);
  const State qL = muscl_left<State>(Q(add(cL, e, -1)), Q(cL), Q(cR), fp.muscl);
  const State qR = muscl_right<State>(Q(cL), Q(cR), Q(add(cR, e)), fp.muscl);
  return roe_flux<Real>(qL, qR, FaceGeom{b.S[d](f), b.kt[d](f)}, fp.beta);
}

State muscl_face_flux(const Block& b, const GhostArray<State>& Q, const GhostArray<Real>& nu, int d,
                      const Index3& f, const FlowParams& fp) {
  return inviscid_face_flux(b, Q, d, f, fp) - viscous_face_flux(b, Q, nu, d, f, fp.viscous);
}

State boundary_face_flux(const Block& b, const Patch& p, const GhostArray<State>& Q, const GhostArray<Real>& nu,
                         const Index3& c, const FlowParams& fp) {
  const int d = side_dir(p.side);
  const Index3 f = boundary_face_index(b, p.side, c);
  const Index3 c1 = interior_cell(b, p.side, c, 1);
  if (p.type == BcType::Wall) {
    return wall_flux(wall_velocity(b, p, f), Q(c1), FaceGeom{b.S[d](f), b.kt[d](f)}, side_high(p.side),
                     wall_distance(b, p.side, c),
                     1.0 / fp.reynolds, fp.beta);
  }
  if (is_characteristic_bc(p.type)) {
    const State qb = boundary_state(p, Q(c1), outward_face(b, p.side, c), b.xf[d](f), fp);
    State F = physical_flux<Real>(qb, FaceGeom{b.S[d](f), b.kt[d](f)}, fp.beta);
    F -= viscous_face_flux(b, Q, nu, d, f, fp.viscous);
    return F;
  }
  return muscl_face_flux(b, Q, nu, d, f, fp);  // symmetry, interface: Roe through the ghosts
}

void compute_residual(const Grid& g, const FlowField& fl, const FlowParams& fp, std::vector<GhostArray<State>>& R) {
  R.resize(g.blocks.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    const auto& Q = fl.Q[ib];
    const auto& nu = fl.nu[ib];
    auto& Rb = R[ib];
    if (Rb.ni() != b.ni || Rb.nj() != b.nj || Rb.nk() != b.nk) Rb.resize(b.ni, b.nj, b.nk, 0);
    Rb.fill(State::Zero());
    for (int d = 0; d < 3; ++d) {
      for_each_interior_face(b, d, [&](const Index3& f) {  // boundary faces come from the patches
        const State F = muscl_face_flux(b, Q, nu, d, f, fp);
        Rb(add(f, unit(d), -1)) += F;
        Rb(f) -= F;
      });
    }
    for (const Patch& p : b.patches) {
      if (side_dir(p.side) == b.invariant_dir) continue;  // the layer's two faces cancel (physics/invariant_direction.hpp)
      const PatchRange r = face_range(p);
      for_each_in(r, [&](Index3 c) {
        const State F = boundary_face_flux(b, p, Q, nu, c, fp);
        const Index3 c1 = interior_cell(b, p.side, c, 1);
        if (side_high(p.side))
          Rb(c1) += F;
        else
          Rb(c1) -= F;
      });
    }
    if (ib < fl.tau_nl.size()) add_nonlinear_stress_flux(b, fl.tau_nl[ib], Rb);
    for (const auto& source : fp.sources) source->add_to_residual(b, Q, Rb);
  }
}

}  // namespace narwhal
