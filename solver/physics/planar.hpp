#pragma once
// Planar (2-D) grids stored as one-cell-thick 3-D slabs.
//
// A block that is one cell thick in direction d, bounded on both sides by
// symmetry planes that are parallel, with no grid face elsewhere tilted out of
// the plane, holds a planar flow when no velocity has a component along the
// plane normal. Then the mirror ghosts equal the cell state, each symmetry face
// carries the flux (0, p S) of a still face, and the two faces of every cell
// cancel exactly, in the residual and in its Jacobian. Skipping them changes no
// converged answer and removes half of the face work of a 2-D case.

#include <string>

#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

// Direction in which `b` is a planar slab (geometry and boundary conditions
// only), or -1. On success `normal` holds the unit plane normal.
int planar_slab_direction(const Block& b, Vec3& normal);

// Marks every block of `g` as planar when all of them are slabs with the same
// normal and neither the state in `f`, the patch velocities nor the momentum
// source has a component along it; otherwise marks none. Returns a one-line
// description of the decision for the log (empty when no block is a slab).
std::string mark_planar_blocks(Grid& g, const FlowField& f, const FlowParams& fp);

}  // namespace narwhal
