#pragma once
// A ceiling on the SER CFL (§6.6) that a sustained residual rise lowers.
//
// SER measures the residual against the first one, so once that has fallen by
// CFL_max / CFL_0 the CFL stays at CFL_max whatever the residual does next: a mode the
// iteration amplifies at that CFL grows until the state is ruined, long before the
// residual has climbed back to its start (implicit/DESIGN.md: a 436 k-cell appended SUBOFF
// member, 3-fold per cycle at CFL 1e3, k and omega non-finite four cycles later).
// The guard arms once the CFL has reached its cap (CFL_max, or the ceiling): below it SER
// answers a rise itself, CFL_0 |R^0| / |R^m| falling as the residual climbs, and the early
// rises of a start (a turbulent duct's 64-fold by its fourth iteration, a TMR plate's as
// its SST layer forms) must not cap the rest of the run (implicit/DESIGN.md). Armed,
// a residual that rose in two successive iterations, by more than the rise limit in all,
// lowers the ceiling to the CFL of the moment times the inverse of that rise, and at
// least halves it (kCut). The ceiling then stays: deterministic, and no cycling between a stable
// and an unstable CFL. After a cut the next one waits for two new rises, so that the
// lower CFL shows its effect first. One spike, or a slow wander, cuts nothing.
#include <algorithm>
#include <array>
#include <limits>

#include "core/types.hpp"

namespace narwhal {

class CflRiseGuard {
 public:
  // Why 1.5: implicit/DESIGN.md. Infinite: off.
  static constexpr Real kDefaultRiseLimit = 1.5;
  static constexpr Real kCut = 0.5;

  explicit CflRiseGuard(Real rise_limit = kDefaultRiseLimit) : rise_limit_(rise_limit) {}

  // What a restart carries: the ceiling (infinite: none) and the residual norms of the
  // last two iterations since the last cut (< 0: none), older first.
  struct State {
    Real ceiling = std::numeric_limits<Real>::infinity();
    std::array<Real, 2> recent{-1.0, -1.0};
    bool armed = false;
  };

  // The CFL reached its cap: from now on sustained rises lower the ceiling.
  void arm() { s_.armed = true; }

  // This iteration's residual norm and the CFL the last iteration used; a rise never
  // lowers the ceiling below `floor`. True when the ceiling was lowered (only when armed).
  bool observe(Real norm, Real last_cfl, Real floor) {
    const auto [older, last] = s_.recent;
    const bool sustained = older > 0.0 && last > older && norm > last && norm > rise_limit_ * older;
    if (sustained && s_.armed && last_cfl > 0.0) {
      // Never raised: a retreat (lower_ceiling) may have put it below the floor.
      s_.ceiling = std::min(s_.ceiling, std::max(floor, last_cfl * std::min(kCut, older / norm)));
      s_.recent = {-1.0, -1.0};
      ++cuts_;
      return true;
    }
    s_.recent = {last, norm};
    return false;
  }

  // A ceiling imposed from outside (a retreat from a divergence, app/retreat.hpp): it only
  // lowers the ceiling, arms the guard and starts a new watch.
  void lower_ceiling(Real ceiling) {
    s_.ceiling = std::min(s_.ceiling, ceiling);
    s_.armed = true;
    s_.recent = {-1.0, -1.0};
  }

  Real ceiling() const { return s_.ceiling; }
  int cuts() const { return cuts_; }  // in this run (not restored)
  const State& state() const { return s_; }
  void restore(const State& s) { s_ = s; }

 private:
  Real rise_limit_;
  State s_;
  int cuts_ = 0;
};

}  // namespace narwhal
