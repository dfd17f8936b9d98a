#pragma once
// Wall distance (NUMERICS §2.6) for multiblock grids: for every cell centre the
// exact distance to the nearest no-slip wall face of any block, each quadrilateral
// face taken as the nearer of its two triangulations, and the index of that face
// (for u_tau and y+). §2.6 asks for the distance to face centroids, which is too large
// between centroids by up to half a wall face's width. Both triangulations,
// because a block's mirror image numbers its corners the other way round: with one, the
// distances of mirror cells differed by the faces' warp.
//
// Search: wall faces are binned in a uniform grid of buckets; a cell visits the
// bucket shells around it in order of distance and stops once the next shell is
// farther than the best face found, so the cost grows like cells x (faces near
// the cell) rather than cells x all wall faces. Computed once per grid; grids that
// move relative to their walls call it again.
#include <vector>

#include "fields/ghost_array.hpp"
#include "mesh/block.hpp"

namespace narwhal {

struct WallFaceRef {
  int block = -1, side = -1;
  Index3 cell{0, 0, 0};  // the wall-adjacent interior cell
};

struct WallDistance {
  std::vector<GhostArray<Real>> d;     // per block, interior cells; +inf when the grid has no wall
  std::vector<GhostArray<int>> face;   // index into `faces`, -1 when none
  std::vector<WallFaceRef> faces;      // all no-slip wall faces
  bool any_wall() const { return !faces.empty(); }
};

WallDistance compute_wall_distance(const Grid& g);

// Exact distance from p to the triangle (a, b, c).
Real point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace narwhal
