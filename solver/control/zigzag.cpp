#include "control/zigzag.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace narwhal {

Zigzag::Zigzag(ZigzagSettings s) : s_(s) {
  if (!(s.angle > 0.0)) fail("zig-zag: the deflection must be positive, got {} rad", s.angle);
  if (!(s.switch_at > 0.0)) fail("zig-zag: the switching attitude must be positive, got {} rad", s.switch_at);
  if (!(s.rate >= 0.0) || !std::isfinite(s.rate)) fail("zig-zag: the surface rate must be finite and >= 0, got {}", s.rate);
  if (s.first != 1 && s.first != -1) fail("zig-zag: the first deflection's sign must be +1 or -1, got {}", s.first);
}

suboff::Deflections Zigzag::command(Real t_next, Real dt, const VehicleReading& now,
                                    const suboff::Deflections& present) {
  if (t_next < s_.start) return present;
  const bool rudder = s_.surface == ZigzagSettings::Surface::Rudder;
  const Real attitude = rudder ? now.heading : now.pitch;
  if (sign_ == 0) {
    sign_ = s_.first;
  } else if (-sign_ * attitude >= s_.switch_at) {
    sign_ = -sign_;
    ++reversals_;
  }
  suboff::Deflections d = present;
  Real& surface = rudder ? d.rudder : d.stern_planes;
  const Real target = sign_ * s_.angle;
  const Real most = s_.rate > 0.0 ? s_.rate * dt : std::abs(target - surface);
  surface += std::clamp(target - surface, -most, most);
  return d;
}

void Zigzag::restore(const std::vector<Real>& v) {
  if (v.size() != 2) fail("restart: the zig-zag's state has {} values, 2 expected", v.size());
  sign_ = static_cast<int>(v[0]);
  reversals_ = static_cast<int>(v[1]);
}

}  // namespace narwhal
