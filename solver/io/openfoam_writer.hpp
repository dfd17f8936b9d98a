#pragma once
// A grid as an OpenFOAM polyMesh (constant/polyMesh: points, faces, owner, neighbour,
// boundary), so that a peer code runs on exactly Narwhal's grid.
//
// Every cell of every block is one hexahedron. Nodes shared by blocks become one point
// (matched by position, to 1e-10 of the grid's extent); a block-boundary face that is
// not on a patch is joined to the face of another block with the same four points.
// Faces follow OpenFOAM's rules: internal faces in upper-triangular order (by owner,
// then neighbour), each pointing from its owner (the lower cell number) to its
// neighbour; boundary faces pointing out of the domain, grouped by patch label in the
// order the labels first appear. No-slip walls become `wall` patches, the rest `patch`.
#include <cstddef>
#include <string>

#include "mesh/block.hpp"

namespace narwhal {

struct OpenFoamMeshCounts {
  std::size_t points = 0, cells = 0, faces = 0, internal_faces = 0;
};

// Writes DIR/constant/polyMesh/*. Periodic interfaces are refused (their faces share
// no points).
OpenFoamMeshCounts write_openfoam_mesh(const std::string& case_dir, const Grid& g);

}  // namespace narwhal
