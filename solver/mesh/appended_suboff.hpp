#pragma once
// Grids around the appended SUBOFF (mesh/suboff_geometry.hpp): the body-of-revolution
// topology (four sectors between two pole squares, body_of_revolution.hpp) with the sail
// and the stern appendages standing in the sectors' boundary planes (mesh/DESIGN.md,
// "Appended SUBOFF", says why and what it costs).
//
// - Along the hull, two windows of grid lines follow the appendages: over the sail's
//   chord the wall lines run straight up (the sail's sections are constant in x); over
//   the stern appendages' chord they run along lines of constant chord fraction, so that
//   each appendage's planform is exactly a rectangle of index space in its boundary plane
//   (i from its leading to its trailing edge, k from the hull to its tip). All
//   configurations share these lines: `bare` and `sail_stern4` differ only where the
//   appendages are, which keeps the appendage increments free of grid changes elsewhere.
// - One tip level k_tip: the wall lines are split there at every station (at the sail's
//   crest over the sail, at the stern appendages' tip over theirs, blended between).
// - An appendage is made by turning the nodes near its plane about the hull axis, each
//   boundary-plane node to the appendage's surface at its own radius (so that the hull's
//   nodes stay on the hull), the turn fading over the sector's 90 degrees. A deflected
//   control surface would be made by the same turn (not yet: deflections are refused).
// - The blocks are then cut at the windows' ends and at k_tip, so that each appendage
//   side is a whole block face: the solver's interfaces stay whole-face.
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
  std::string configuration = "bare";  // bare, sail, stern4, sail_stern4
  suboff::Deflections deflections;
  Real length = 1.0;        // the overall length in grid units
  // Cells along the hull, in five stretches between the pole squares:
  int cells_bow = 96;       // nose square -> the sail's leading edge
  int cells_sail = 32;      // the sail's chord
  int cells_middle = 64;    // the sail's trailing edge -> the stern appendages' leading edges
  int cells_fin = 32;       // the stern appendages' chord
  int cells_stern = 48;     // their trailing edges -> the tail square
  int cells_around = 32;    // per 90-degree sector
  int cells_span = 64;      // hull -> tip level
  int cells_outer = 48;     // tip level -> far field
  Real first_spacing = 2e-6;   // off the hull, grid units
  Real fin_spacing = 2e-6;     // off the appendages (at the sail's crest, the largest radius)
  Real tip_spacing = 1e-3;     // along the wall lines at the tip level
  // Chordwise at the appendages' leading and trailing edges. The wall lines leave a blunt
  // leading edge sideways (an H-grid), so the first cell behind it is sheared by about
  // sqrt(2 r_le / spacing) (r_le the edge's radius: sail 0.0053 L, stern appendages 0.0018 L):
  // 1.5e-3 L keeps that under 3 (with 2e-4 L the SST runs with the sail diverged).
  Real leading_edge_spacing = 1.5e-3;
  Real trailing_edge_spacing = 2e-4;
  // Along the meridians at nose and tail. The pole squares are cells_around x pole_spacing
  // / sqrt(2) across: the SUBOFF runs need them no larger than about 0.005 L (mesh/DESIGN.md).
  Real pole_spacing = 2.25e-4;
  Real far_field = 15.0;       // in body lengths
  // The sail's cap closes with this slope instead of tangentially (suboff::Sail): the
  // cells at its crest are sheared by about this ratio.
  Real sail_crest_slope = 4.0;
};

// The configurations these grids mesh: suboff::configuration_names() but `full` (its sail
// planes are not meshed yet).
std::vector<std::string> appended_suboff_configurations();

Grid make_appended_suboff(const AppendedSuboffSpec& spec);

}  // namespace narwhal
