#include "turbulence/launder_sharma.hpp"

#include <algorithm>
#include <cmath>

namespace narwhal {

namespace {
constexpr Real cmu = 0.09, c1 = 1.44, c2 = 1.92, sigk = 1.0, sige = 1.3;
constexpr Real kFloor = 1e-20, eFloor = 1e-20;

Real strain2(const Mat3& G) {
  const Mat3 S = 0.5 * (G + G.transpose());
  return 2.0 * S.squaredNorm();
}
Real turbulence_reynolds(Real k, Real e, Real nu) { return k * k / (nu * std::max(e, eFloor)); }
Real f_mu(Real rt) { return std::exp(-3.4 / ((1.0 + rt / 50.0) * (1.0 + rt / 50.0))); }
}  // namespace

TurbState LaunderSharma::freestream(Real nu) const {
  const Real k = 1.5 * settings_.intensity * settings_.intensity;
  return TurbState(k, cmu * k * k / (settings_.freestream_nut_ratio * nu));
}

Real LaunderSharma::nut(const TurbState& phi, const CellFlow& c) const {
  const Real k = std::max(phi[0], 0.0), e = std::max(phi[1], eFloor);
  return cmu * f_mu(turbulence_reynolds(k, e, c.nu)) * k * k / e;
}

TurbState LaunderSharma::cell_aux(const TurbState& phi, const CellFlow& c) const { return TurbState(nut(phi, c), 0.0); }

TurbState LaunderSharma::diffusivity(const TurbState& /*phi*/, Real nu, const TurbState& aux) const {
  return TurbState(nu + aux[0] / sigk, nu + aux[0] / sige);
}

PointSource LaunderSharma::source(const TurbState& phi, const CellFlow& c) const {
  PointSource s;
  const Real k = std::max(phi[0], kFloor), e = std::max(phi[1], eFloor);
  const Real rt = turbulence_reynolds(k, e, c.nu);
  const Real nt = cmu * f_mu(rt) * k * k / e;
  const Real P = nt * strain2(c.grad_u);
  const Real D = 2.0 * c.nu * c.grad_sqrt_phi0.squaredNorm();
  const Real E = 2.0 * c.nu * nt * c.hessian_u2;
  const Real f2 = 1.0 - 0.3 * std::exp(-std::min(rt * rt, 50.0));
  s.value[0] = P - e - D;
  s.value[1] = c1 * e / k * P - c2 * f2 * e * e / k + E;
  s.implicit[0] = (e + D) / k;
  s.implicit[1] = 2.0 * c2 * f2 * e / k;
  return s;
}

}  // namespace narwhal
