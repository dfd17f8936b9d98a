#include "manoeuvring/manoeuvring_model.hpp"

#include <cmath>

namespace narwhal {

std::vector<std::pair<std::string, Real*>> ManoeuvringCoefficients::named() {
  return {{"Xuu", &Xuu},     {"Xvv", &Xvv},     {"Xww", &Xww},     {"Xqq", &Xqq},     {"Xrr", &Xrr},
          {"Xdrdr", &Xdrdr}, {"Xdsds", &Xdsds}, {"Xudot", &Xudot}, {"Yv", &Yv},       {"Yr", &Yr},
          {"Yvv", &Yvv},     {"Ydr", &Ydr},     {"Yvdot", &Yvdot}, {"Yrdot", &Yrdot}, {"Z0", &Z0},
          {"Zw", &Zw},       {"Zq", &Zq},       {"Zww", &Zww},     {"Zds", &Zds},     {"Zdb", &Zdb},
          {"Zwdot", &Zwdot}, {"Zqdot", &Zqdot}, {"Kp", &Kp},       {"Kpdot", &Kpdot}, {"M0", &M0},
          {"Mw", &Mw},       {"Mq", &Mq},       {"Mww", &Mww},     {"Mds", &Mds},     {"Mdb", &Mdb},
          {"Mwdot", &Mwdot}, {"Mqdot", &Mqdot}, {"Nv", &Nv},       {"Nr", &Nr},       {"Nvv", &Nvv},
          {"Ndr", &Ndr},     {"Nvdot", &Nvdot}, {"Nrdot", &Nrdot}};
}

BodyLoads hydrodynamic_loads(const ManoeuvringCoefficients& c, const Vec6& nu, const suboff::Deflections& d) {
  const Real u = nu[0], v = nu[1], w = nu[2], p = nu[3], q = nu[4], r = nu[5];
  const Real uu = u * std::abs(u);  // keeps the resistance's sign when the body backs
  const Real dr = d.rudder, ds = d.stern_planes, db = d.sail_planes;
  BodyLoads l;
  l.force.x() = c.Xuu * uu + c.Xvv * v * v + c.Xww * w * w + c.Xqq * q * q + c.Xrr * r * r +
                (c.Xdrdr * dr * dr + c.Xdsds * ds * ds) * u * u;
  l.force.y() = c.Yv * u * v + c.Yr * u * r + c.Yvv * v * std::abs(v) + c.Ydr * uu * dr;
  l.force.z() = c.Z0 * uu + c.Zw * u * w + c.Zq * u * q + c.Zww * w * std::abs(w) + (c.Zds * ds + c.Zdb * db) * uu;
  l.moment.x() = c.Kp * u * p;
  l.moment.y() = c.M0 * uu + c.Mw * u * w + c.Mq * u * q + c.Mww * w * std::abs(w) + (c.Mds * ds + c.Mdb * db) * uu;
  l.moment.z() = c.Nv * u * v + c.Nr * u * r + c.Nvv * v * std::abs(v) + c.Ndr * uu * dr;
  l.force *= 0.5;
  l.moment *= 0.5;
  return l;
}

Mat6 added_mass(const ManoeuvringCoefficients& c) {
  Mat6 m = Mat6::Zero();
  m(0, 0) = c.Xudot;
  m(1, 1) = c.Yvdot;
  m(2, 2) = c.Zwdot;
  m(3, 3) = c.Kpdot;
  m(4, 4) = c.Mqdot;
  m(5, 5) = c.Nrdot;
  m(1, 5) = m(5, 1) = 0.5 * (c.Yrdot + c.Nvdot);
  m(2, 4) = m(4, 2) = 0.5 * (c.Zqdot + c.Mwdot);
  return -0.5 * m;
}

}  // namespace narwhal
