#pragma once
// Depth, pitch and heading autopilots for a submarine's control surfaces (issue 19).
// Sampled once per physical step from the body's state at the step's start, each loop is
// a PidController (control/pid_controller.hpp) whose output is a surface's angle, kept
// within its limits and rate:
//   * heading -> rudders;
//   * pitch -> stern planes; with a depth command the pitch command comes from an outer
//     depth loop (limited to the steepest pitch the case allows), so that the vehicle
//     changes depth by pitching, as submarines do at speed;
//   * depth -> sail planes as well, when the case asks for them (their force acts near
//     the centre: a heave force rather than a moment).
//
// Signs. The vehicle's axes are marine (x_B forward, z_B down): pitch > 0 raises the nose,
// heading > 0 turns it to starboard, depth grows downwards. The surfaces' angles are
// suboff_geometry.hpp's (Gertler & Hagen): a rudder > 0 puts its trailing edge to port
// and turns the nose to port; stern planes > 0 (trailing edges down) lift the stern and
// put the nose down; sail planes > 0 lift the sail. So every loop's surface angle is minus
// its PID's output, and the gains in the case are positive.
#include <optional>
#include <vector>

#include "control/pid_controller.hpp"
#include "control/vehicle_reading.hpp"
#include "mesh/suboff_geometry.hpp"

namespace narwhal {

struct AutopilotSettings {
  // Commands: unset leaves the loop off (its surface keeps the angle it has).
  std::optional<Real> heading;       // psi to hold (rad)
  std::optional<Real> pitch;         // theta to hold (rad), without a depth command
  std::optional<Real> depth_change;  // how much deeper to go (> 0: down), from the start
  PidSettings heading_loop;          // -> rudder (rad)
  PidSettings pitch_loop;            // -> stern planes (rad)
  PidSettings depth_loop;            // -> the pitch command (rad), limits: the steepest pitch
  std::optional<PidSettings> sail_plane_loop;  // depth -> sail planes (rad), when set
};

class Autopilot {
 public:
  // Throws Error when a depth command has neither loop to act through, or a command has
  // no loop.
  explicit Autopilot(AutopilotSettings s);

  // The surfaces' angles for the step of length dt that begins with the vehicle at `now`;
  // `present`: the angles they have (those no loop commands are kept).
  suboff::Deflections command(const VehicleReading& now, Real dt, const suboff::Deflections& present);
  Real pitch_command() const { return pitch_command_; }  // the depth loop's (or the fixed one)

  // The loops' integrals and outputs, for restarts.
  std::vector<Real> checkpoint() const;
  void restore(const std::vector<Real>& values);  // throws Error on a list of another length

 private:
  AutopilotSettings s_;
  PidController heading_, pitch_, depth_;
  std::optional<PidController> sail_;
  Real pitch_command_ = 0.0;
};

}  // namespace narwhal
