#pragma once
// How a run drives its turbulence model (NUMERICS §8.6, loosely coupled): one model
// update after every mean-flow step (coupling "cycle", and every single-grid run),
// or, in a multigrid run with coupling "smoothing", one after every fine-level
// smoothing step through the multigrid's hook. A run may begin with the start's
// scheme (TurbulenceStart) and turn to the settings' own once its wall forces have
// settled. The run and the benchmarks share this class, so that what is timed is
// what runs.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "app/force_steadiness.hpp"
#include "multigrid/fas.hpp"
#include "physics/wall_forces.hpp"
#include "turbulence/model.hpp"

namespace narwhal {

// Where the start stands; restarts carry it so that a resumed run turns where the
// uninterrupted one did.
struct TurbulenceStartState {
  bool starting = false;       // still in the start
  int ended_at = 0;            // the cycle that ended it (0: not ended, or no start)
  std::vector<Real> window{};  // the force window (ForceSteadiness::state)
  int components = 0;          // values per sample of `window`
};

class TurbulenceCoupling {
 public:
  // Makes the model of `s` (none for laminar), initializes its variables (kept when
  // `from_restart`) and the eddy viscosity, and attaches it to `mg` (may be null). A run
  // from a uniform state begins with the start when the settings have one; a restart
  // continues where restore() says. `g`, `f` and `fp` outlive this object; `comm` is the
  // ranks `g` is distributed over.
  TurbulenceCoupling(const TurbulenceSettings& s, Grid& g, FlowField& f, const FlowParams& fp, Multigrid* mg,
                     bool from_restart, const Communicator& comm);
  TurbulenceCoupling(const TurbulenceCoupling&) = delete;  // the hook holds `this`
  TurbulenceCoupling& operator=(const TurbulenceCoupling&) = delete;

  TurbulenceModel* model() const { return model_.get(); }

  // After a mean-flow step taken at pseudo-time CFL `cfl`: the model's update when it
  // is not inside the cycle. The norms of the model's last update either way.
  TurbulenceNorms after_mean_flow_step(Real cfl);

  // The wall forces after cycle `iteration`: ends the start when they have settled.
  // Returns what changed, to print ("" when nothing did).
  std::string observe_forces(int iteration, const std::map<std::string, ForceCoefficients>& forces);

  TurbulenceStartState start_state() const;
  // The start's state as a restart or a retreat (app/retreat.hpp) kept it, with its update scheme.
  void restore(const TurbulenceStartState& state);

 private:
  // The update's scheme: `in_cycle` (the model in the smoothing) and its relaxation
  // and iterations.
  void use_scheme(const std::string& coupling, Real relaxation, int iterations);
  void use_current_scheme();  // the start's scheme while starting, else the model's

  Grid& g_;
  FlowField& f_;
  const FlowParams& fp_;
  TurbulenceSettings settings_;
  std::unique_ptr<TurbulenceModel> model_;
  bool has_cycle_ = false;  // a multigrid run: "smoothing" can apply
  bool in_cycle_ = false;
  bool starting_ = false;
  int start_ended_at_ = 0;
  ForceSteadiness start_forces_;
  TurbulenceNorms last_;
};

}  // namespace narwhal
