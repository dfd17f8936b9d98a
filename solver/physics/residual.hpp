#pragma once
// Spatial residual R_c(Q) = sum_f s_cf [F_f - Fv_f] - V_c S_c (NUMERICS §2.5).
#include <vector>

#include "mesh/block.hpp"
#include "physics/ac_flux.hpp"
#include "physics/flow.hpp"

namespace narwhal {

// §4.1–4.3 viscous face flux [0; tau S] at face index f of direction d.
State viscous_face_flux(const Block& b, const GhostArray<State>& Q, const GhostArray<Real>& nu, int d,
                        const Index3& f, ViscousForm form);

// Thin-layer (Laplacian) viscous coefficient nu_f |S|^2 / V_f of a face (§4.3, §4.4).
Real thin_layer_coefficient(const Block& b, const GhostArray<Real>& nu, int d, const Index3& f);

// Distance from the wall-face centroid to the first cell centre along the normal
// into the fluid (§4.5), and that normal.
Real wall_distance(const Block& b, int side, const Index3& c, Vec3* n_into_fluid = nullptr);

// Second-order (MUSCL) Roe flux of an interior, interface or symmetry face, without
// the viscous part (its first component / beta + k_t is the face volume flux).
State inviscid_face_flux(const Block& b, const GhostArray<State>& Q, int d, const Index3& f, const FlowParams& fp);

// Second-order (MUSCL) flux of an interior, interface or symmetry face.
State muscl_face_flux(const Block& b, const GhostArray<State>& Q, const GhostArray<Real>& nu, int d,
                      const Index3& f, const FlowParams& fp);

// Flux of a boundary face of a physical patch (walls and state BCs override Roe).
State boundary_face_flux(const Block& b, const Patch& p, const GhostArray<State>& Q, const GhostArray<Real>& nu,
                         const Index3& c, const FlowParams& fp);

// Residual of every block (ghosts must be filled). R has no ghost layers.
void compute_residual(const Grid& g, const FlowField& f, const FlowParams& fp, std::vector<GhostArray<State>>& R);

}  // namespace narwhal
