#include "app/turbulence_coupling.hpp"

#include "bc/boundary.hpp"

namespace narwhal {

TurbulenceCoupling::TurbulenceCoupling(const TurbulenceSettings& s, Grid& g, FlowField& f, const FlowParams& fp,
                                       Multigrid* mg, bool keep_state)
    : g_(g), f_(f), fp_(fp), model_(make_turbulence_model(s, g)) {
  if (!model_) return;
  model_->initialize(g_, f_, fp_, keep_state);
  fill_ghosts(g_, f_, fp_);
  model_->update_viscosity(g_, f_, fp_);
  if (mg && with_model_defaults(s).coupling == "smoothing") {
    in_cycle_ = true;
    mg->set_fine_smoothing_hook([this](Real cfl) { last_ = model_->advance(g_, f_, fp_, cfl); });
  }
}

TurbulenceNorms TurbulenceCoupling::after_mean_flow_step(Real cfl) {
  if (model_ && !in_cycle_) last_ = model_->advance(g_, f_, fp_, cfl);
  return last_;
}

}  // namespace narwhal
