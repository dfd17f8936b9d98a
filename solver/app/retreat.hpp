#pragma once
// Retreat from a divergence (CaseConfig solver.retreats).
//
// A steady run keeps, in memory, its state at the lowest mean-flow residual so far. When it
// diverges it goes back there and on with the CFL ceiling at half the lower of that state's
// CFL and the ceiling it had (implicit/cfl_rise_guard.hpp), instead of stopping: the
// appended SUBOFF starts at incidence grow a mode while the CFL still climbs (the rise guard
// arms only at the cap), and their states are ruined some ten cycles later, long after the
// residual's lowest. Halving: that lowest was reached at its CFL and the mode grew above
// it, so half leaves a margin; a further divergence halves again. A run that never
// diverges follows exactly the path it had without this: the copy is only read by a retreat.
#include <map>
#include <string>
#include <vector>

#include "io/restart.hpp"
#include "physics/flow.hpp"
#include "physics/wall_forces.hpp"

namespace narwhal {

// The state a retreat returns to: what a restart carries (io/restart.hpp), the
// variables and the monitors and controllers, with the forces they were measured with.
// The viscosity is derived again on the return, as a restart derives it.
struct LastGoodState {
  int iteration = 0;
  std::vector<GhostArray<State>> Q;
  std::vector<GhostArray<TurbState>> turb;
  RestartInfo info;
  std::map<std::string, ForceCoefficients> forces;
};

// One retreat, as run.json reports it.
struct RetreatRecord {
  int diverged_at = 0;   // the iteration that diverged
  int back_to = 0;       // the iteration whose state the run went back to
  Real cfl_ceiling = 0;  // the CFL ceiling from there on
  std::string reason;    // what the divergence was
};

// The factor on the CFL ceiling at each retreat (see above).
inline constexpr Real kRetreatCflFactor = 0.5;

}  // namespace narwhal
