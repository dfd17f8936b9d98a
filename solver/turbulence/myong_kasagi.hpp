#pragma once
// Myong–Kasagi low-Reynolds-number k–epsilon model (NUMERICS §8.4; Myong & Kasagi,
// JSME Int. J. Ser. II 33, 1990), the linear base of the paper's nonlinear k–epsilon.
//
// Equations (nondimensional: nu = 1/Re), epsilon the true dissipation:
//   Dk/Dt   = div((nu + nu_t/sigma_k) grad k) + P - eps
//   Deps/Dt = div((nu + nu_t/sigma_e) grad eps) + C1 f1 eps/k P - C2 f2 eps^2/k
//   nu_t = C_mu f_mu k^2/eps,  P = nu_t S^2 (S = sqrt(2 S_ij S_ij)),
//   R_t = k^2/(nu eps) (>= 1e-12), y+ = u_tau d/nu (u_tau of the nearest wall face),
//   f_mu = (1 - exp(-y+/70)) (1 + 3.45/sqrt(R_t)), f1 = 1,
//   f2 = (1 - 2/9 exp(-(R_t/6)^2)) (1 - exp(-y+/5))^2.
// Constants: C_mu 0.09, C1 1.4, C2 1.8, sigma_k 1.4, sigma_e 1.3.
// Wall: k = 0, eps_w = 2 nu k_1/d_1^2 (from eps = 2 nu (d sqrt(k)/dn)^2 with
// sqrt(k) ~ y), through the ghosts -k_1 and 2 eps_w - eps_1. Free stream: k = 1.5 Tu^2,
// eps = C_mu k^2/(ratio nu) (the f_mu -> 1 limit, §8.7).
// Discretization as transport_model.hpp with 2x2 point-implicit sources (the k and
// eps sources only converge together); updates keep k and eps positive.
// Limits: u_tau -> 0 at separation switches the y+ damping off spuriously (§8.4's
// doubt; kept as in the source); no wall functions (wall cells at y+ ~ 1).
#include "turbulence/transport_model.hpp"

namespace narwhal {

class MyongKasagi : public TransportModel {
 public:
  using TransportModel::TransportModel;
  std::string name() const override { return "myong-kasagi"; }
  int num_variables() const override { return 2; }
  std::string variable_name(int m) const override { return m == 0 ? "k" : "epsilon"; }
  std::string cgns_name(int m) const override { return m == 0 ? "TurbulentEnergyKinetic" : "TurbulentDissipation"; }
  PointSource source(const TurbState& phi, const CellFlow& c) const override;
  Real nut(const TurbState& phi, const CellFlow& c) const override;

 protected:
  // Production P_k of the model's stress (the linear one here; §8.5 adds its terms).
  virtual Real production(const TurbState& phi, const CellFlow& c, Real nu_t) const;
  TurbState freestream(Real nu) const override;
  TurbState wall_value(Real nu, Real d1, const TurbState& phi1) const override;
  TurbState cell_aux(const TurbState& phi, const CellFlow& c) const override;
  TurbState diffusivity(const TurbState& phi, Real nu, const TurbState& aux) const override;
  TurbState limit_update(const TurbState& phi, const TurbState& dphi) const override { return keep_positive(phi, dphi); }
  bool needs_friction_velocity() const override { return true; }
  bool coupled_sources() const override { return true; }
};

}  // namespace narwhal
