#include "app/propulsion_control.hpp"

#include <fmt/format.h>

#include "core/error.hpp"

namespace narwhal {

PropulsionControl::PropulsionControl(const CaseConfig& c, const Grid& g, const Communicator& comm)
    : comm_(comm),
      propulsor_(std::make_shared<BodyForcePropulsor>(c.propulsor->spec, c.propulsor->curve)),
      reference_area_(c.output.reference_area),
      water_(far_water_velocity(c)) {
  // The towing speed: the vehicle's speed through the water along the axis.
  propulsor_->set_surge_speed(-water_.dot(propulsor_->axis()));
  propulsor_->normalise(comm_, g);
  if (c.propulsor->rpm_control) rpm_.emplace(*c.propulsor->rpm_control);
}

void PropulsionControl::follow(const RigidMotionSample& m, const Vec3& pivot) {
  propulsor_->place(m.pose, pivot);
  const Vec3 disk_velocity = m.velocity + m.angular_velocity.cross(propulsor_->centre() - m.pose.apply(pivot, pivot));
  propulsor_->set_surge_speed((disk_velocity - water_).dot(propulsor_->axis()));
}

void PropulsionControl::after_subiteration(const Grid& g, const FlowField& f) { propulsor_->measure_inflow(comm_, g, f.Q); }

BodyLoads PropulsionControl::vehicle_loads(const Vec3& origin) const {
  return {propulsor_->vehicle_force(), propulsor_->vehicle_moment(origin)};
}

void PropulsionControl::after_cycle(int cycle, const Grid& g, const FlowField& f,
                                    const std::map<std::string, ForceCoefficients>& forces) {
  propulsor_->measure_inflow(comm_, g, f.Q);
  // The flow's force on the walls against the thrust's direction: C_F = 2 F / A_ref
  // (rho = U = 1).
  Real along = 0.0;
  for (const auto& [name, fc] : forces) along += fc.force.dot(propulsor_->axis());
  resistance_ = -0.5 * reference_area_ * along + 0.0;  // + 0.0: no "-0" in the outputs
  if (!rpm_) return;
  const Real n = propulsor_->spec().rps;
  const Real next = rpm_->update(cycle, n, propulsor_->loads().thrust, resistance_, propulsor_->thrust_slope());
  if (next != n) propulsor_->set_rps(next);
}

std::vector<Real> PropulsionControl::checkpoint() const {
  std::vector<Real> s{propulsor_->spec().rps, propulsor_->loads().advance_speed};
  if (rpm_) {
    const RpmController::State r = rpm_->state();
    s.insert(s.end(), {static_cast<Real>(r.last_step_cycle), static_cast<Real>(r.steps), r.surplus,
                       r.settled ? 1.0 : 0.0});
  }
  return s;
}

void PropulsionControl::restore(const std::vector<Real>& s) {
  if (s.empty()) return;  // a restart written without a propulsor: start at the case's rotation rate
  // A run without a controller takes the operating point of a restart written with one:
  // a manoeuvre starts at the self-propulsion point a steady run found.
  if (s.size() != (rpm_ ? 6u : 2u) && !(s.size() == 6u && !rpm_))
    fail("restart: its propulsor state has {} values, this case's propulsor {} (with{} an rpm controller)", s.size(),
         rpm_ ? 6 : 2, rpm_ ? "" : "out");
  propulsor_->restore_operating_point(s[0], s[1]);
  if (rpm_) rpm_->restore({static_cast<int>(s[2]), static_cast<int>(s[3]), s[4], s[5] != 0.0});
}

nlohmann::ordered_json PropulsionControl::report(const Vec3& moment_centre) const {
  // Nondimensional (rho = 1, NUMERICS §0.2); the loads on the vehicle in grid axes (§9.5).
  const BodyForcePropulsor& p = *propulsor_;
  const PropulsorLoads& l = p.loads();
  const Vec3 F = p.vehicle_force(), M = p.vehicle_moment(moment_centre);
  nlohmann::ordered_json j = {{"name", p.name()},
                              {"curve", p.curve().describe()},
                              {"rps", p.spec().rps},
                              {"surge_speed", l.surge_speed},
                              {"advance_speed", l.advance_speed},
                              {"wake_fraction", l.wake_fraction},
                              {"advance_from", p.spec().inflow_distance ? "inflow" : "surge"},
                              {"advance_ratio", l.advance_ratio},
                              {"kt", l.kt},
                              {"kq", l.kq},
                              {"thrust", l.thrust},
                              {"torque", l.torque},
                              {"swirl", p.spec().swirl},
                              {"rotation", p.spec().rotation > 0 ? "right" : "left"},
                              {"disk_volume", p.disk_volume()},
                              {"resistance", resistance_},
                              {"vehicle_force", {F[0], F[1], F[2]}},
                              {"vehicle_moment", {M[0], M[1], M[2]}}};
  if (rpm_)
    j["rpm_control"] = {{"settled", rpm_->settled()}, {"surplus", rpm_->surplus()}, {"steps", rpm_->steps()}};
  return j;
}

std::string PropulsionControl::describe() const {
  const BodyForcePropulsor& p = *propulsor_;
  const PropulsorLoads& l = p.loads();
  return fmt::format("propulsor '{}': J {:.4f} (V_A {:.4g}, n {:.4g}), K_T {:.4f}, K_Q {:.5f}, T {:.4g}, Q {:.4g}{}; {}",
                     p.name(), l.advance_ratio, l.advance_speed, p.spec().rps, l.kt, l.kq, l.thrust, l.torque,
                     rpm_ ? ", rpm controlled to self-propulsion" : "", p.curve().describe());
}

}  // namespace narwhal
