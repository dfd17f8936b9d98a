#pragma once
// Rigid motion of a whole grid (NUMERICS §2.4, §6.8 step 2). A pose maps the grid's
// nodes as they were built (reference positions x0, ghost nodes included) to
//   x = R (x0 - pivot) + pivot + d,
// and moving to the pose of t^{n+1} recomputes the metrics there (§2.2, §2.3) and the
// face speeds from the volumes the faces sweep (§2.4):
//   k_t = -(c0 dV^{n+1} - c2 dV^n) / dt_n,
// dV^{n+1} the signed volume face f sweeps from t^n to t^{n+1} (positive towards +S_f),
// dV^n the previous step's. With those, the discrete GCL
//   (c0 V^{n+1} + c1 V^n + c2 V^{n-1}) / dt_n = -sum_f s_cf k_t,f
// holds to round-off in every cell, under rotation too (where -v_g . S would not),
// and a uniform stream stays uniform (§1.5). Every multigrid level moves its own nodes
// and so keeps its own GCL (§7.1). Ghost nodes move with the grid: a rigid motion
// commutes with their linear extrapolation and with translational periodic copies.
#include <array>
#include <vector>

#include "core/types.hpp"
#include "implicit/physical_time.hpp"
#include "mesh/block.hpp"

namespace narwhal {

struct RigidPose {
  Mat3 rotation = Mat3::Identity();
  Vec3 displacement = Vec3::Zero();  // of the pivot
  Vec3 apply(const Vec3& x0, const Vec3& pivot) const { return rotation * (x0 - pivot) + pivot + displacement; }
};

// A rigid motion at one instant: the pose, the pivot's velocity and the angular
// velocity (grid axes).
struct RigidMotionSample {
  RigidPose pose;
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
};

// The signed volume of the trilinear hexahedron with nodes n[p + 2 q + 4 r] at the
// corners (p, q, r) of the unit cube, by §2.3's formula; positive when right-handed.
Real hexahedron_volume(const std::array<Vec3, 8>& n);

// The volume face (d, f) of a block sweeps between node positions `from` and `to`
// (§2.4), positive when it moves towards its area vector's side.
Real swept_volume(const GhostArray<Vec3>& from, const GhostArray<Vec3>& to, int d, const Index3& f);

class MovingGrid {
 public:
  // The grid's present nodes become its reference (pose: identity).
  MovingGrid(Grid& g, const Vec3& pivot);

  // Nodes to the pose of t^{n+1}, metrics there, face speeds for a step dt with
  // coefficients c; the blocks' walls move with the sample's velocity (of the pivot) and
  // angular velocity (§5.1). A step's first move (new_step) starts from the present
  // nodes (t^n); a free body's corrections move again within the step (new_step false),
  // from the same t^n.
  void move_to(const RigidMotionSample& m, Real dt, const BdfCoefficients& c, bool new_step = true);

  // Nodes to the pose the motion starts from, metrics there; the first step's sweep
  // starts here (no face speeds: nothing has moved yet).
  void place_at(const RigidPose& pose);

  // A grid that deforms as it moves (control surfaces turned during a manoeuvre): the
  // nodes as built are replaced by `reference` (the same blocks and layout, ghost nodes
  // included) from the next move on. That move sweeps the faces from where they are to
  // the pose applied to the new shape, so the face speeds carry the deformation and the
  // discrete GCL holds as under rigid motion. The walls' velocity (§5.1) stays the rigid
  // motion's: the deformation's own speed at a wall is left out.
  void reshape(std::vector<GhostArray<Vec3>> reference);
  const std::vector<GhostArray<Vec3>>& reference() const { return x0_; }

  const Vec3& pivot() const { return pivot_; }
  // Each block's bounding box as built, before any move or reshape (min x, y, z, max
  // x, y, z): restarts check a moving grid's blocks there.
  std::vector<std::array<double, 6>> reference_extents() const;

 private:
  Grid& g_;
  Vec3 pivot_;
  std::vector<GhostArray<Vec3>> x0_;                   // reference nodes per block
  std::vector<std::array<double, 6>> built_extents_;   // each block's bounding box as built
  std::vector<GhostArray<Vec3>> previous_x_;           // the nodes before the last move
  std::vector<std::array<GhostArray<Real>, 3>> swept_;   // dV^{n+1} per face, of the step under way
  std::vector<std::array<GhostArray<Real>, 3>> swept_n_;  // dV^n, the step before
  bool moved_ = false;        // a move since the grid was placed
  bool have_sweep_n_ = false;  // dV^n known (the step under way is not the first since placed)
};

}  // namespace narwhal
