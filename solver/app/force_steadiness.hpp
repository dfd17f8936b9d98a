#pragma once
// Whether a run's wall forces have settled: the second half of its convergence test
// when `solver.force_tolerance` > 0. A residual drop says how far the equations are
// from being satisfied, not how far the forces are from their converged values; a
// run that converges fast (a few cycles per decade) can meet its residual drop while
// its drag still moves in the fifth digit. The forces count as steady when, over the
// last `window` iterations, no force coefficient of any wall group has moved by more
// than `tolerance` times the largest group's force (max - min over the window).
#include <deque>
#include <map>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "physics/wall_forces.hpp"

namespace narwhal {

class ForceSteadiness {
 public:
  // tolerance <= 0: always steady (the test is off).
  ForceSteadiness(int window, Real tolerance) : window_(window), tolerance_(tolerance) {}

  // This iteration's force coefficients (every group, in the map's order).
  void observe(const std::map<std::string, ForceCoefficients>& forces);

  bool enabled() const { return tolerance_ > 0.0; }
  bool steady() const { return !enabled() || (static_cast<int>(samples_.size()) >= window_ && span() <= tolerance_); }

  // max - min over the window of every force component, over the largest group's
  // force magnitude in the latest sample; infinite before the window has filled.
  Real span() const;

  int window() const { return window_; }
  // Values per sample (3 per wall group); 0 before the first.
  int components() const { return samples_.empty() ? 0 : static_cast<int>(samples_.back().size()); }
  Real tolerance() const { return tolerance_; }

  // The window's samples, flattened oldest first (restarts carry them, so that a
  // resumed run stops where the uninterrupted one did), and back.
  std::vector<Real> state() const;
  void restore(const std::vector<Real>& flat, int components_per_sample);

 private:
  int window_;
  Real tolerance_;
  std::deque<std::vector<Real>> samples_;  // per sample: 3 force components per group
};

}  // namespace narwhal
