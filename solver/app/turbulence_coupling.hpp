#pragma once
// How a run drives its turbulence model (NUMERICS §8.6, loosely coupled): one model
// update after every mean-flow step (coupling "cycle", and every single-grid run),
// or, in a multigrid run with coupling "smoothing", one after every fine-level
// smoothing step through the multigrid's hook. The run and the benchmarks share it,
// so that what is timed is what runs.
#include <memory>

#include "multigrid/fas.hpp"
#include "turbulence/model.hpp"

namespace narwhal {

class TurbulenceCoupling {
 public:
  // Makes the model of `s` (none for laminar), initializes its variables (kept when
  // `keep_state`, a restart) and the eddy viscosity, and attaches it to `mg` (may be
  // null) when its coupling asks for that. `g`, `f` and `fp` outlive this object.
  TurbulenceCoupling(const TurbulenceSettings& s, Grid& g, FlowField& f, const FlowParams& fp, Multigrid* mg,
                     bool keep_state);
  TurbulenceCoupling(const TurbulenceCoupling&) = delete;  // the hook holds `this`
  TurbulenceCoupling& operator=(const TurbulenceCoupling&) = delete;

  TurbulenceModel* model() const { return model_.get(); }

  // After a mean-flow step taken at pseudo-time CFL `cfl`: the model's update when it
  // is not inside the cycle. The norms of the model's last update either way.
  TurbulenceNorms after_mean_flow_step(Real cfl);

 private:
  Grid& g_;
  FlowField& f_;
  const FlowParams& fp_;
  std::unique_ptr<TurbulenceModel> model_;
  bool in_cycle_ = false;
  TurbulenceNorms last_;
};

}  // namespace narwhal
