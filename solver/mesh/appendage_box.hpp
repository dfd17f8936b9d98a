#pragma once
// The blocks of an appendage's box (mesh/DESIGN.md, "Appendage boxes"): inside a box of
// the hull's grid about the appendage's plane, one O-grid (mesh/section_ogrid.hpp) about
// its section at every level of the hull's wall lines, stacked into six blocks from the
// hull to the tip level and six above it (front and back halved where the box passes
// from one sector of the hull's grid to the next), and a cap over the tip, filling the
// section's outline from the tip to the far field in two halves.
//
// The chart of a level: sigma, the arc length along the level's meridional curve (the
// hull's at level 0), and w = r (phi - phi_plane), so that near the plane the chart is
// the level surface's own metric and the O's first cells are orthogonal to the section.
// Nodes go back to space exactly: a section node at (x, r) is turned out of the plane by
// the appendage's own angle there, so it lies on the appendage; level-0 nodes on the hull.
#include <array>
#include <functional>
#include <string>
#include <vector>

#include "mesh/block.hpp"
#include "mesh/level_stack.hpp"
#include "mesh/section_ogrid.hpp"
#include "mesh/suboff_geometry.hpp"

namespace narwhal {

struct AppendageBox {
  const suboff::Appendage* appendage = nullptr;
  Real feet = 1.0;   // grid units per foot
  Real plane = 0.0;  // the appendage plane's azimuth, atan2(z, y) in grid axes
  // The box's nodes in the hull's grid, per level k = 0 .. levels: front from the -w
  // corner to the +w corner, top (+w) and bottom (-w) from front to back, back from +w to
  // -w. They stay bit for bit.
  std::vector<std::vector<Vec3>> front, top, back, bottom;
  // The station parameter (the wall line's foot, arc length along the hull's meridian)
  // of each top/bottom node, front to back, and the level curves: (x, r) of the wall line
  // from foot s at level k, exact at the stations and on the hull at level 0.
  std::vector<Real> stations;
  std::function<std::array<Real, 2>(Real s, int k)> level;
  int tip_level = 0;          // where the appendage ends (its tip is a flat face there)
  ogrid::Spec section_grid;   // cells, first spacing and layer at the appendage
  Real outer_angle = 0.0;     // the hull grid's azimuthal cell: the O's spacing at the box
  // Above the tip the section's outline (the cap block) widens to twice its thickness and
  // the O's first spacing grows to a quarter of its spacing at the box, over this height.
  Real cap_growth = 0.0;
  // Raises the cap block's lowest nodes (the tip face) by this height at (x, w) (grid
  // units): the sail's elliptic cap over its uniform section. Null: a flat tip.
  std::function<Real(Real x, Real w)> crest;
  // An O ring at this distance across the plane (grid units), clustered with this spacing
  // either side (ogrid::Spec's knot): where the sail planes' tips lie. 0: none.
  Real knot_offset = 0.0;
};

// The box's blocks, named `<tag>_<part>_inner` (hull to tip) and `_outer` (tip to far
// field), parts fm, fp (the front's halves on the -w and +w side), up, bp, bm, lo (the
// lower side); the cap `<tag>_cap_<part>` and `<tag>_cap_corem`/`corep` (CGNS allows zone
// names of 32 characters: the tag is short). Wall patches are labelled `name` on the
// appendage and its tip, "body" on the hull; "farfield" at the last level.
// With `levels_out`, the box's levels (k = 0 .. the last) are left there too: what a grid
// that cuts the box further (the sail planes' tube) needs of it.
std::vector<Block> make_appendage_box(const AppendageBox& box, const std::string& name, const std::string& tag,
                                      std::vector<Level>* levels_out = nullptr);

}  // namespace narwhal
