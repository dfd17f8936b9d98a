#pragma once
// The run's propulsor and what steers it (issue 19): the body-force propulsor of [propulsor]
// (NUMERICS §9), its advance speed measured in the flow after every cycle when the case asks
// for it, and an rpm controller that moves the rotation rate to the self-propulsion point
// (thrust = the walls' resistance along the thrust axis). What a restart carries of them,
// and what run.json reports.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "config/case_config.hpp"
#include "motion/grid_motion.hpp"
#include "motion/rigid_body.hpp"
#include "parallel/communicator.hpp"
#include "physics/wall_forces.hpp"
#include "propulsion/body_force_propulsor.hpp"
#include "propulsion/rpm_controller.hpp"

namespace narwhal {

class PropulsionControl {
 public:
  // The operating point at the towing speed, the disk normalised on g's cells. `comm`: the
  // ranks sharing g; the constructor, after_cycle, walls_moved and after_subiteration are
  // collective over it.
  PropulsionControl(const CaseConfig& c, const Grid& g, const Communicator& comm);

  std::shared_ptr<VolumeSource> source() const { return propulsor_; }
  const BodyForcePropulsor& propulsor() const { return *propulsor_; }

  // After cycle `cycle`: the advance speed from the flow (collective), then the
  // controller's step on the resistance of the wall forces (coefficients on
  // output.reference_area, as measure_forces leaves them on every rank).
  void after_cycle(int cycle, const Grid& g, const FlowField& f,
                   const std::map<std::string, ForceCoefficients>& forces);
  // A dual-time run on a moving grid: the disk carried with the grid (pose m about
  // `pivot`), and the surge speed from the motion, u_B = (v_p - u_water).e_a with v_p
  // the disk centre's velocity (NUMERICS §9.1).
  void follow(const RigidMotionSample& m, const Vec3& pivot);
  // The grid deformed near the disk (control surfaces turned): its cells found again on
  // g's present nodes (collective).
  void walls_moved(const Grid& g) { propulsor_->normalise(comm_, g); }
  // After a dual-time sub-iteration: the advance speed from the flow, when the case
  // measures it (collective). The rotation rate stays.
  void after_subiteration(const Grid& g, const FlowField& f);
  // The propulsor's loads on the vehicle (§9.5), grid (earth) axes, about `origin`, in
  // flow units (rho = 1).
  BodyLoads vehicle_loads(const Vec3& origin) const;

  // Whether the rotation rate has settled (always, without a controller).
  bool settled() const { return !rpm_ || rpm_->settled(); }
  Real resistance() const { return resistance_; }  // along the thrust axis, when last measured

  std::vector<Real> checkpoint() const;
  void restore(const std::vector<Real>& state);

  nlohmann::ordered_json report(const Vec3& moment_centre) const;
  std::string describe() const;

 private:
  Communicator comm_;
  std::shared_ptr<BodyForcePropulsor> propulsor_;
  std::optional<RpmController> rpm_;
  Real reference_area_ = 1.0;
  Vec3 water_ = Vec3::Zero();  // the water's velocity far from the vehicle (the far field's)
  Real resistance_ = 0.0;  // the walls' resistance along the thrust axis when last measured
};

}  // namespace narwhal
