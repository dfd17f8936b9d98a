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

}  // namespace narwhal
