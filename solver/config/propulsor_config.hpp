#pragma once
// [propulsor]: a body-force propulsor (NUMERICS §9; propulsion/body_force_propulsor.hpp),
// its open-water curve read when the case is, so that a missing or malformed table is an
// input error naming the key before any iteration.
#include <memory>
#include <optional>
#include <string>

#include "propulsion/body_force_propulsor.hpp"
#include "propulsion/rpm_controller.hpp"

namespace narwhal {

class ConfigReader;

struct PropulsorConfig {
  PropulsorSpec spec;
  std::shared_ptr<const OpenWaterCurve> curve;
  // [propulsor.rpm_control]: the rotation rate moved to the self-propulsion point.
  std::optional<RpmControlSettings> rpm_control;
};

// Nothing without a [propulsor] table. Paths are relative to the folder of the file that
// gives them (ConfigReader::file_path).
std::optional<PropulsorConfig> read_propulsor(const ConfigReader& r);

}  // namespace narwhal
