#pragma once
// Grids around a body of revolution (sphere, prolate spheroid, the SUBOFF hull):
// six blocks with no singular axis.
//
// Topology ("butterfly" O-O, the cubed sphere's): on the body surface, a small
// square patch covers each pole (nose and tail) and four sectors of 90 degrees of
// azimuth each run from the nose square to the tail square along meridians. The
// sector boundaries lie at azimuths 0, 90, 180 and 270 degrees (appendages attach
// there); the squares' corners lie on them. Near a pole the surface is mapped from
// its polar projection (X, Y) = s (cos phi, sin phi), s the arc length from the pole,
// which is smooth for a blunt end; the square is the diamond |X| + |Y| <= rho there,
// its grid the transfinite interpolation of its four straight edges, whose nodes lie
// where the sectors' meridians meet them. Three blocks meet at each square corner
// (angles of about 90, 135 and 135 degrees): no zero-area face and no axis anywhere.
// Each surface block is extruded to the far field: wall lines leave along the surface
// normal and turn towards the direction of polar angle pi s / S (forward at the nose,
// radial at mid-length, aft at the tail), so that the outer boundary is roughly a
// sphere `far_field` body lengths out.
//
// The squares' edges are C0 interfaces: the sectors' meridians meet a square's grid
// lines at up to 45 degrees. The index-space MUSCL reconstruction (NUMERICS §3.7) is
// first order across such a kink, so keep the squares small (pole_spacing) until the
// lines leave the squares smoothly (DESIGN.md has the measurements and the plan).
//
// Coordinates: the axis is x, the nose at x = 0 and the tail at x = L; azimuth phi
// runs from +y towards +z. Patch labels: "body" (every block's kmin) and "farfield"
// (every kmax); the blocks' other faces are 1-to-1 interfaces, connected by
// finalize_grid (mesh/setup.hpp).
#include <functional>
#include <string>
#include <vector>

#include "mesh/block.hpp"

namespace narwhal {

// The meridian r(x), 0 <= x <= length, r > 0 inside and r = 0 at both ends.
struct BodyProfile {
  std::string name;
  Real length = 1.0;
  std::function<Real(Real)> radius;
};

BodyProfile sphere_profile(Real diameter);
// Prolate spheroid of the given length and length-to-diameter ratio.
BodyProfile spheroid_profile(Real length, Real ratio);
// The DARPA SUBOFF axisymmetric hull (DTRC models 5470/5471) of the given overall length.
BodyProfile suboff_profile(Real length);

struct BodyGridSpec {
  BodyProfile profile;
  int cells_along = 64;     // nose square edge to tail square edge, along a meridian
  int cells_around = 16;    // per 90-degree sector (and along each square edge)
  int cells_normal = 48;    // body to far field
  Real first_spacing = 1e-3;   // wall-normal, in the length unit of the profile
  Real pole_spacing = 0.0;     // meridional spacing at nose and tail (0: length / (4 cells_along))
  Real far_field = 20.0;       // distance of the outer boundary, in body lengths
};

Grid make_body_of_revolution(const BodyGridSpec& spec);

}  // namespace narwhal
