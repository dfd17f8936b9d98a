#pragma once
// Flow-solver parameters and the per-block flow fields.
#include <functional>
#include <vector>

#include "core/types.hpp"
#include "fields/ghost_array.hpp"
#include "mesh/block.hpp"
#include "physics/muscl.hpp"
#include "physics/volume_source.hpp"

namespace narwhal {

// §4.3: Full = §4.2 complete stress; ThinLayer = Laplacian form in all directions (TL-all).
enum class ViscousForm { Inviscid, ThinLayer, Full };

struct FlowParams {
  Real beta = 5.0;          // artificial compressibility (§0.2, §13.2)
  Real reynolds = 1.0e5;    // Re = U L / nu
  MusclParams muscl;
  ViscousForm viscous = ViscousForm::Full;
  VolumeSources sources;  // volume sources of the residual (physics/volume_source.hpp)
  // The exact state of a manufactured solution (§12.2), for Dirichlet patches; empty when unused.
  std::function<State(const Vec3&)> exact;
};

// Transported turbulence variables of a cell (up to two; models use the first n).
using TurbState = Eigen::Matrix<Real, 2, 1>;

struct FlowField {
  std::vector<GhostArray<State>> Q;   // [p, u, v, w] per cell, two ghost layers
  std::vector<GhostArray<Real>> nu;   // effective viscosity nu_e = (1 + nut_hat)/Re (§0.2)
  std::vector<GhostArray<TurbState>> turb;  // turbulence model variables (empty: none)
  // Non-linear part of the Reynolds stress tau_NL (§1.1, §8.5) per cell, two ghost
  // layers; empty unless the turbulence model has one. Enters the viscous face flux
  // explicitly (face average, not in the Jacobian, §4.1).
  std::vector<GhostArray<Mat3>> tau_nl;

  void allocate(const Grid& g, const FlowParams& fp, const State& init);
  // Q alone: a time level kept for a restart (gathered and written as Q is).
  void allocate_states(const Grid& g, const State& init);
  // turb: one zeroed array per block of g (a transport model's two variables), ghosts too.
  void allocate_turbulence(const Grid& g);
};

}  // namespace narwhal
