#pragma once
// What the manoeuvres' controllers (control/autopilot.hpp, control/zigzag.hpp) read of the
// vehicle at a step's start. Marine axes (x_B forward, z_B down).
#include "core/types.hpp"
#include "motion/grid_motion.hpp"

namespace narwhal {

struct VehicleReading {
  Real depth = 0.0, depth_rate = 0.0;      // along gravity, from the start
  Real pitch = 0.0, pitch_rate = 0.0;      // theta (nose up > 0), its rate
  Real heading = 0.0, heading_rate = 0.0;  // psi (nose to starboard > 0), its rate
};

// What the controllers read of a vehicle in rigid motion m (pivot: its origin as built):
// depth along the grid's +z (NUMERICS §0.1: z_B down; body axes at release
// grid_axes.hpp's), the Euler angles of its turn since release and their rates.
VehicleReading read_vehicle(const RigidMotionSample& m);

}  // namespace narwhal
