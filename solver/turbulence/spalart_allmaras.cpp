#include "turbulence/spalart_allmaras.hpp"

#include <algorithm>
#include <cmath>

#include "turbulence/flow_gradients.hpp"

namespace narwhal {

namespace {
constexpr Real cb1 = 0.1355, sigma = 2.0 / 3.0, cb2 = 0.622, kappa = 0.41, cw2 = 0.3, cw3 = 2.0, cv1 = 7.1,
               ct3 = 1.2, ct4 = 0.5, cv2 = 0.7, cv3 = 0.9, cn1 = 16.0;
constexpr Real cw1 = cb1 / (kappa * kappa) + (1.0 + cb2) / sigma;
}  // namespace

TurbState SpalartAllmaras::freestream(Real nu) const {
  return TurbState(settings_.freestream_nut_ratio * nu, 0.0);
}

TurbState SpalartAllmaras::diffusivity(const TurbState& phi, Real nu, const TurbState&) const {
  const Real nt = phi[0];
  if (nt >= 0.0) return TurbState((nu + nt) / sigma, 0.0);
  const Real chi3 = std::pow(nt / nu, 3);
  return TurbState((nu + nt * (cn1 + chi3) / (cn1 - chi3)) / sigma, 0.0);
}

TransportModel::FaceDiffusivity SpalartAllmaras::face_diffusivity(const TurbState& phiL, const TurbState& phiR,
                                                                  Real nu, const TurbState& auxL,
                                                                  const TurbState& auxR) const {
  // (1 + cb2) times the face coefficient minus cb2 times each cell's own (SA-neg's
  // f_n form below zero through `diffusivity`).
  const TurbState dL = diffusivity(phiL, nu, auxL), dR = diffusivity(phiR, nu, auxR);
  const TurbState face = 0.5 * (dL + dR);
  return {(1.0 + cb2) * face - cb2 * dL, (1.0 + cb2) * face - cb2 * dR};
}

Real SpalartAllmaras::nut(const TurbState& phi, const CellFlow& c) const {
  const Real nt = phi[0];
  if (nt <= 0.0) return 0.0;
  const Real chi3 = std::pow(nt / c.nu, 3);
  return nt * chi3 / (chi3 + cv1 * cv1 * cv1);
}

PointSource SpalartAllmaras::source(const TurbState& phi, const CellFlow& c) const {
  PointSource s;
  const Real nt = phi[0];
  const Real omega = vorticity_magnitude(c.grad_u);
  const Real d = std::isfinite(c.d) ? c.d : 1e150;  // no wall: no destruction
  const Real d2 = d * d;
  if (nt < 0.0) {
    const Real prod = cb1 * (1.0 - ct3) * omega * nt;  // < 0
    const Real dest = -cw1 * nt * nt / d2;
    s.value[0] = prod - dest;
    s.implicit[0] = -cb1 * (1.0 - ct3) * omega - 2.0 * cw1 * nt / d2;  // -dS/dnu~ >= 0
    return s;
  }
  const Real chi = nt / c.nu;
  const Real chi3 = chi * chi * chi;
  const Real fv1 = chi3 / (chi3 + cv1 * cv1 * cv1);
  const Real fv2 = 1.0 - chi / (1.0 + chi * fv1);
  const Real ft2 = ct3 * std::exp(-ct4 * chi * chi);
  const Real k2d2 = kappa * kappa * d2;
  const Real sbar = nt * fv2 / k2d2;
  const Real stilde = sbar >= -cv2 * omega
                          ? omega + sbar
                          : omega + omega * (cv2 * cv2 * omega + cv3 * sbar) / ((cv3 - 2.0 * cv2) * omega - sbar);
  const Real r = stilde > 0.0 ? std::min(nt / (stilde * k2d2), 10.0) : 10.0;
  const Real g = r + cw2 * (std::pow(r, 6) - r);
  const Real cw36 = std::pow(cw3, 6);
  const Real fw = g * std::pow((1.0 + cw36) / (std::pow(g, 6) + cw36), 1.0 / 6.0);
  const Real dest_coeff = cw1 * fw - cb1 / (kappa * kappa) * ft2;
  s.value[0] = cb1 * (1.0 - ft2) * stilde * nt - dest_coeff * nt * nt / d2;
  s.implicit[0] = std::max(0.0, 2.0 * dest_coeff * nt / d2);
  return s;
}

}  // namespace narwhal
