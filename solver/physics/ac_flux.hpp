#pragma once
// Artificial-compressibility inviscid flux and Roe's approximate Riemann solver
// (NUMERICS §3). Kernels are templated on the scalar so that unit tests can
// complex-step them; on real data they compile to plain double arithmetic.
#include <cmath>
#include <complex>

#include "core/error.hpp"
#include "core/types.hpp"

namespace narwhal {

// The flux kernels are evaluated nine times per face by the numerical Jacobian
// (§6.3); inlined, the independent evaluations overlap in the pipeline.
#define NARWHAL_INLINE inline __attribute__((always_inline))

inline Real real_part(Real x) { return x; }
inline Real real_part(const std::complex<Real>& x) { return x.real(); }

// Face data the flux depends on: area vector S (not unit), grid term k_t (§1.3), beta.
struct FaceGeom {
  Vec3 S;
  Real kt = 0.0;
};

// §3.1: F(Q) = [beta Theta', u theta + Sx p, v theta + Sy p, w theta + Sz p].
template <class T>
NARWHAL_INLINE StateT<T> physical_flux(const StateT<T>& q, const FaceGeom& f, Real beta) {
  const T Theta = f.S[0] * q[1] + f.S[1] * q[2] + f.S[2] * q[3];
  const T theta = f.kt + Theta;
  StateT<T> F;
  F[0] = beta * Theta;
  F[1] = q[1] * theta + f.S[0] * q[0];
  F[2] = q[2] * theta + f.S[1] * q[0];
  F[3] = q[3] * theta + f.S[2] * q[0];
  return F;
}

// Acoustic eigen-data at the Roe (arithmetic-mean) state, §3.3–3.5.
template <class T>
struct AcousticData {
  T theta, sigma, c, lp, lm, Np, Nm;
  Real S2;
};

template <class T>
NARWHAL_INLINE AcousticData<T> acoustic_data(const T& ux, const T& uy, const T& uz, const FaceGeom& f, Real beta) {
  AcousticData<T> a;
  a.S2 = f.S.squaredNorm();
  const T Theta = f.S[0] * ux + f.S[1] * uy + f.S[2] * uz;
  a.theta = f.kt + Theta;
  a.sigma = a.theta - 0.5 * f.kt;
  a.c = std::sqrt(a.sigma * a.sigma + beta * a.S2);
  a.lp = a.sigma + a.c;
  a.lm = a.sigma - a.c;
  a.Np = 2.0 * a.c * a.lp * (a.lp - a.theta);
  a.Nm = -2.0 * a.c * a.lm * (a.lm - a.theta);
  // §3.6 guard: acoustic and convective eigenvalues must stay distinct (§3.3).
  if (std::abs(real_part(a.lp - a.theta)) < 1e-8 * real_part(a.c) ||
      std::abs(real_part(a.lm - a.theta)) < 1e-8 * real_part(a.c))
    fail("Roe flux: hyperbolicity condition beta > (v_g.n)^2/4 violated (NUMERICS §3.3); increase beta "
         "(face: |S|^2 = {:.3e}, k_t = {:.3e})", real_part(a.S2), real_part(f.kt));
  return a;
}

// §3.6 low-flop form F(QL) + A^-(Qbar) dQ with the cheap projector evaluation.
template <class T>
NARWHAL_INLINE StateT<T> roe_flux(const StateT<T>& qL, const StateT<T>& qR, const FaceGeom& f, Real beta) {
  const T ux = 0.5 * (qL[1] + qR[1]), uy = 0.5 * (qL[2] + qR[2]), uz = 0.5 * (qL[3] + qR[3]);
  const StateT<T> dQ = qR - qL;
  const auto a = acoustic_data(ux, uy, uz, f, beta);
  const T Sdu = f.S[0] * dQ[1] + f.S[1] * dQ[2] + f.S[2] * dQ[3];
  // alpha_pm = (|S|^2 dp + lambda_pm S.du) / N_pm with a single division.
  const T inv = 1.0 / (a.Np * a.Nm);
  const T alpha_p = (a.S2 * dQ[0] + a.lp * Sdu) * (a.Nm * inv);
  const T alpha_m = (a.S2 * dQ[0] + a.lm * Sdu) * (a.Np * inv);
  const T theta_m = real_part(a.theta) < 0.0 ? a.theta : T(0.0);
  StateT<T> rp, rm;
  rp << beta * (a.lp - a.theta), beta * f.S[0] + a.lp * ux, beta * f.S[1] + a.lp * uy, beta * f.S[2] + a.lp * uz;
  rm << beta * (a.lm - a.theta), beta * f.S[0] + a.lm * ux, beta * f.S[1] + a.lm * uy, beta * f.S[2] + a.lm * uz;
  StateT<T> F = physical_flux(qL, f, beta);
  F += theta_m * dQ - (theta_m * alpha_p) * rp + ((a.lm - theta_m) * alpha_m) * rm;
  return F;
}

// |A| dQ in the projector form (§3.6), used by tests and the far-field BC.
template <class T>
StateT<T> abs_A_times(const StateT<T>& qbar, const StateT<T>& dQ, const FaceGeom& f, Real beta) {
  const auto a = acoustic_data(qbar[1], qbar[2], qbar[3], f, beta);
  const T Sdu = f.S[0] * dQ[1] + f.S[1] * dQ[2] + f.S[2] * dQ[3];
  const T alpha_p = (a.S2 * dQ[0] + a.lp * Sdu) / a.Np;
  const T alpha_m = (a.S2 * dQ[0] + a.lm * Sdu) / a.Nm;
  StateT<T> rp, rm;
  rp << beta * (a.lp - a.theta), beta * f.S[0] + a.lp * qbar[1], beta * f.S[1] + a.lp * qbar[2],
      beta * f.S[2] + a.lp * qbar[3];
  rm << beta * (a.lm - a.theta), beta * f.S[0] + a.lm * qbar[1], beta * f.S[1] + a.lm * qbar[2],
      beta * f.S[2] + a.lm * qbar[3];
  using std::abs;
  const T at = abs(a.theta);
  return at * dQ + ((abs(a.lp) - at) * alpha_p) * rp + ((abs(a.lm) - at) * alpha_m) * rm;
}

// Projections onto the acoustic eigenvectors at state qb: P_pm X = r_pm (l_pm X) (§3.4, §5.2).
struct AcousticProjectors {
  Mat4 Pp, Pm;
  Real theta;
};
AcousticProjectors acoustic_projectors(const State& qb, const FaceGeom& f, Real beta);

}  // namespace narwhal
