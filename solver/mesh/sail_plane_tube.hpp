#pragma once
// The sail planes' tube (mesh/DESIGN.md, "Sail planes: a tube of their own, round the
// hull"): one box for the pair, whose levels run from the starboard plane's root on the
// sail's side out through the sail box's O layers, round the hull through the sectors'
// azimuthal planes, and in through the other side's O layers to the port plane's root.
// Its cross-section is a rectangle of the host's stations and levels about the planes;
// at every level an O about the plane's section (or, between the tips, about the tip's
// section widened) fills it, and beyond each tip the cap (mesh/level_stack.hpp) fills the
// section's outline. The tube's two ends are walls, so no block of it ends inside the grid.
//
// The chart of every level is (x, r): the axial position and the distance from the hull
// axis, mapped back to space on the level's surface through its azimuth phi(x, r): a
// sector's level is a meridional half-plane (phi constant), a sail box layer the surface
// through the host's nodes (phi interpolated between them; on the sail's side, exact).
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "mesh/block.hpp"
#include "mesh/section_ogrid.hpp"
#include "mesh/suboff_geometry.hpp"

namespace narwhal {

// One level of the tube: the host's node at (station, level) and the surface's azimuth
// (atan2(z, y), grid axes) at chart point (x, r), grid units.
struct TubeLevel {
  std::function<Vec3(int station, int level)> node;
  std::function<Real(Real x, Real r)> azimuth;
};

struct SailPlaneTube {
  // The plane rooted at the first level and the one rooted at the last.
  std::array<const suboff::Fin*, 2> planes{};
  Real feet = 1.0;  // grid units per foot
  std::vector<TubeLevel> levels;
  // The cross-section: stations [station_first, station_last], the host's levels
  // [level_low, level_high], its front and back halved at level_mid (the planes' height).
  int station_first = 0, station_last = 0, level_low = 0, level_mid = 0, level_high = 0;
  // The tube levels of the two tips (each plane's tip face lies on it; its O up to there).
  std::array<int, 2> tips{};
  // Tube levels where the host's blocks change (the tips are added): the tube's blocks
  // break there, so every face it shares with the host is whole.
  std::vector<int> breaks;
  ogrid::Spec section_grid;  // the O's cells, first spacing and layer at the planes
  Real cap_growth = 0.0;     // over this distance from a tip the outline widens (grid units)
  std::string tag = "sp";    // block name prefix
};

// The azimuth of the surface through a patch of a host's nodes (nodes[i][k]: i along x,
// k outwards in r) beside a plane through the axis at azimuth `plane` (on its `sign`
// side: the sail's): each node's distance from that plane less `follow` times `side(x)`
// (the sail's half-thickness) interpolated bilinearly in the chart cell holding the point
// (its corners' (x, r) inverted; the nearest cell's extension outside the patch), and the
// azimuth at that distance. A layer close to the side follows it (follow = 1: an
// interpolated azimuth cut into the curved side between the nodes by more than the first
// cell); the planes' tip layer, a plane across, follows nothing (interpolating its
// distance beyond the side bowed it out by the side's sag between stations).
std::function<Real(Real x, Real r)> patch_azimuth(std::vector<std::vector<Vec3>> nodes, std::function<Real(Real x)> side,
                                                  Real follow, Real plane, Real sign);

// The tube's blocks. Patch labels: each plane's name on its section and its tip, `root`
// (the sail) at both ends.
std::vector<Block> make_sail_plane_tube(const SailPlaneTube& tube, const std::string& root);


}  // namespace narwhal
