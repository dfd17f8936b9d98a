#include "mesh/body_of_revolution.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "core/error.hpp"
#include "mesh/generators.hpp"
#include "mesh/meridian.hpp"
#include "mesh/suboff_geometry.hpp"

namespace narwhal {

BodyProfile sphere_profile(Real diameter) {
  return {"sphere", diameter, [diameter](Real x) { return std::sqrt(std::max(0.0, x * (diameter - x))); }};
}

BodyProfile spheroid_profile(Real length, Real ratio) {
  const Real a = 0.5 * length, b = a / ratio;
  return {"spheroid", length, [a, b](Real x) {
            const Real u = (x - a) / a;
            return b * std::sqrt(std::max(0.0, 1.0 - u * u));
          }};
}

// The DARPA SUBOFF hull (mesh/suboff_geometry.hpp), scaled so that its overall length is `length`.
BodyProfile suboff_profile(Real length) {
  return {"suboff", length, [length](Real x_scaled) {
            return suboff::hull_radius(x_scaled / length * suboff::kOverallLength) / suboff::kOverallLength * length;
          }};
}

namespace {

using namespace revolution;

void add_patches(Block& b) {
  for (int side = 0; side < 6; ++side) {
    if (side_dir(side) != 2) continue;  // i and j faces: interfaces, found by connect_free_faces
    Patch p;
    p.side = side;
    p.lo = {0, 0, 0};
    p.hi = b.dims();
    p.label = side_high(side) ? "farfield" : "body";
    b.patches.push_back(p);
  }
}

}  // namespace

Grid make_body_of_revolution(const BodyGridSpec& spec) {
  const int na = spec.cells_around, nl = spec.cells_along;
  if (na < 1 || nl < 2 || spec.cells_normal < 1) fail("body grid: cell counts must be >= 1 (along >= 2)");
  if (nl % 2 != 0) fail("body grid: cells_along ({}) must be even (clustered at both poles)", nl);
  const Meridian m(spec.profile);
  const Real S = m.length(), L = spec.profile.length;
  const Real pole_ds = spec.pole_spacing > 0.0 ? spec.pole_spacing : L / (4.0 * nl);
  // The squares' cells about as long as the meridians' first ones.
  const Real rho = na * pole_ds / std::sqrt(2.0);
  if (rho >= 0.25 * S)
    fail("body grid: the pole squares ({} across) would cover more than half the meridian ({}); use a smaller "
         "pole spacing or fewer cells around",
         2 * rho, S);
  // Fractions along a sector's meridians, clustered at both poles; every meridian
  // takes them over its own length between the two squares.
  const Real inner = S - 2.0 * rho;
  const std::vector<Real> f = geometric_nodes_both_ends(0.0, 1.0, nl, std::min(pole_ds / inner, 1.0 / nl));
  const Extrusion ex(spec, m, L);
  const int nk = ex.cells();

  const Azimuth az{na};
  Grid g;
  // Four sectors; j runs against the azimuth so that (i, j, k) is right-handed.
  for (int sector = 0; sector < 4; ++sector) {
    Block b(fmt::format("sector_{}", sector * 90), nl, na, nk);
    for (int j = 0; j <= na; ++j) {
      const int ma = (sector + 1) * na - j;
      const auto end = diamond(rho, az, ma);
      const Real re = std::hypot(end[0], end[1]);
      for (int i = 0; i <= nl; ++i) {
        SurfacePoint p;
        if (i == 0 || i == nl)  // on a square's edge: the square's own formula, so that both blocks agree
          p = near_pole(m, end, i == nl);
        else
          p = surface(m, re + (S - 2.0 * re) * f[static_cast<std::size_t>(i)], az.unit(ma));
        for (int k = 0; k <= nk; ++k) b.x(i, j, k) = ex.node(p, k);
      }
    }
    add_patches(b);
    g.blocks.push_back(std::move(b));
  }
  // The pole squares: transfinite interpolation of the diamond's edges in (X, Y).
  for (const bool tail : {false, true}) {
    Block b = make_pole_square(m, az, rho, nk, tail, [&](const SurfacePoint& p, int k) { return ex.node(p, k); });
    add_patches(b);
    g.blocks.push_back(std::move(b));
  }
  return g;  // the i and j faces are connected by finalize_grid (mesh/setup.hpp)
}

}  // namespace narwhal
