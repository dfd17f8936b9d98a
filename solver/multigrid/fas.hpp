#pragma once
// FAS multigrid over blocks (NUMERICS §7.2–7.3) with Newton–SGS smoothing on
// every level: V (gamma = 1) or W (gamma = 2) cycles, volume-weighted solution
// restriction, summed residual restriction, trilinear (index-space) prolongation
// of corrections with homogeneous-BC ghosts, first-order fluxes on coarse levels.
// The forcing term carries everything a dual-time outer loop would add.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "implicit/newton.hpp"
#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

struct MultigridSettings {
  int levels = 3;          // requested; fewer when the grid does not allow it
  int gamma = 2;           // 1: V-cycle, 2: W-cycle
  int pre_smooth = 1;      // nu_1
  int post_smooth = 1;     // nu_2
  int coarse_smooth = 2;   // nu_c on the coarsest level
  bool injection = false;  // prolongation by injection instead of trilinear
  bool reuse_jacobian = true;  // post-smoothing keeps the pre-smoothing block matrices
  int jacobian_interval = 1;   // block matrices reassembled every this many cycles
  // The fewest cells a coarse level keeps in any halved direction of a block: a level
  // whose blocks would keep fewer is not built. A body grid's pole squares two cells
  // across on the coarsest level gave corrections that made its nose diverge
  // (mesh/DESIGN.md, "The root cause"); 1 builds every level the grid allows.
  int min_cells = 1;
};

class Multigrid {
 public:
  // `fine` and `field` are the finest level (owned by the caller); `comm`: the ranks its
  // blocks are distributed over, every level's solver collective over it.
  Multigrid(Grid& fine, FlowField& field, const FlowParams& fp, const NewtonSettings& ns, MultigridSettings ms,
            const Communicator& comm);

  // One cycle; returns the norms of the finest-level residual at its start. The CFL
  // follows switched evolution relaxation on the finest level, or is given (dual time).
  IterationNorms cycle();
  IterationNorms cycle_with_cfl(Real cfl);

  // Dual time stepping (§7.3): the finest level solves R* with `finest` (which holds
  // the old time levels); each coarse level gets a term of its own, without them (they
  // cancel in the forcing), whose step and coefficients follow the finest's every cycle.
  void use_physical_time(const PhysicalTimeTerm* finest);

  int levels() const { return static_cast<int>(levels_.size()); }
  const std::string& level_note() const { return note_; }
  NewtonSolver& finest() { return *levels_[0].solver; }
  // Level l's grid (0: the finest, the caller's): a moving grid moves every level's nodes.
  Grid& grid(int l) { return *levels_[static_cast<std::size_t>(l)].grid; }

  // Called after every smoothing iteration on the finest level, with its CFL: a
  // loosely coupled turbulence model updated inside the cycle, so that the mean
  // flow's post-smoothing already sees the model's update (TurbulenceSettings::coupling).
  void set_fine_smoothing_hook(std::function<void(Real cfl)> hook) { after_fine_smoothing_ = std::move(hook); }

 private:
  struct Level {
    Grid* grid = nullptr;
    std::unique_ptr<Grid> owned;
    FlowField* field = nullptr;
    std::unique_ptr<FlowField> owned_field;
    FlowParams fp;
    std::unique_ptr<NewtonSolver> solver;
    std::vector<GhostArray<State>> forcing, q0, correction;
    std::unique_ptr<PhysicalTimeTerm> time;  // coarse levels in a dual-time run
  };
  IterationNorms run_cycle(IterationNorms n);
  const PhysicalTimeTerm* finest_time_ = nullptr;
  Real visit(int l, Real cfl, const IterationNorms* fresh, bool frozen);
  Real smooth(int l, int iterations, Real cfl, const IterationNorms* fresh = nullptr, bool reuse = false);
  bool frozen_ = false;
  void restrict_to(int l);
  void prolong_from(int l);

  std::vector<Level> levels_;
  MultigridSettings ms_;
  std::string note_;
  int cycles_ = 0;
  std::function<void(Real)> after_fine_smoothing_;
};

}  // namespace narwhal
