#include "mesh/turned_fin.hpp"

#include <cmath>

#include "core/error.hpp"

namespace narwhal {

Real root_span_shift(const TurnedFin& f, Real xi, Real s, int side) {
  Real d0 = 0.0, g0 = f.off_root(f.surface(xi, s, side));
  Real d1 = g0 > 0.0 ? -1e-3 : 1e-3, g1 = f.off_root(f.surface(xi, s + d1, side));
  for (int it = 0; it < 40 && std::abs(g1) > 1e-14 * f.feet && g1 != g0; ++it) {
    const Real d2 = d1 - g1 * (d1 - d0) / (g1 - g0);
    d0 = d1, g0 = g1;
    d1 = d2, g1 = f.off_root(f.surface(xi, s + d1, side));
  }
  if (!(std::abs(g1) <= 1e-9 * f.feet))
    fail("'{}': the deflected root at chord fraction {:.3f} does not meet what it stands on", f.fin.name(), xi);
  return d1;
}

}  // namespace narwhal
