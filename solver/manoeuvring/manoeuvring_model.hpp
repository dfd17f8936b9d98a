#pragma once
// A submarine's hydrodynamic loads as a manoeuvring model (issue 19's cheap simulator,
// `narwhal simulate`): the standard submarine equations' hydrodynamic terms (Gertler &
// Hagen 1967; Feldman 1979), linear derivatives plus cross-flow (v|v|, w|w|) and
// quadratic surge terms, with coefficients measured by the CFD (captive sweeps, rotary
// runs, the self-propulsion point).
//
// Nondimensional as the captive rungs report them: forces on rho/2 L^2 U^2, moments on
// rho/2 L^3 U^2, with velocities on U, rates on U/L and accelerations on U^2/L (U/L^2),
// e.g. Y = rho/2 L^2 (Y'_v u v + Y'_r L u r + Y'_v|v| v |v| + Y'_dr u^2 dr) + rho/2 L^3 Y'_vdot vdot.
// In the flow's units (rho = 1, L = 1) each load is half its sum. Body axes about O
// (marine: x_B forward, y_B starboard, z_B down); deflections in radians with
// suboff_geometry.hpp's signs, so that coefficients measured with them need no change.
#include <string>
#include <vector>

#include "mesh/suboff_geometry.hpp"
#include "motion/rigid_body.hpp"

namespace narwhal {

struct ManoeuvringCoefficients {
  // Surge: X'_uu u^2 (resistance), X'_vv v^2, X'_ww w^2, X'_qq q^2, X'_rr r^2,
  // X'_drdr u^2 dr^2, X'_dsds u^2 ds^2, X'_udot udot.
  Real Xuu = 0, Xvv = 0, Xww = 0, Xqq = 0, Xrr = 0, Xdrdr = 0, Xdsds = 0, Xudot = 0;
  // Sway: Y'_v u v, Y'_r u r, Y'_v|v| v|v|, Y'_dr u^2 dr, Y'_vdot vdot, Y'_rdot rdot.
  Real Yv = 0, Yr = 0, Yvv = 0, Ydr = 0, Yvdot = 0, Yrdot = 0;
  // Heave: Z'_0 u^2 (out of trim at zero incidence: the sail), Z'_w u w, Z'_q u q,
  // Z'_w|w| w|w|, Z'_ds u^2 ds (stern planes), Z'_db u^2 db (sail planes), Z'_wdot, Z'_qdot.
  Real Z0 = 0, Zw = 0, Zq = 0, Zww = 0, Zds = 0, Zdb = 0, Zwdot = 0, Zqdot = 0;
  // Roll: K'_p u p, K'_pdot pdot.
  Real Kp = 0, Kpdot = 0;
  // Pitch: as heave.
  Real M0 = 0, Mw = 0, Mq = 0, Mww = 0, Mds = 0, Mdb = 0, Mwdot = 0, Mqdot = 0;
  // Yaw: as sway.
  Real Nv = 0, Nr = 0, Nvv = 0, Ndr = 0, Nvdot = 0, Nrdot = 0;

  // Every coefficient with its name (the names case files use), for reading and reports.
  std::vector<std::pair<std::string, Real*>> named();
};

// The hydrodynamic loads (flow units, body axes about O) at body velocities nu = (u, v,
// w, p, q, r) through the water and the surfaces' deflections; the acceleration terms
// are not among them (added_mass).
BodyLoads hydrodynamic_loads(const ManoeuvringCoefficients& c, const Vec6& nu, const suboff::Deflections& d);

// The added-mass matrix M_A (flow units) the acceleration derivatives make: the loads
// -M_A (udot ... rdot), so M_A = -1/2 [X'_udot ...] (symmetric off-diagonal pairs
// Y'_rdot / N'_vdot and Z'_qdot / M'_wdot averaged: potential flow's are equal).
Mat6 added_mass(const ManoeuvringCoefficients& c);

}  // namespace narwhal
