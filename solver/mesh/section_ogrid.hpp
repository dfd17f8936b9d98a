#pragma once
// An O-grid about a thin section (an appendage's cross-section at one span level) inside
// a four-sided box, in a 2-D chart (sigma along the chord, w across it), and the
// quadrilateral grid inside the section (the cap block over a tip). The appendage grids
// stack one such O-grid per span level (mesh/DESIGN.md, "Appendage boxes": why the
// appendages get boxes of their own instead of clustering the hull's H-grid).
//
// The O's wall-normal lines start along the section's normal (so the first spacing is
// exactly the wall spacing asked for) for a layer holding half their cells, then run
// straight to their box node; the box's nodes are given (they are the surrounding grid's), so
// the O's clustering stays inside the box. Its ring of section nodes runs from the lower
// leading-edge junction round the leading edge, along the upper side, round the trailing
// edge and back along the lower side, matched side by side to the box:
//   front block: box front (lower corner -> upper)  <-> the leading-edge arc
//   upper block: box top (front -> back)            <-> the upper side
//   back block:  box back (upper corner -> lower)   <-> the trailing-edge arc (the sharp
//                                                        edge at its middle node)
//   lower block: box bottom (back -> front)         <-> the lower side
#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/types.hpp"

namespace narwhal::ogrid {

using Point = Eigen::Matrix<Real, 2, 1>;

// The section's two sides from the leading edge (u = 0, shared) to the trailing edge
// (u = 1, shared); u about the chord fraction. A round leading edge (w ~ sqrt(u)) and a
// sharp trailing edge are what it is made for.
struct Section {
  std::function<Point(Real)> upper, lower;
};

// The box's nodes, each side in the ring's running direction; consecutive sides share
// their corner node.
struct Box {
  std::vector<Point> front, top, back, bottom;
};

struct Spec {
  int cells_normal = 32;         // from the section to the box
  Real first_spacing = 1e-5;     // off the section, along its normal
  Real outer_spacing = 1e-2;     // along the lines at the box (at most the line's mean spacing)
  Real leading_edge_arc = 0.03;  // the front block's arc reaches this u on each side
  Real trailing_edge_arc = 0.9;  // the back block's arc starts at this u on each side
  Real leading_edge_spacing = 1e-3;   // along the section at the leading edge
  Real trailing_edge_spacing = 1e-3;  // and at the trailing edge
  Real layer = 0.05;             // the lines leave along the section's normal for this distance
  int trailing_edge_fan = 3;     // nodes either side of the sharp edge whose normals fan
  int cells_layer = 0;           // cells within `layer` (0: half of cells_normal)
  // A ring clustered at a distance across the section's plane: on the sides' lines it lies
  // at |w| = knot_w, with spacing knot_spacing either side (the sail planes' tips lie on
  // it: mesh/sail_plane_tube.hpp); the arcs' lines take it at the fraction of their length
  // their junctions' lines have, blended across. 0: none.
  int knot_ring = 0;
  Real knot_w = 0.0;
  Real knot_spacing = 0.0;
};

struct OGrid {
  // ring[t][s]: t = 0 on the section, t = cells_normal on the box; s = 0 .. cells_around
  // (the last node repeats the first: the lower leading-edge junction).
  std::vector<std::vector<Point>> ring;
  // Where the blocks start along the ring: front, upper, back, lower, and the end.
  std::array<int, 5> split{};
  std::vector<Real> u;  // each section node's u (the ring's t = 0)
  int cells_around() const { return split[4]; }
  int cells_normal() const { return static_cast<int>(ring.size()) - 1; }
};

// The O-grid between `section` and `box` (fails, naming what, when the counts do not
// allow one: the arcs need an even number of cells, so the edges are nodes).
OGrid make_section_ogrid(const Section& section, const Box& box, const Spec& spec);

// The grid inside the section (the cap over a tip): a ring of `ring_cells` cells inward
// from the section's nodes, as the O's ring outward (ring[t][s], t = 0 the section's
// nodes, s as the O's), and a core within it, core[a][b]: a = 0 .. cells along the upper
// side (the lower side must have as many), b = 0 .. cells round the leading edge (the
// trailing edge's must be as many), b = 0 the lower side. The core's corners are real
// corners (its front and back straight across the section where the O's arcs end, its
// sides halfway between the section's sides and its mean line); a single quadrilateral
// with its corners on the smooth outline has a straight angle at each, which folds.
struct SectionCap {
  std::vector<std::vector<Point>> ring;
  std::vector<std::vector<Point>> core;
};
SectionCap section_cap(const OGrid& o, const Section& section, int ring_cells);

// Twice the signed area of the quadrilateral a, b, c, d (counter-clockwise positive).
Real quad_area2(const Point& a, const Point& b, const Point& c, const Point& d);

}  // namespace narwhal::ogrid
