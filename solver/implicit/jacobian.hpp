#pragma once
// Numerical flux Jacobians by one-sided differences (NUMERICS §6.3).
#include <algorithm>
#include <cmath>

#include "core/types.hpp"

namespace narwhal {

// J(:,m) = (F(q + h_m e_m) - F(q)) / h_m with h_m = eps * max(|q_m|, Q_ref,m), Q_ref = 1.
template <class F>
Mat4 numerical_jacobian(F&& flux, const State& q, const State& f0, Real eps) {
  Mat4 J;
  for (int m = 0; m < kNumEq; ++m) {
    const Real h = eps * std::max(std::abs(q[m]), 1.0);
    State qp = q;
    qp[m] += h;
    J.col(m) = (flux(qp) - f0) / h;
  }
  return J;
}

}  // namespace narwhal
