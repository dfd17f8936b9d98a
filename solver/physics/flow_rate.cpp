#include "physics/flow_rate.hpp"

#include <cmath>

#include "core/error.hpp"
#include "parallel/reduction.hpp"

namespace narwhal {

FlowRateControl::FlowRateControl(const Communicator& comm, const Grid& g, const Vec3& initial_force, Real target)
    : comm_(comm), G_(std::make_shared<Real>(initial_force.norm())), target_(target) {
  if (!(initial_force.norm() > 0.0)) fail("a target bulk velocity needs flow.body_force for its direction");
  e_ = initial_force.normalized();
  for (const Block& b : g.blocks) for_each_cell(b, [&](int i, int j, int k) { volume_ += b.vol(i, j, k); });
}

std::function<Vec3(const Vec3&)> FlowRateControl::source() const {
  return [G = G_, e = e_](const Vec3&) { return Vec3(*G * e); };
}

Real FlowRateControl::bulk_velocity(const Grid& g, const FlowField& f) const {
  std::vector<Real> flux(g.blocks.size(), 0.0);  // per block, added in block order
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    for_each_cell(b, [&](int i, int j, int k) { flux[ib] += b.vol(i, j, k) * e_.dot(f.Q[ib](i, j, k).tail<3>()); });
  }
  return sum_in_block_order(comm_, g, std::move(flux), 1)[0] / volume_;
}

void FlowRateControl::update(const Grid& g, const FlowField& f,
                             const std::map<std::string, std::vector<WallFace>>& walls) {
  // Force of the fluid on the walls along e: shear cf/2 (U_ref = 1) and pressure
  // -p n = -cp/2 n (n into the fluid).
  // (A_ref = 2 makes the coefficients the forces themselves.)
  Real Fw = 0.0;
  for (const auto& [name, c] : integrate_forces(comm_, g, walls, 2.0, 1.0, Vec3::Zero())) Fw += e_.dot(c.force);
  const Real ub = bulk_velocity(g, f);
  if (!(ub > 0.0)) return;  // the flow runs backwards or is not finite: keep the force
  const Real balance = Fw / volume_ * (target_ / ub) * (target_ / ub);
  *G_ += 0.5 * (balance - *G_);
}

}  // namespace narwhal
