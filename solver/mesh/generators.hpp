#pragma once
// Built-in grid generators: tensor-product (stretched) boxes for plates, channels
// and ducts; smoothly perturbed curvilinear boxes for verification; and block
// surgery (extract a sub-block, re-orient its indices) to build multiblock cases.
#include <cstdint>
#include <vector>

#include "mesh/block.hpp"

namespace narwhal {

// 1-D node distributions (n cells -> n+1 nodes).
std::vector<Real> uniform_nodes(Real a, Real b, int n);
// Geometric growth away from `a` with first spacing ds (ds <= (b-a)/n required).
std::vector<Real> geometric_nodes(Real a, Real b, int n, Real ds_first);
// Geometric growth towards `a` from `b`: last spacing (at b) is ds_last.
std::vector<Real> geometric_nodes_to_end(Real a, Real b, int n, Real ds_last);
// Geometric growth from both ends towards the middle, first spacing ds at each end
// (n even; the two halves are mirror images: ducts and channels).
std::vector<Real> geometric_nodes_both_ends(Real a, Real b, int n, Real ds);
// Geometric growth from the middle out to both ends, first spacing ds either side of the
// middle (n even; mirror images: a disk or a jet on the box's centre line).
std::vector<Real> geometric_nodes_from_middle(Real a, Real b, int n, Real ds);
// Clustered at both ends with first spacing ds_a at a and last spacing ds_b at b, both
// exact (a tanh stretching made asymmetric by a Moebius map of the unit interval).
// Needs sqrt(ds_a ds_b) < (b - a) / n.
std::vector<Real> two_sided_nodes(Real a, Real b, int n, Real ds_a, Real ds_b);

// Tensor-product box; patches labelled "imin".."kmax" cover the six faces.
Block make_box(const std::string& name, const std::vector<Real>& xs, const std::vector<Real>& ys,
               const std::vector<Real>& zs);

struct FlatPlateSpec {
  Real x_runup = 0.25;       // symmetry run-up length ahead of the leading edge
  Real length = 1.0;         // plate length
  Real height = 1.0;         // domain height
  Real width = 0.1;          // one-cell span (z), symmetry on both sides
  int n_runup = 24;
  int n_plate = 96;
  int n_normal = 64;
  Real dx_le = 2e-3;         // streamwise spacing at the leading edge
  Real dx_te = 0.0;          // spacing at the trailing edge (0: geometric from the leading edge only)
  Real dy_wall = 1e-4;       // first wall-normal spacing
};
// Labels: inlet (imin), outlet (imax), runup and plate (jmin), top (jmax),
// side_lo (kmin), side_hi (kmax).
Grid make_flat_plate(const FlatPlateSpec& s);

// Unit box [0,1]^3 with n cells per direction mapped by
// x = X + a sin(2 pi X) sin(2 pi Y) sin(2 pi Z) (1, 0.8, 0.6)... smooth, boundary-preserving.
Block make_perturbed_box(const std::string& name, int n, Real amplitude);

// Random interior perturbation of every node (boundary nodes of the block too
// when `move_boundary`), amplitude relative to the local spacing.
void randomly_perturb(Block& b, Real fraction, std::uint64_t seed, bool move_boundary);

// Sub-block of nodes [lo, hi] (cell range lo..hi). Patches on sides shared with the
// parent are clipped and copied; the other sides are left free (to be connected).
Block extract_block(const Block& parent, const std::string& name, const Index3& lo, const Index3& hi);

// Re-index a block: new axis m runs along old axis perm[m], reversed when
// sign[m] < 0. The map must be a proper rotation (keeps the block right-handed).
Block reorient_block(const Block& b, const Index3& perm, const Index3& sign);

}  // namespace narwhal

namespace narwhal {
// Split every block into parts[0] x parts[1] x parts[2] sub-blocks (as even as the
// cell counts allow). With `rotate`, sub-blocks are re-indexed by a cycle of
// proper rotations so that interfaces join blocks of different orientations.
Grid split_blocks(const Grid& g, const Index3& parts, bool rotate);
}  // namespace narwhal
