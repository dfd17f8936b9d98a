#pragma once
// Boundary conditions (NUMERICS §5): ghost-cell fill for every patch type and the
// face fluxes that override Roe's flux on walls and characteristic boundaries.
#include "mesh/block.hpp"
#include "physics/ac_flux.hpp"
#include "physics/flow.hpp"

namespace narwhal {

// BCs with a boundary value Q_b (a function of the first interior cell); their
// ghosts are 2 Q_b - Q_m (far field, inflow, outflow, Dirichlet).
inline bool is_state_bc(BcType t) {
  return t == BcType::Farfield || t == BcType::Inflow || t == BcType::Outflow || t == BcType::Dirichlet;
}
// Characteristic BCs replace Roe's flux by F(Q_b) (§5.2–5.3). Dirichlet data
// (§12.2) go through the ghosts and Roe's flux, whose pressure dissipation then
// anchors the pressure level at the boundary.
inline bool is_characteristic_bc(BcType t) {
  return t == BcType::Farfield || t == BcType::Inflow || t == BcType::Outflow;
}

// Outward face geometry (S_o, k_t,o) of boundary face at tangential cell `c` on `side`.
FaceGeom outward_face(const Block& b, int side, const Index3& c);
// Face index (in the face array of the side's direction) of that boundary face.
Index3 boundary_face_index(const Block& b, int side, Index3 c);

// §5.2 / §5.3 / §12.2 boundary state from the first interior cell.
State boundary_state(const Patch& p, const State& q1, const FaceGeom& outward, const Vec3& xface,
                     const FlowParams& fp);

// §5.1: the velocity of a wall at its boundary face f (direction of the patch's side):
// the patch's own (a sliding lid), plus on a moving grid the grid's rigid velocity at
// the face centroid with its normal component replaced by S . u_w = -k_t, so that the
// relative volume flux through the wall is exactly zero (GCL).
Vec3 wall_velocity(const Block& b, const Patch& p, const Index3& f);

// Ghost values of depth m for a non-interface patch, from interior Q_m (and Q_b / n);
// u_wall: a wall's velocity (wall_velocity); for a slip wall, the velocity it moves
// with along its normal (the mirror is taken relative to it, so that a moving slip wall
// lets no fluid through; a symmetry plane's is zero).
State ghost_value(const Patch& p, const State& qm, const State& qb, const Vec3& unit_normal,
                  const Vec3& u_wall = Vec3::Zero());

// §5.1 wall flux in the block's face orientation (S as stored), wall velocity u_wall.
State wall_flux(const Vec3& u_wall, const State& q1, const FaceGeom& face, bool high_side, Real d_wall, Real nu_wall,
                Real beta);

// Fill both ghost layers of Q (and nu) on every block: interfaces copy donors,
// physical patches apply their BC. Edge/corner ghosts included (ghost_sweep).
void fill_ghosts(Grid& g, FlowField& f, const FlowParams& fp);

// Ghosts of a per-cell Cartesian tensor field (the non-linear Reynolds stress).
void fill_tensor_ghosts(const Grid& g, std::vector<GhostArray<Mat3>>& T);

// Copy donor values into interface ghosts of any state-like field (velocity rotated).
void exchange_interfaces(const Grid& g, std::vector<GhostArray<State>>& field);

}  // namespace narwhal
