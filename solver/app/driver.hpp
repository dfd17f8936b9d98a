#pragma once
// One steady run from a case file to its outputs (the contract the harness reads).
#include <array>
#include <optional>
#include <utility>
#include <vector>
#include <string>

#include "app/retreat.hpp"
#include "config/case_config.hpp"

namespace narwhal {

struct RunOptions {
  std::string out_dir = "run";
  std::optional<std::string> restart;
  std::optional<int> max_iterations;  // overrides solver.max_iterations
  bool progress = false;              // live progress line (only on a terminal)
};

// Stalled: the residuals stopped falling (solver.stall_window, app/stall_detector.hpp).
// Completed: a dual-time run that took all its physical steps.
enum class RunStatus { Converged, MaxIterations, Stalled, Diverged, Completed };
const char* to_string(RunStatus s);

struct RunSummary {
  RunStatus status = RunStatus::MaxIterations;
  int iterations = 0;
  Real wall_seconds = 0.0;
  Real residual_drop = 1.0;
  // Each equation's drop against the largest residual it has had (p, u, v, w; 0 for an
  // equation that never had a residual), and the turbulence model's variables' drops
  // measured the same way (name, drop).
  std::array<Real, 4> equation_drops{1.0, 1.0, 1.0, 1.0};
  std::vector<std::pair<std::string, Real>> turbulence_drops;
  Real turbulence_drop = 0.0;  // the largest of them: the one convergence waits for
  // The wall forces' span over the last solver.force_window iterations, relative to
  // the largest force (app/force_steadiness.hpp); < 0 when the run does not test it.
  Real force_span = -1.0;
  // The cycle that ended the turbulence model's start (TurbulenceStart); 0: no start
  // ended in this run's history.
  int turbulence_start_ended = 0;
  std::string message;
  // Cost of this process's run: wall seconds per iteration (or cycle) it ran, and its
  // peak resident memory (all ranks together) per cell of the grid.
  Real seconds_per_cycle = 0.0;
  Real peak_bytes_per_cell = 0.0;
  // Newton corrections of this process's run rejected on the finest level, each followed
  // by a CFL cut (NewtonSolver::relax_and_update).
  int cfl_cuts = 0;
  int cfl_ceiling_cuts = 0;
  std::vector<RetreatRecord> retreats;  // divergences the run went back from (app/retreat.hpp)  // sustained residual rises that lowered the CFL ceiling (implicit/cfl_rise_guard.hpp)
};

RunSummary run_case(const CaseConfig& c, const RunOptions& opt);

// Builds FlowParams from the case (manufactured-solution hooks included).
FlowParams flow_params(const CaseConfig& c);

}  // namespace narwhal
