#pragma once
// Grid quality measures of a structured multiblock grid, for `narwhal grid` and
// `narwhal check`: what a CFD user looks at before spending cycles on a grid.
//
//  - scaled corner Jacobian: at each of a cell's eight corners, det(e1, e2, e3) /
//    (|e1| |e2| |e3|) of the three edges leaving it along +i, +j, +k (sign-corrected).
//    1 for a box, <= 0 for a folded or collapsed cell, which is an error even when
//    the cell's total volume is positive;
//  - wall orthogonality: 90 degrees minus the angle between a wall face's normal and
//    the line from its centroid to the centroid of the first cell's opposite face;
//  - stretching: the largest ratio of the widths of neighbouring cells along an index
//    direction (width = volume / mean area of the two faces across that direction);
//  - aspect ratio: a cell's largest width over its smallest;
//  - y+ estimate of the first cell centre off each wall, from the turbulent flat-plate
//    friction Cf = 0.026 Re_L^(-1/7) (White, Viscous Fluid Flow, eq. 6-70) at the wall's
//    streamwise length L — a planning figure, not a result.
#include <string>
#include <vector>

#include "mesh/block.hpp"

namespace narwhal {

// One extreme value of a measure and where it occurs.
struct QualityExtreme {
  Real value = 0.0;
  std::string block;
  Index3 cell{0, 0, 0};
};

struct GridQuality {
  std::size_t cells = 0;
  QualityExtreme min_volume;
  QualityExtreme min_corner_jacobian;
  std::size_t folded_cells = 0;  // cells with a scaled corner Jacobian <= 0
  bool has_walls = false;
  QualityExtreme min_wall_orthogonality_deg;
  QualityExtreme max_first_cell_height;  // wall-normal distance of the first cell centre
  QualityExtreme max_y_plus;             // estimate (see above); 0 when reynolds is 0
  QualityExtreme max_stretching;
  QualityExtreme max_aspect_ratio;
};

// The folds alone, what a grid deformation must check: the smallest scaled corner
// Jacobian and the number of cells at or below 0.
struct FoldReport {
  QualityExtreme worst;
  std::size_t folded = 0;
};
FoldReport measure_folds(const std::vector<Block>& blocks);

// `wall_labels`: patch labels that are no-slip walls. `reynolds`: Re per unit length
// of the grid (0: no y+ estimate).
GridQuality measure_grid_quality(const Grid& g, const std::vector<std::string>& wall_labels, Real reynolds);

// The report printed by `narwhal grid`: one line per measure with where it occurs.
std::string format_grid_quality(const GridQuality& q);

// Throws an Error naming the first folded cell's block and indices when any cell has
// a scaled corner Jacobian <= 0. `where` names the grid's source (case file).
void require_unfolded(const FoldReport& folds, const std::string& where);
void require_unfolded(const GridQuality& q, const std::string& where);

// Skin-friction estimate behind the y+ figure: Cf = 0.026 Re_L^(-1/7).
Real flat_plate_friction_estimate(Real reynolds_length);

}  // namespace narwhal
