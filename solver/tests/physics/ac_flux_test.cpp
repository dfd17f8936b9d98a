// Roe flux for the artificial-compressibility system (NUMERICS §3, §12.1 item 2):
// consistency, Roe property, the three identical flux forms, the projector form
// against the explicit eigen-decomposition, and the numerical Jacobian against
// the complex step.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <complex>
#include <random>

#include "implicit/jacobian.hpp"
#include "physics/ac_flux.hpp"

namespace narwhal {
namespace {

constexpr Real kBeta = 5.0;

struct Sample {
  State qL, qR;
  FaceGeom f;
};

std::vector<Sample> random_samples(int n, bool moving) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<Real> U(-1.0, 1.0);
  std::vector<Sample> out;
  for (int m = 0; m < n; ++m) {
    Sample s;
    for (int q = 0; q < 4; ++q) {
      s.qL[q] = 2.0 * U(rng);
      s.qR[q] = 2.0 * U(rng);
    }
    s.f.S = Vec3(U(rng), U(rng), U(rng)) * (0.1 + std::abs(U(rng)));
    const Vec3 vg = moving ? Vec3(U(rng), U(rng), U(rng)) : Vec3::Zero();
    s.f.kt = -vg.dot(s.f.S);
    out.push_back(s);
  }
  return out;
}

// §3.2 analytic Jacobian.
Mat4 flux_jacobian(const State& q, const FaceGeom& f) {
  const Vec3 u = q.tail<3>();
  const Real theta = f.kt + f.S.dot(u);
  Mat4 A = Mat4::Zero();
  A.block<1, 3>(0, 1) = kBeta * f.S.transpose();
  A.block<3, 1>(1, 0) = f.S;
  A.block<3, 3>(1, 1) = theta * Mat3::Identity() + u * f.S.transpose();
  return A;
}

// §3.4 full eigen-decomposition with explicit tangents.
struct Eigen4 {
  Mat4 R, L;
  State lambda;
};
Eigen4 eigen_system(const State& q, const FaceGeom& f) {
  const Vec3 u = q.tail<3>();
  const Real S2 = f.S.squaredNorm();
  const Vec3 n = f.S / std::sqrt(S2);
  int m = 0;
  for (int a = 1; a < 3; ++a)
    if (std::abs(n[a]) < std::abs(n[m])) m = a;
  const Vec3 t1 = n.cross(Vec3::Unit(m)).normalized();
  const Vec3 t2 = n.cross(t1);
  const Real Theta = f.S.dot(u), theta = f.kt + Theta, sigma = theta - 0.5 * f.kt;
  const Real c = std::sqrt(sigma * sigma + kBeta * S2);
  const Real lp = sigma + c, lm = sigma - c;
  Eigen4 e;
  e.lambda << theta, theta, lp, lm;
  e.R.col(0) << 0.0, t1;
  e.R.col(1) << 0.0, t2;
  e.R.col(2) << kBeta * (lp - theta), kBeta * f.S + lp * u;
  e.R.col(3) << kBeta * (lm - theta), kBeta * f.S + lm * u;
  const Real den = kBeta * S2 + theta * Theta;
  const Vec3 tm[2] = {t1, t2};
  for (int r = 0; r < 2; ++r) {
    const Real a = -S2 * tm[r].dot(u) / den;
    e.L.row(r) << a, (tm[r] + theta * a / S2 * f.S).transpose();
  }
  const Real Np = 2.0 * c * lp * (lp - theta), Nm = -2.0 * c * lm * (lm - theta);
  e.L.row(2) << S2 / Np, (lp / Np) * f.S.transpose();
  e.L.row(3) << S2 / Nm, (lm / Nm) * f.S.transpose();
  return e;
}

Real rel(const State& a, const State& b) { return (a - b).norm() / std::max(1.0, b.norm()); }

TEST(RoeFlux, IsConsistent) {
  for (const auto& s : random_samples(200, true))
    EXPECT_LT(rel(roe_flux<Real>(s.qL, s.qL, s.f, kBeta), physical_flux<Real>(s.qL, s.f, kBeta)), 1e-14);
}

TEST(RoeFlux, ArithmeticMeanHasTheRoeProperty) {
  for (const auto& s : random_samples(200, true)) {
    const State qbar = 0.5 * (s.qL + s.qR);
    const State lhs = physical_flux<Real>(s.qR, s.f, kBeta) - physical_flux<Real>(s.qL, s.f, kBeta);
    EXPECT_LT(rel(lhs, flux_jacobian(qbar, s.f) * (s.qR - s.qL)), 1e-13);
  }
}

TEST(RoeFlux, EigenDecompositionReproducesA) {
  for (const auto& s : random_samples(200, true)) {
    const auto e = eigen_system(s.qL, s.f);
    EXPECT_LT((e.L * e.R - Mat4::Identity()).norm(), 1e-12);
    const Mat4 A = flux_jacobian(s.qL, s.f);
    EXPECT_LT((e.R * e.lambda.asDiagonal() * e.L - A).norm(), 1e-12 * std::max(1.0, A.norm()));
    EXPECT_GT(e.lambda[2], 0.0);
    EXPECT_LT(e.lambda[3], 0.0);
  }
}

TEST(RoeFlux, SplitMatricesSumToAAndAllThreeFormsAgree) {
  for (const auto& s : random_samples(200, true)) {
    const State qbar = 0.5 * (s.qL + s.qR), dQ = s.qR - s.qL;
    const auto e = eigen_system(qbar, s.f);
    const State lp = e.lambda.cwiseMax(0.0), lm = e.lambda.cwiseMin(0.0);
    const Mat4 Ap = e.R * lp.asDiagonal() * e.L, Am = e.R * lm.asDiagonal() * e.L;
    const Mat4 Aabs = e.R * e.lambda.cwiseAbs().asDiagonal() * e.L;
    const Mat4 A = flux_jacobian(qbar, s.f);
    EXPECT_LT((Ap + Am - A).norm(), 1e-12 * std::max(1.0, A.norm()));
    const State FL = physical_flux<Real>(s.qL, s.f, kBeta), FR = physical_flux<Real>(s.qR, s.f, kBeta);
    const State roe = roe_flux<Real>(s.qL, s.qR, s.f, kBeta);
    EXPECT_LT(rel(roe, FL + Am * dQ), 1e-12);
    EXPECT_LT(rel(roe, FR - Ap * dQ), 1e-12);
    EXPECT_LT(rel(roe, 0.5 * (FL + FR) - 0.5 * Aabs * dQ), 1e-12);
    // Cheap projector |A| dQ equals the eigen form.
    EXPECT_LT(rel(abs_A_times<Real>(qbar, dQ, s.f, kBeta), Aabs * dQ), 1e-12);
  }
}

TEST(RoeFlux, ContinuityComponentMatchesClosedForm) {
  for (const auto& s : random_samples(100, true)) {
    const State qbar = 0.5 * (s.qL + s.qR), dQ = s.qR - s.qL;
    const Real theta = s.f.kt + s.f.S.dot(qbar.tail<3>());
    const Real sigma = theta - 0.5 * s.f.kt;
    const Real c = std::sqrt(sigma * sigma + kBeta * s.f.S.squaredNorm());
    const Real F1 = kBeta * s.f.S.dot(qbar.tail<3>()) -
                    kBeta / (2 * c) * (s.f.S.squaredNorm() * dQ[0] + sigma * s.f.S.dot(dQ.tail<3>()));
    EXPECT_NEAR(roe_flux<Real>(s.qL, s.qR, s.f, kBeta)[0], F1, 1e-12 * std::max(1.0, std::abs(F1)));
  }
}

TEST(RoeFlux, NumericalJacobianMatchesComplexStep) {
  using C = std::complex<Real>;
  for (const auto& s : random_samples(100, true)) {
    const State F0 = roe_flux<Real>(s.qL, s.qR, s.f, kBeta);
    const Mat4 AL = numerical_jacobian([&](const State& q) { return roe_flux<Real>(q, s.qR, s.f, kBeta); }, s.qL,
                                       F0, 1e-7);
    const Mat4 AR = numerical_jacobian([&](const State& q) { return roe_flux<Real>(s.qL, q, s.f, kBeta); }, s.qR,
                                       F0, 1e-7);
    Mat4 csL, csR;
    const Real h = 1e-30;
    for (int m = 0; m < 4; ++m) {
      StateT<C> qL = s.qL.cast<C>(), qR = s.qR.cast<C>();
      qL[m] += C(0.0, h);
      csL.col(m) = roe_flux<C>(qL, s.qR.cast<C>(), s.f, kBeta).imag() / h;
      qL = s.qL.cast<C>();
      qR[m] += C(0.0, h);
      csR.col(m) = roe_flux<C>(qL, qR, s.f, kBeta).imag() / h;
    }
    EXPECT_LT((AL - csL).norm() / csL.norm(), 1e-6);
    EXPECT_LT((AR - csR).norm() / csR.norm(), 1e-6);
  }
}

}  // namespace
}  // namespace narwhal
