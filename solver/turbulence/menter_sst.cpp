#include "turbulence/menter_sst.hpp"

#include <algorithm>
#include <cmath>

namespace narwhal {

namespace {
constexpr Real sk1 = 0.85, sw1 = 0.5, beta1 = 0.075, gamma1 = 5.0 / 9.0;
constexpr Real sk2 = 1.0, sw2 = 0.856, beta2 = 0.0828, gamma2 = 0.44;
constexpr Real betastar = 0.09, a1 = 0.31;
constexpr Real kFloor = 1e-20, wFloor = 1e-20;

Real strain_magnitude(const Mat3& G) {
  const Mat3 S = 0.5 * (G + G.transpose());
  return std::sqrt(2.0 * S.squaredNorm());
}

Real distance(const CellFlow& c) { return std::isfinite(c.d) ? c.d : 1e150; }

// F1 and the cross-diffusion term 2 sigma_w2 grad k . grad omega / omega.
struct Blend {
  Real f1, cross;
};
Blend blend(const TurbState& phi, const CellFlow& c) {
  const Real k = std::max(phi[0], kFloor), w = std::max(phi[1], wFloor), d = distance(c);
  const Real cross = 2.0 * sw2 * c.grad_phi.col(0).dot(c.grad_phi.col(1)) / w;
  const Real cd = std::max(cross, 1e-10);
  const Real arg1 = std::min(std::max(std::sqrt(k) / (betastar * w * d), 500.0 * c.nu / (d * d * w)),
                             4.0 * sw2 * k / (cd * d * d));
  return {std::tanh(std::pow(arg1, 4)), cross};
}

Real f2(const TurbState& phi, const CellFlow& c) {
  const Real k = std::max(phi[0], kFloor), w = std::max(phi[1], wFloor), d = distance(c);
  const Real arg2 = std::max(2.0 * std::sqrt(k) / (betastar * w * d), 500.0 * c.nu / (d * d * w));
  return std::tanh(arg2 * arg2);
}
}  // namespace

TurbState MenterSst::freestream(Real nu) const {
  const Real k = 1.5 * settings_.intensity * settings_.intensity;
  return TurbState(k, k / (settings_.freestream_nut_ratio * nu));
}

TurbState MenterSst::wall_value(Real nu, Real d1, const TurbState& /*phi1*/) const {
  const Real dy1 = dy1_per_d1_ * d1;
  return TurbState(0.0, 60.0 * nu / (beta1 * dy1 * dy1));
}

Real MenterSst::nut(const TurbState& phi, const CellFlow& c) const {
  const Real k = std::max(phi[0], 0.0), w = std::max(phi[1], wFloor);
  return a1 * k / std::max(a1 * w, strain_magnitude(c.grad_u) * f2(phi, c));
}

TurbState MenterSst::cell_aux(const TurbState& phi, const CellFlow& c) const {
  return TurbState(blend(phi, c).f1, nut(phi, c));
}

TurbState MenterSst::diffusivity(const TurbState& /*phi*/, Real nu, const TurbState& aux) const {
  const Real F1 = aux[0], nt = aux[1];
  return TurbState(nu + (F1 * sk1 + (1.0 - F1) * sk2) * nt, nu + (F1 * sw1 + (1.0 - F1) * sw2) * nt);
}

PointSource MenterSst::source(const TurbState& phi, const CellFlow& c) const {
  PointSource s;
  const Real k = std::max(phi[0], 0.0), w = std::max(phi[1], wFloor);
  const Blend b = blend(phi, c);
  const Real beta = b.f1 * beta1 + (1.0 - b.f1) * beta2;
  const Real gamma = b.f1 * gamma1 + (1.0 - b.f1) * gamma2;
  const Real S = strain_magnitude(c.grad_u);
  const Real prod = std::min(nut(phi, c) * S * S, 10.0 * betastar * k * w);
  s.value[0] = prod - betastar * k * w;
  s.value[1] = gamma * S * S - beta * w * w + (1.0 - b.f1) * b.cross;
  s.implicit[0] = betastar * w;
  s.implicit[1] = 2.0 * beta * w;
  return s;
}

}  // namespace narwhal
