#pragma once
// MUSCL kappa-phi extrapolation to a face, in index space, unlimited (NUMERICS §3.7).
#include "core/types.hpp"

namespace narwhal {

struct MusclParams {
  Real kappa = 1.0 / 3.0;
  Real phi = 1.0;  // 0: first order
};

// Left state at face i+1/2 from cells i-1, i, i+1.
template <class V>
inline V muscl_left(const V& qm1, const V& q0, const V& qp1, const MusclParams& m) {
  return q0 + (0.25 * m.phi) * ((1.0 - m.kappa) * (q0 - qm1) + (1.0 + m.kappa) * (qp1 - q0));
}
// Right state at face i+1/2 from cells i, i+1, i+2.
template <class V>
inline V muscl_right(const V& q0, const V& qp1, const V& qp2, const MusclParams& m) {
  return qp1 - (0.25 * m.phi) * ((1.0 - m.kappa) * (qp2 - qp1) + (1.0 + m.kappa) * (qp1 - q0));
}

}  // namespace narwhal
