#include "physics/flow.hpp"

namespace narwhal {

void FlowField::allocate(const Grid& g, const FlowParams& fp, const State& init) {
  Q.clear();
  nu.clear();
  for (const auto& b : g.blocks) {
    Q.emplace_back(b.ni, b.nj, b.nk, kGhost, init);
    nu.emplace_back(b.ni, b.nj, b.nk, kGhost, 1.0 / fp.reynolds);
  }
}

void FlowField::allocate_states(const Grid& g, const State& init) {
  Q.clear();
  nu.clear();
  for (const auto& b : g.blocks) Q.emplace_back(b.ni, b.nj, b.nk, kGhost, init);
}

void FlowField::allocate_turbulence(const Grid& g) {
  turb.clear();
  for (const auto& b : g.blocks) turb.emplace_back(b.ni, b.nj, b.nk, kGhost, TurbState::Zero());
}

}  // namespace narwhal
