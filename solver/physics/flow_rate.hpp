#pragma once
// Constant flow rate for periodic ducts and channels (as in the DNS they are compared
// with): the driving body force G e is adjusted after every iteration (or cycle) so
// that the bulk velocity U_b reaches its target. With the force fixed instead, U_b
// and hence the Reynolds number would be an outcome of the model's friction.
//
// The update is the steady momentum balance, scaled towards the target:
//   G <- G + w [ (F_w / V) (U_target / U_b)^2 - G ],   w = 0.5,
// F_w the streamwise force of the fluid on the walls and V the fluid volume. At a
// steady state F_w = G V, so the fixed point is U_b = U_target; the friction term keeps
// G near the balance while the flow develops, the square its turbulent scaling.
// Usage (case file):
//   [flow]
//   body_force = [0.0083, 0.0, 0.0]   # direction and first estimate of G
//   bulk_velocity = 1.0               # target U_b along the force (0: force fixed)
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mesh/block.hpp"
#include "physics/flow.hpp"
#include "physics/wall_forces.hpp"

namespace narwhal {

class FlowRateControl {
 public:
  // bulk_velocity and update are collective over `comm` (the ranks the grid is distributed over).
  FlowRateControl(const Communicator& comm, const Grid& g, const Vec3& initial_force, Real target_bulk_velocity);

  // The momentum source of the residual; every copy (one per multigrid level) reads
  // the current force.
  std::function<Vec3(const Vec3&)> source() const;
  // Volume average of u . e (the bulk velocity of a duct of constant section).
  Real bulk_velocity(const Grid& g, const FlowField& f) const;
  void update(const Grid& g, const FlowField& f, const std::map<std::string, std::vector<WallFace>>& walls);
  Vec3 force() const { return *G_ * e_; }
  Real magnitude() const { return *G_; }
  void set_magnitude(Real G) { *G_ = G; }  // from a restart

 private:
  Communicator comm_;
  Vec3 e_;
  std::shared_ptr<Real> G_;
  Real target_, volume_ = 0.0;
};

}  // namespace narwhal
