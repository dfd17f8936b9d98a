#pragma once
// A deflected control surface in grid units (mesh/DESIGN.md, "Deflected control
// surfaces"): its plane's coordinates of a node, a node turned about its stock, the turned
// surface's point at a chord fraction and span, and how far a node lies off what the fin
// stands on (the hull for the stern appendages, the sail's side for the sail planes).
// The appendage boxes and the sail planes' tube deform their grids with it.
#include <functional>

#include "mesh/suboff_geometry.hpp"

namespace narwhal {

struct TurnedFin {
  const suboff::Fin& fin;
  Real feet;  // grid units per foot
  // Signed distance of a node outside the root's surface (grid units).
  std::function<Real(const Vec3&)> off_root;

  Vec3 plane(const Vec3& node) const { return fin.plane_coordinates(suboff::from_grid_axes(node / feet)); }
  Vec3 grid(const Vec3& p) const { return suboff::to_grid_axes(p) * feet; }
  Vec3 turn(const Vec3& node, Real angle) const {
    const Vec3 c = plane(node);
    return grid(fin.turned(c[0], c[1], c[2], angle));
  }
  Vec3 surface(Real xi, Real s, int side) const {
    const Real x = fin.trailing_edge(s) + fin.chord(s) * (xi - 1.0);
    return grid(fin.turned(x, s, side * fin.half_thickness(x, s), fin.deflection));
  }
};

// The span shift (feet) that puts the turned surface's point at (xi, s, side) on the
// root's surface: secant steps from no shift. Fails naming the fin when it finds none.
Real root_span_shift(const TurnedFin& f, Real xi, Real s, int side);

}  // namespace narwhal
