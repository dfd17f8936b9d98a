#include "physics/ac_flux.hpp"

namespace narwhal {

AcousticProjectors acoustic_projectors(const State& qb, const FaceGeom& f, Real beta) {
  const auto a = acoustic_data(qb[1], qb[2], qb[3], f, beta);
  State rp, rm;
  rp << beta * (a.lp - a.theta), beta * f.S + a.lp * qb.tail<3>();
  rm << beta * (a.lm - a.theta), beta * f.S + a.lm * qb.tail<3>();
  Eigen::Matrix<Real, 1, 4> lp, lm;
  lp << a.S2, a.lp * f.S.transpose();
  lm << a.S2, a.lm * f.S.transpose();
  AcousticProjectors P;
  P.Pp = rp * (lp / a.Np);
  P.Pm = rm * (lm / a.Nm);
  P.theta = a.theta;
  return P;
}

}  // namespace narwhal
