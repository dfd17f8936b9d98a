#pragma once
// `narwhal simulate` (issue 19's cheap simulator): a case's manoeuvre flown by a
// manoeuvring model (manoeuvring/manoeuvring_model.hpp) instead of the flow, in seconds:
// the vehicle of its [motion] (type free: mass, gravity, free degrees of freedom, ballast,
// trim), its control law ([controls], [autopilot], [zigzag]: control/control_law.hpp) and
// its [time] steps; the propulsor's thrust from the case's open-water curve at the model's
// rotation rate, wake fraction and thrust deduction. Each step is one RK4 step with every
// load evaluated at each stage (no flow to interpolate). It writes motion.csv and
// controls.csv as the CFD run does (positions and velocities relative to the grid, in
// which the water moves at the far field's velocity), so that the harness reads both the
// same way and overlays them.
#include <optional>
#include <string>

#include "config/case_config.hpp"
#include "manoeuvring/manoeuvring_model.hpp"

namespace narwhal {

// A model file (TOML): [coefficients] (ManoeuvringCoefficients' names, absent ones 0) and
// an optional [propulsion] table: rps (n L / U, the self-propulsion point's),
// wake_fraction (w_T) and thrust_deduction (t), which the propulsor then needs.
struct ManoeuvringModel {
  ManoeuvringCoefficients coefficients;
  std::optional<Real> rps;
  Real wake_fraction = 0.0;
  Real thrust_deduction = 0.0;
};
// Throws Error naming the file and the key on a bad or unknown entry.
ManoeuvringModel load_manoeuvring_model(const std::string& path);

struct SimulationSummary {
  int steps = 0;
  Real seconds = 0.0;  // wall time
};
// Throws Error when the case has no free body or no [time], or the model propels a case
// without [propulsor].
SimulationSummary simulate(const CaseConfig& c, const ManoeuvringModel& model, const std::string& out_dir);

}  // namespace narwhal
