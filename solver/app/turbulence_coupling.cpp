#include "app/turbulence_coupling.hpp"

#include <fmt/format.h>

#include "bc/boundary.hpp"

namespace narwhal {

TurbulenceCoupling::TurbulenceCoupling(const TurbulenceSettings& s, Grid& g, FlowField& f, const FlowParams& fp,
                                       Multigrid* mg, bool from_restart,
                                       const Communicator& comm)
    : g_(g),
      f_(f),
      fp_(fp),
      settings_(with_model_defaults(s)),
      model_(make_turbulence_model(s, g, comm)),
      start_forces_(settings_.start.window, *settings_.start.force_span) {
  if (!model_) return;
  model_->initialize(g_, f_, fp_, from_restart);
  fill_ghosts(g_, f_, fp_);
  model_->update_viscosity(g_, f_, fp_);
  if (mg) {
    has_cycle_ = true;
    mg->set_fine_smoothing_hook([this](Real cfl) {
      if (in_cycle_) last_ = model_->advance(g_, f_, fp_, cfl);
    });
  }
  starting_ = !from_restart && start_forces_.enabled();
  use_current_scheme();
}

void TurbulenceCoupling::restore(const TurbulenceStartState& state) {
  if (!model_) return;
  starting_ = state.starting;
  start_ended_at_ = state.ended_at;
  start_forces_.restore(state.window, state.components);
  use_current_scheme();
}

void TurbulenceCoupling::use_current_scheme() {
  if (starting_)
    use_scheme(settings_.start.coupling, *settings_.start.relaxation, *settings_.start.iterations);
  else
    use_scheme(settings_.coupling, *settings_.relaxation, *settings_.iterations);
}

void TurbulenceCoupling::use_scheme(const std::string& coupling, Real relaxation, int iterations) {
  in_cycle_ = has_cycle_ && coupling == "smoothing";
  model_->set_update(relaxation, iterations);
}

TurbulenceNorms TurbulenceCoupling::after_mean_flow_step(Real cfl) {
  if (model_ && !in_cycle_) last_ = model_->advance(g_, f_, fp_, cfl);
  return last_;
}

std::string TurbulenceCoupling::observe_forces(int iteration, const std::map<std::string, ForceCoefficients>& forces) {
  if (!model_ || !starting_) return "";
  start_forces_.observe(forces);
  if (!start_forces_.steady()) return "";
  starting_ = false;
  start_ended_at_ = iteration;
  use_scheme(settings_.coupling, *settings_.relaxation, *settings_.iterations);
  return fmt::format(
      "the wall forces have settled (span {:.1e} over {} cycles): the {} model's start ends at cycle {}; from here "
      "{}, relaxation {:g}, {} iteration{} per update",
      start_forces_.span(), start_forces_.window(), model_->name(), iteration,
      in_cycle_ ? "inside the smoothing" : "once per cycle", *settings_.relaxation, *settings_.iterations,
      *settings_.iterations == 1 ? "" : "s");
}

TurbulenceStartState TurbulenceCoupling::start_state() const {
  TurbulenceStartState st;
  st.starting = starting_;
  st.ended_at = start_ended_at_;
  if (starting_) st.window = start_forces_.state();
  st.components = starting_ ? start_forces_.components() : 0;
  return st;
}

}  // namespace narwhal
