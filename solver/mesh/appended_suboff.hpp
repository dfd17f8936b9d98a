#pragma once
// Grids around the appended SUBOFF (mesh/suboff_geometry.hpp): the body-of-revolution
// topology (four sectors between two pole squares, body_of_revolution.hpp) with the sail
// and the stern appendages standing in the sectors' boundary planes, each in a box of its
// own (mesh/appendage_box.hpp; mesh/DESIGN.md, "Appendage boxes", says why).
//
// - Along the hull, two windows of wall lines follow the appendages: over the sail's
//   chord they run straight up (its sections are constant in x); over the stern
//   appendages' chord along lines of constant chord fraction. One tip level k_tip: the
//   sail's uniform section's top over the sail, R_max over the stern appendages, blended
//   between. The wall lines are the boxes' levels.
// - Azimuths are uniform. A box spans box_half_width sector cells either side of its
//   plane and cells_margin stations ahead of and behind its window; inside it an O-grid
//   about the appendage's section at every level carries the appendage's clustering, so
//   that it stays in the box.
// - The sectors are cut at the boxes' edges along the hull and across (the squares with
//   them) and at k_tip: every face is whole. All configurations share this grid outside
//   the boxes (a configuration without an appendage keeps the hull grid's pieces in its
//   box), which keeps the appendage increments free of grid changes elsewhere.
// - Deflected control surfaces: the box's (or the tube's) grid deformed about the turned
//   surface (mesh/appendage_box.hpp, mesh/sail_plane_tube.hpp).
// - `full` adds the sail planes on the sail's sides, in a tube of their own round the hull
//   (mesh/sail_plane_tube.hpp), which cuts the sail's box and every sector further.
//
// Coordinates: grid axes (motion/grid_axes.hpp): nose at x = 0, tail at x = length,
// y to port, z down (the sail at -z). Patch labels: "body" (the hull), "farfield", and
// each appendage's name (sail, upper_rudder, lower_rudder, starboard_stern_plane,
// port_stern_plane).
#include <string>
#include <vector>

#include "mesh/block.hpp"
#include "mesh/suboff_geometry.hpp"

namespace narwhal {

struct AppendedSuboffSpec {
  std::string configuration = "bare";  // bare, sail, stern4, sail_stern4, full
  suboff::Deflections deflections;
  Real length = 1.0;        // the overall length in grid units
  // Cells along the hull, in five stretches between the pole squares:
  int cells_bow = 96;       // nose square -> the sail's leading edge
  int cells_sail = 32;      // the sail's chord
  int cells_middle = 64;    // the sail's trailing edge -> the stern appendages' leading edges
  int cells_fin = 32;       // the stern appendages' chord
  int cells_stern = 48;     // their trailing edges -> the tail square
  int cells_around = 32;    // per 90-degree sector
  int cells_span = 80;      // hull -> tip level
  int cells_outer = 64;     // tip level -> far field
  Real first_spacing = 2e-6;   // off the hull, grid units
  Real fin_spacing = 2e-6;     // off the appendages (the O-grids' first spacing along the section's normal)
  Real tip_spacing = 2e-6;     // along the wall lines at the tip level (the tip faces' first spacing)
  // The stations' spacing at the appendages' leading and trailing edges. The boxes' O-grids
  // resolve the edges; the stations only carry the boxes' sides, which want about the
  // chord's mean spacing (and the margins ahead and behind a fair distance): the grid
  // raises either to 0.9 of the chord's mean spacing if it is smaller.
  Real leading_edge_spacing = 1e-3;
  Real trailing_edge_spacing = 1e-3;
  // Along the meridians at nose and tail. The pole squares are cells_around x pole_spacing
  // / sqrt(2) across: the SUBOFF runs need them no larger than about 0.005 L (mesh/DESIGN.md).
  Real pole_spacing = 2.25e-4;
  Real far_field = 15.0;       // in body lengths
  // The appendages' boxes (mesh/appendage_box.hpp): sector cells either side of the
  // plane, stations ahead of and behind the chord, O cells from the section to the box,
  // how far the O's lines leave along the section's normal, the spacing along the section
  // at its edges, and the height over which the cap block widens above the tip.
  int box_half_width = 16;
  int cells_margin = 16;
  int cells_section = 32;
  Real section_layer = 2e-3;
  Real section_edge_spacing = 5e-5;
  Real cap_growth = 0.05;
};

// A member of a grid family: every cell count times `scale`, rounded to a multiple of 4
// (at least 4, the appendages' O-grids at least 12 cells deep), so that every block keeps
// two multigrid levels or more (4 -> 2), but the boxes' half width, which keeps the
// reference's fraction of a sector (whole cells);
// every spacing set at the walls, edges and poles divided by `scale`, so that the family's
// members are alike in shape (the wall cells' y+ goes as 1 / scale). The members are
// generated, not coarsened: the family's finest grid need not be built to run its
// coarsest, and the ratio of refinement is free (the harness takes each member's grid
// spacing from its cell count).
AppendedSuboffSpec scaled(const AppendedSuboffSpec& spec, Real scale);

// The configurations these grids mesh: every one of suboff::configuration_names().
std::vector<std::string> appended_suboff_configurations();

Grid make_appended_suboff(const AppendedSuboffSpec& spec);

}  // namespace narwhal
