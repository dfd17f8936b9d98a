#pragma once
// Directions in which nothing varies: one-cell layers whose two faces cancel.
//
// A block one cell thick in direction d holds a solution that does not vary along d
// when either
// - both its d sides are symmetry planes that are parallel, still and flat, no other
//   grid face is tilted out of the plane, and no velocity has a component along the
//   plane normal (a planar 2-D problem stored as a slab): the mirror ghosts equal
//   the cell state and each plane carries the flux (0, p S) of a still face; or
// - both its d sides are one periodic interface of the block with itself, a pure
//   translation (a streamwise-periodic duct or channel one cell long): the ghosts
//   are the cell itself, any velocity included.
// Either way the two faces of every cell see the same uniform state on equal area
// vectors, and their fluxes cancel exactly, in the residual and in its Jacobian,
// and every derivative along d is zero. The solver then skips those faces
// (Block::invariant_dir): no converged answer changes, half of a 2-D case's face
// work goes, and the multigrid and the line relaxation see the problem they solve;
// a periodic pair of faces left in, with its block coupling lagged, slowed the
// periodic duct's multigrid about 60-fold (turbulence/DESIGN.md).

#include <string>

#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

enum class SlabKind { None, SymmetryPlanes, SelfPeriodic };

// The kind and direction of slab `b` of grid `g` is (geometry, boundary conditions
// and interfaces only): `dir` is -1 for None. `normal` holds the unit normal of
// the skipped faces.
struct Slab {
  SlabKind kind = SlabKind::None;
  int dir = -1;
  Vec3 normal = Vec3::Zero();
};
Slab slab_direction(const Grid& g, int ib);

// Marks every block of `g` with its invariant direction when all of them are slabs
// of one kind with the same normal and, for symmetry slabs, neither the state in
// `f`, the patch velocities nor the momentum source has a component along it;
// otherwise marks none. Returns a one-line description of the decision for the log
// (empty when no block is a slab).
std::string mark_invariant_directions(Grid& g, const FlowField& f, const FlowParams& fp);

}  // namespace narwhal
