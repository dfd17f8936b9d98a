#pragma once
// Block-to-block connectivity: point-matched (1-to-1) faces are found by
// comparing node positions, for any relative index orientation, and turned into
// Interface records (NUMERICS §5.6); periodic pairs are the same with a rigid
// transform between the faces (§5.5).
#include <optional>
#include <string>

#include "mesh/block.hpp"

namespace narwhal {

// Try to match block face (ba, sa) onto (bb, sb) so that x_A = R x_B + t at every
// face node. Returns the interface that fills A's ghosts from B.
std::optional<Interface> match_faces(const Grid& g, int ba, int sa, int bb, int sb, const Mat3& R,
                                     const Vec3& t);

// Every block face with no patch at all is matched against the other free faces;
// a face left without a partner is an error naming block and side.
void connect_free_faces(Grid& g);

// Turn the full-face patches labelled `label_a` and `label_b` into a periodic pair
// with x_A = R x_B + t. When `t` is not given it is the difference of the face
// centroids (translational periodicity).
void connect_periodic(Grid& g, const std::string& label_a, const std::string& label_b, const Mat3& R,
                      const std::optional<Vec3>& t);

// Checks that the patches of every side tile it exactly once.
void check_patch_cover(const Grid& g);

}  // namespace narwhal
