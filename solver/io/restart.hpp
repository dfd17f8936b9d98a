#pragma once
// restart.h5: everything needed to continue a run bit-for-bit (the state of every
// block, the iteration count, the SER reference norm), with provenance (version,
// git SHA, the case file text, a grid fingerprint).
#include <string>

#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

struct RestartInfo {
  int iteration = 0;
  Real reference_norm = -1.0;
  Real wall_seconds = 0.0;
  Real turbulence_reference[2] = {-1.0, -1.0};  // first residuals of the turbulence model's variables
  Real body_force = -1.0;  // magnitude of a flow-rate-controlled body force (< 0: none)
};

// Writes atomically (temporary file + rename) so a crash never leaves a torn restart.
void write_restart(const std::string& path, const Grid& g, const FlowField& f, const RestartInfo& info,
                   const std::string& case_text);

// Reads the state into `f` (allocated for `g`); the block names and sizes must match.
RestartInfo read_restart(const std::string& path, const Grid& g, FlowField& f);

}  // namespace narwhal
