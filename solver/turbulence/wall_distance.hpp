#pragma once
// Wall distance (NUMERICS §2.6) for multiblock grids: for every cell centre the
// exact distance to the nearest no-slip wall face of any block, each quadrilateral
// face taken as the nearer of its two triangulations, and the index of that face
// (for u_tau and y+). §2.6 asks for the distance to face centroids, which is too large
// between centroids by up to half a wall face's width. Both triangulations,
// because a block's mirror image numbers its corners the other way round: with one, the
// distances of mirror cells differed by the faces' warp.
//
// Search: a bounding-volume hierarchy over the wall faces (median splits along the longest
// axis, a few faces a leaf), nearer child first, pruned by the distance to each box; each
// cell starts from its neighbour's nearest face, which bounds the search at once. Ties (a
// cell nearest to an edge two faces share) go to the lowest face index whatever the search
// order, so the face behind u_tau is the brute force's. Only the blocks the grid's rank
// owns are measured (the others keep +inf and -1): nothing reads them there. Computed once
// per grid; grids that move relative to their walls call it again.
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

// The distance from p to wall face f of g (the nearer of its two triangulations): the
// search's measure, for checking it.
Real wall_face_distance(const Grid& g, const WallFaceRef& f, const Vec3& p);

// Exact distance from p to the triangle (a, b, c).
Real point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace narwhal
