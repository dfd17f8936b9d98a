#include "app/simulate.hpp"

#include <chrono>
#include <filesystem>

#include "config/reader.hpp"
#include "control/control_law.hpp"
#include "core/error.hpp"
#include "io/monitors.hpp"
#include "motion/coupled_body.hpp"
#include "motion/grid_axes.hpp"
#include "motion/rk4.hpp"
#include "motion/trim.hpp"

namespace narwhal {

ManoeuvringModel load_manoeuvring_model(const std::string& path) {
  ConfigReader r(path);
  ManoeuvringModel m;
  for (auto& [name, value] : m.coefficients.named())
    *value = r.number_or("coefficients." + name, 0.0, "a nondimensional coefficient (manoeuvring_model.hpp)");
  if (r.has("propulsion")) {
    m.rps = r.number("propulsion.rps", "the rotation rate at the self-propulsion point, n L / U", Range::positive());
    m.wake_fraction = r.number_or("propulsion.wake_fraction", 0.0, "the wake fraction w_T", Range::between(-1.0, 1.0));
    m.thrust_deduction =
        r.number_or("propulsion.thrust_deduction", 0.0, "the thrust deduction t", Range::between(-1.0, 1.0));
  }
  r.reject_unknown_keys();
  return m;
}

namespace {

// The vehicle and the loads on it, evaluated at any state and time.
class ModelledVehicle {
 public:
  ModelledVehicle(const CaseConfig& c, const ManoeuvringModel& model, const ControlLaw& law)
      : c_(c), f_(*c.free_body), model_(model), law_(law), body_(f_.mass, options(f_, model)),
        water_(far_water_velocity(c)) {
    if (model.rps && !c.propulsor) fail("simulate: the model's [propulsion] needs the case's [propulsor]");
  }

  const RigidBodyEquations& body() const { return body_; }

  // The hydrodynamic and propulsive loads (body axes, about O) at state s.
  BodyLoads loads(const RigidBodyState& s) const {
    const Mat3 r = rotation_matrix(s.attitude());
    Vec6 nu;  // through the water: the grid frame's velocity less the water's
    nu << Vec3(s.velocity()) - r.transpose() * water_, s.angular_velocity();
    return hydrodynamic_loads(model_.coefficients, nu, law_.angles()) + propulsion(nu);
  }
  // With the weights the vehicle carries besides its own: ballast changes, trim.
  BodyLoads all_loads(const RigidBodyState& s, Real t) const {
    const Vec3 down = rotation_matrix(s.attitude()).transpose() * f_.mass.down;
    return loads(s) + ballast_loads(f_.ballast, down, t) + trim_.loads(down);
  }
  void trim_at(const RigidBodyState& s) {
    trim_ = f_.trim.any() ? trim_at_release(f_.trim, body_, s, loads(s)) : TrimWeights{};
  }

 private:
  static AccelerationOptions options(const FreeBodySpec& f, const ManoeuvringModel& m) {
    AccelerationOptions o = f.options;
    o.added_mass_estimate = added_mass(m.coefficients);  // the model's, solved with the body's own (not an estimate)
    return o;
  }
  // (1 - t) T e_a at the disk, T = K_T n^2 D^4 at J = (1 - w) u_a / (n D) (NUMERICS §9.1
  // option a); the torque's reaction on the vehicle, -rotation Q e_a.
  BodyLoads propulsion(const Vec6& nu) const {
    if (!model_.rps) return {};
    const PropulsorSpec& p = c_.propulsor->spec;
    const Vec3 axis = grid_to_body_axes(p.axis), arm = grid_to_body_axes(p.centre - f_.origin);
    const Real n = *model_.rps, d = 2.0 * p.disk.tip_radius;
    const Real j = (1.0 - model_.wake_fraction) * Vec3(nu.head<3>()).dot(axis) / (n * d);
    const Real thrust = c_.propulsor->curve->kt(j) * n * n * d * d * d * d;
    const Real torque = c_.propulsor->curve->kq(j) * n * n * d * d * d * d * d;
    const Vec3 force = (1.0 - model_.thrust_deduction) * thrust * axis;
    return {force, arm.cross(force) - static_cast<Real>(p.rotation) * torque * axis};
  }

  const CaseConfig& c_;
  const FreeBodySpec& f_;
  const ManoeuvringModel& model_;
  const ControlLaw& law_;
  RigidBodyEquations body_;
  Vec3 water_;
  TrimWeights trim_;
};

}  // namespace

SimulationSummary simulate(const CaseConfig& c, const ManoeuvringModel& model, const std::string& out_dir) {
  if (!c.free_body) fail("simulate: the case has no free body ([motion] type = \"free\")");
  if (!c.time.unsteady()) fail("simulate: the case has no [time] table (the steps to fly)");
  const auto started = std::chrono::steady_clock::now();
  std::filesystem::create_directories(out_dir);
  const FreeBodySpec& f = *c.free_body;
  ControlLaw law(c.controls, c.autopilot, c.zigzag, c.grid.appended.deflections);
  ModelledVehicle vehicle(c, model, law);
  RigidBodyState s = body_state_at_release(f.origin, f.velocity, f.angular_velocity);
  const Mat3 initial = rotation_matrix(s.attitude());
  law.start();
  vehicle.trim_at(s);
  MotionWriter motion((std::filesystem::path(out_dir) / "motion.csv").string(), std::nullopt);
  const bool turning = c.controls || c.autopilot || c.zigzag;
  std::optional<ControlsWriter> controls;
  if (turning) controls.emplace((std::filesystem::path(out_dir) / "controls.csv").string(), std::nullopt);
  const StateDependentLoads loads = [&](const RigidBodyState& x, Real t) { return vehicle.all_loads(x, t); };
  const Real dt = c.time.step;
  for (int n = 0; n < c.time.steps; ++n) {
    const Real t = n * dt;
    law.begin_step(t + dt, dt, read_vehicle(motion_sample(s, initial, f.origin)));
    s = advance_rk4(vehicle.body(), s, t, dt, BodyLoads{}, BodyLoads{}, loads).state;
    const EulerAngles turned =
        euler_from_quaternion(quaternion_from_rotation(initial.transpose() * rotation_matrix(s.attitude())));
    motion.write(n + 1, t + dt, s, turned, vehicle.loads(s), 1, 0.0);
    const suboff::Deflections& a = law.angles();
    if (controls) controls->write(n + 1, t + dt, a.rudder, a.stern_planes, a.sail_planes, law.pitch_command());
  }
  return {c.time.steps, std::chrono::duration<Real>(std::chrono::steady_clock::now() - started).count()};
}

}  // namespace narwhal
