#pragma once
// Turning a generated or imported grid into a ready-to-run one: BC types by
// patch label, periodic pairs, automatic 1-to-1 connection, geometry and checks.
#include <string>

#include "mesh/block.hpp"

namespace narwhal {

struct PatchBc {
  BcType type = BcType::Wall;
  Vec3 velocity = Vec3::Zero();
  Real pressure = 0.0;
  bool body_surface = false;  // Patch::body_surface (implied for walls)
};

// Applies `bc` to every patch labelled `label`; returns how many patches matched.
int assign_bc(Grid& g, const std::string& label, const PatchBc& bc);

// Connects free faces, checks the patch cover, builds ghost nodes and metrics,
// and checks that every cell volume is positive.
void finalize_grid(Grid& g);

}  // namespace narwhal
