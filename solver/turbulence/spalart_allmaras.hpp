#pragma once
// Spalart–Allmaras one-equation model, "SA-neg" as on NASA's Turbulence Modeling
// Resource (turbmodels.larc.nasa.gov/spalart.html): the standard SA (with the
// laminar-suppression term f_t2, without the trip term) for nu_tilde >= 0, and the
// negative branch of Allmaras, Johnson & Spalart (ICCFD7-1902, 2012) below zero.
//
// Equation (nondimensional: nu = 1/Re, lengths in L):
//   D nu~/Dt = cb1 (1 - ft2) S~ nu~ - (cw1 fw - cb1/kappa^2 ft2) (nu~/d)^2
//              + (1/sigma) [div((nu + nu~) grad nu~) + cb2 |grad nu~|^2]
//   nu_t = nu~ fv1,  fv1 = chi^3/(chi^3 + cv1^3),  chi = nu~/nu
//   S~ = Omega + S_bar, S_bar = nu~ fv2/(kappa d)^2, fv2 = 1 - chi/(1 + chi fv1),
//        with S_bar < -cv2 Omega replaced by Omega (cv2^2 Omega + cv3 S_bar)/((cv3 - 2 cv2) Omega - S_bar)
//   fw = g [(1 + cw3^6)/(g^6 + cw3^6)]^(1/6), g = r + cw2 (r^6 - r), r = min(nu~/(S~ kappa^2 d^2), 10)
//   ft2 = ct3 exp(-ct4 chi^2)
// nu~ < 0: production cb1 (1 - ct3) Omega nu~, destruction -cw1 (nu~/d)^2, nu_t = 0,
//          diffusion coefficient nu + nu~ fn, fn = (cn1 + chi^3)/(cn1 - chi^3).
// Constants: cb1 0.1355, sigma 2/3, cb2 0.622, kappa 0.41, cw2 0.3, cw3 2, cv1 7.1,
//            ct3 1.2, ct4 0.5, cv2 0.7, cv3 0.9, cn1 16, cw1 = cb1/kappa^2 + (1 + cb2)/sigma.
// Omega is the vorticity magnitude. Wall: nu~ = 0. Free stream: nu~ = 3 nu (TMR),
// set by turbulence.freestream_nut_ratio.
// Discretization (transport_model.hpp): the diffusion terms in the equivalent form
//   (1/sigma) [(1 + cb2) div((nu + nu~) grad nu~) - cb2 (nu + nu~) lap nu~],
// i.e. per face and cell side the coefficient ((1 + cb2)(nu + nu~_f) - cb2 (nu + nu~_cell))/sigma
// (positive for nu~ >= 0), all implicit. An explicit cb2 |grad nu~|^2 source acts as
// explicit diffusion and made the iteration cycle with period 2 at large CFL (measured
// on the coarse TMR plate). The implicit diagonal also carries the destruction
// (fw frozen) and, for nu~ < 0, the negative-branch production.
// Limits: fully turbulent (no trip, no transition); no rotation/curvature correction.
#include "turbulence/transport_model.hpp"

namespace narwhal {

class SpalartAllmaras final : public TransportModel {
 public:
  using TransportModel::TransportModel;
  std::string name() const override { return "sa"; }
  int num_variables() const override { return 1; }
  std::string variable_name(int) const override { return "nu_tilde"; }
  std::string cgns_name(int) const override { return "TurbulentSANuTilde"; }

  // The point source and its implicit coefficient (public for unit tests).
  PointSource source(const TurbState& phi, const CellFlow& c) const override;

 protected:
  TurbState freestream(Real nu) const override;
  TurbState wall_value(Real, Real, const TurbState&) const override { return TurbState::Zero(); }
  TurbState diffusivity(const TurbState& phi, Real nu, const TurbState& aux) const override;
  FaceDiffusivity face_diffusivity(const TurbState& phiL, const TurbState& phiR, Real nu, const TurbState& auxL,
                                   const TurbState& auxR) const override;
  Real nut(const TurbState& phi, const CellFlow& c) const override;
};

}  // namespace narwhal
