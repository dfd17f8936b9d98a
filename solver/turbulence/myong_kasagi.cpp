#include "turbulence/myong_kasagi.hpp"

#include <algorithm>
#include <cmath>

namespace narwhal {

namespace {
constexpr Real cmu = 0.09, c1 = 1.4, c2 = 1.8, sigk = 1.4, sige = 1.3;
constexpr Real kFloor = 1e-20, eFloor = 1e-20;

Real yplus(const CellFlow& c) { return std::isfinite(c.d) ? c.u_tau * c.d / c.nu : 1e300; }
Real turbulence_reynolds(Real k, Real e, Real nu) { return std::max(k * k / (nu * std::max(e, eFloor)), 1e-12); }
Real f_mu(Real rt, Real yp) { return -std::expm1(-yp / 70.0) * (1.0 + 3.45 / std::sqrt(rt)); }
Real f_2(Real rt, Real yp) {
  const Real damp = -std::expm1(-yp / 5.0);
  return (1.0 - 2.0 / 9.0 * std::exp(-std::min(rt * rt / 36.0, 700.0))) * damp * damp;
}
}  // namespace

TurbState MyongKasagi::freestream(Real nu) const {
  const Real k = 1.5 * settings_.intensity * settings_.intensity;
  return TurbState(k, cmu * k * k / (settings_.freestream_nut_ratio * nu));
}

TurbState MyongKasagi::wall_value(Real nu, Real d1, const TurbState& phi1) const {
  return TurbState(0.0, 2.0 * nu * std::max(phi1[0], 0.0) / (d1 * d1));
}

Real MyongKasagi::nut(const TurbState& phi, const CellFlow& c) const {
  const Real k = std::max(phi[0], 0.0), e = std::max(phi[1], eFloor);
  return cmu * f_mu(turbulence_reynolds(k, e, c.nu), yplus(c)) * k * k / e;
}

TurbState MyongKasagi::cell_aux(const TurbState& phi, const CellFlow& c) const { return TurbState(nut(phi, c), 0.0); }

TurbState MyongKasagi::diffusivity(const TurbState& /*phi*/, Real nu, const TurbState& aux) const {
  return TurbState(nu + aux[0] / sigk, nu + aux[0] / sige);
}

Real MyongKasagi::production(const TurbState& /*phi*/, const CellFlow& c, Real nu_t) const {
  const Mat3 S = 0.5 * (c.grad_u + c.grad_u.transpose());
  return nu_t * 2.0 * S.squaredNorm();
}

PointSource MyongKasagi::source(const TurbState& phi, const CellFlow& c) const {
  PointSource s;
  const Real k = std::max(phi[0], kFloor), e = std::max(phi[1], eFloor);
  const Real rt = turbulence_reynolds(k, e, c.nu), yp = yplus(c);
  const Real P = production(phi, c, cmu * f_mu(rt, yp) * k * k / e);
  const Real f2 = f_2(rt, yp);
  s.value[0] = P - e;
  s.value[1] = c1 * e / k * P - c2 * f2 * e * e / k;
  s.implicit[0] = e / k;
  s.implicit[1] = 2.0 * c2 * f2 * e / k;
  return s;
}

}  // namespace narwhal
