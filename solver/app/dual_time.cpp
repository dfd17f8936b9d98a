#include "app/dual_time.hpp"

#include <utility>

namespace narwhal {

DualTime::DualTime(const Grid& g, const TimeConfig& tc)
    : tc_(tc),
      term_(g, true),
      q_n_(owned_cell_arrays(g, State(State::Zero()))),
      q_nm1_(q_n_),
      vol_n_(owned_cell_arrays(g, Real(0.0))),
      vol_nm1_(vol_n_) {}

void DualTime::begin_step(const Grid& g, const FlowField& f) {
  std::swap(q_n_, q_nm1_);
  std::swap(vol_n_, vol_nm1_);
  std::swap(turb_n_, turb_nm1_);
  if (!f.turb.empty() && turb_n_.empty()) {
    turb_n_ = owned_cell_arrays(g, TurbState(TurbState::Zero()));
    turb_nm1_ = turb_n_;
  }
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    // V^n: the volumes of the grid the state was reached on (before this step moves it).
    for_each_cell(b, [&](int i, int j, int k) {
      q_n_[ib](i, j, k) = f.Q[ib](i, j, k);
      vol_n_[ib](i, j, k) = b.vol(i, j, k);
      if (!turb_n_.empty()) turb_n_[ib](i, j, k) = f.turb[ib](i, j, k);
    });
  }
  term_.set_step(tc_.step, coefficients_of_step(step_ + 1));
  term_.set_old_levels(g, vol_n_, q_n_, vol_nm1_, q_nm1_, turb_n_, turb_nm1_);
  previous_step_ = tc_.step;
  ++step_;
  time_ += tc_.step;
}

BdfCoefficients DualTime::coefficients_of_step(int n) const {
  // Steps of one size so far (time.step): omega = 1.
  return tc_.scheme == TimeConfig::Scheme::Bdf2 && n > 1 ? BdfCoefficients::bdf2(1.0) : BdfCoefficients::bdf1();
}

void DualTime::save_previous(const Grid& g, FlowField& f) const {
  if (!turb_n_.empty() && f.turb.size() != g.blocks.size()) f.allocate_turbulence(g);
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    if (g.owns(ib))
      for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
        f.Q[ib](i, j, k) = q_n_[ib](i, j, k);
        if (!turb_n_.empty()) f.turb[ib](i, j, k) = turb_n_[ib](i, j, k);
      });
}

void DualTime::restore(const Grid& g, const FlowField& previous, int step, Real time) {
  if (!previous.turb.empty() && turb_n_.empty()) {
    turb_n_ = owned_cell_arrays(g, TurbState(TurbState::Zero()));
    turb_nm1_ = turb_n_;
  }
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    for_each_cell(b, [&](int i, int j, int k) {
      q_n_[ib](i, j, k) = previous.Q[ib](i, j, k);
      vol_n_[ib](i, j, k) = b.vol(i, j, k);
      if (!previous.turb.empty()) turb_n_[ib](i, j, k) = previous.turb[ib](i, j, k);
    });
  }
  step_ = step;
  time_ = time;
  previous_step_ = step > 0 ? tc_.step : 0.0;
  if (step > 0) term_.set_step(tc_.step, coefficients_of_step(step));
}

}  // namespace narwhal
