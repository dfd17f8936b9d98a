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
#include "physics/wall_forces.hpp"
#include "propulsion/body_force_propulsor.hpp"
#include "propulsion/rpm_controller.hpp"

namespace narwhal {

class PropulsionControl {
 public:
  // The operating point at the towing speed, the disk normalised on g's cells (collective
  // over the ranks sharing g).
  PropulsionControl(const CaseConfig& c, const Grid& g);

  std::shared_ptr<VolumeSource> source() const { return propulsor_; }
  const BodyForcePropulsor& propulsor() const { return *propulsor_; }

  // After cycle `cycle`: the advance speed from the flow (collective over the ranks sharing
  // g), then the controller's step on the resistance of the wall forces (coefficients on
  // output.reference_area, as measure_forces leaves them on every rank).
  void after_cycle(int cycle, const Grid& g, const FlowField& f,
                   const std::map<std::string, ForceCoefficients>& forces);
  // Whether the rotation rate has settled (always, without a controller).
  bool settled() const { return !rpm_ || rpm_->settled(); }
  Real resistance() const { return resistance_; }  // along the thrust axis, when last measured

  std::vector<Real> checkpoint() const;
  void restore(const std::vector<Real>& state);

  nlohmann::ordered_json report(const Vec3& moment_centre) const;
  std::string describe() const;

 private:
  std::shared_ptr<BodyForcePropulsor> propulsor_;
  std::optional<RpmController> rpm_;
  Real reference_area_ = 1.0;
  Real resistance_ = 0.0;  // the walls' resistance along the thrust axis when last measured
};

}  // namespace narwhal
