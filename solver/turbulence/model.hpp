#pragma once
// Turbulence models (NUMERICS §8): the interface the driver sees, and run-time
// selection by name.
//
// A model advances its own variables with the mean flow frozen ("loosely coupled",
// §8.6): the driver calls `advance` after every mean-flow iteration, after every
// multigrid cycle or after every fine-level smoothing step of a cycle (the model's
// `coupling`); `advance` ends by writing the effective viscosity nu = 1/Re + nu_t
// into the flow field, which the next mean-flow step (and its coarse levels) uses.
// Loose coupling keeps the mean-flow 4x4 blocks and their tuned kernels; the
// coupling error is a lag of one step, gone at convergence. How the coupling and the
// model's smoother were chosen: turbulence/DESIGN.md.
//
// Usage (case file):
//   [turbulence]
//   model = "sa"                 # `narwhal list-models` prints the valid names
//   freestream_nut_ratio = 3.0   # SA: nu_tilde/nu in the free stream (TMR: 3)
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "implicit/physical_time.hpp"
#include "mesh/block.hpp"
#include "parallel/communicator.hpp"
#include "physics/flow.hpp"
#include "turbulence/nonlinear_stress.hpp"
#include "turbulence/wall_distance.hpp"

namespace narwhal {

// The start of a run (turbulence/DESIGN.md, "the start"): a robust scheme from the
// uniform initial state until the wall forces have settled, then the settings' own
// scheme. The low-Re k-epsilon models' fast scheme (model in the smoothing, full
// Newton steps) diverges or finds the laminar plate solution from a uniform start;
// the robust one (relaxed, once per cycle) finds the turbulent one but converges its
// tail slowly. The forces settle when the boundary layers have formed, whatever the
// case; the switch waits for that, not for a cycle count.
struct TurbulenceStart {
  std::string coupling;            // cycle or smoothing; empty: the model's default
  std::optional<Real> relaxation;  // unset: the model's default
  std::optional<int> iterations;   // unset: the model's default
  // The start ends when, over the last `window` cycles, no wall force has moved by
  // more than this times the largest group's force; 0: no start (unset: the model's
  // default).
  std::optional<Real> force_span;
  int window = 25;
};

struct TurbulenceSettings {
  std::string model = "laminar";
  Real freestream_nut_ratio = 3.0;  // SA: nu_tilde_inf / nu; two-equation models: nu_t_inf / nu
  Real intensity = 0.001;           // free-stream turbulence intensity Tu (k-based models, §8.7)
  std::optional<int> iterations;    // model iterations per update; unset: the model's default (with_model_defaults)
  int sgs_iterations = 8;           // symmetric Gauss-Seidel pairs per model iteration (scalar blocks: cheap)
  // Relaxation of the model's linear equations: "lines" (line Gauss-Seidel in each
  // block's stiffest direction) or "points". When a multigrid run updates the model:
  // "cycle" (after every cycle) or "smoothing" (after every fine-level smoothing
  // step). Empty: the model's default (with_model_defaults).
  std::string smoother, coupling;
  Real cfl_max = 1.0e4;             // cap of the model's pseudo-time CFL (follows the mean flow's below it)
  // Under-relaxation of the model's update; unset: the model's default
  // (with_model_defaults). Full steps let the once-per-cycle coupling with point relaxation oscillate with
  // period 2 (TMR plate, coarse grids at any CFL and finer grids with well-converged
  // SGS); 0.7 removed it in every case measured.
  std::optional<Real> relaxation;
  // Largest factor by which k, epsilon or omega may grow in one step (positivity
  // halves a step that would make them negative). Where production dwarfs destruction
  // (a start from uniform flow puts S ~ U/d_1 in the wall cells: P/eps ~ 1e6 in the
  // 96 x 96 duct) the point-implicit step is about k P/eps and overflowed within two
  // iterations (measured). The cap is inactive at convergence but changes the path:
  // with 10 the TMR plates (SST, LS, MK) converge to the uncapped solutions (Cf equal
  // to 6e-6); with 2 MK's converged to another solution, with local Cf spikes of
  // +9 % (its y+ damping makes the discrete solution non-unique).
  Real max_growth = 10.0;
  // Sustained free stream (Spalart & Rumsey 2007, AIAA J. 45(10)): every cell gains the
  // negative of the model's point source at the free-stream values in a uniform flow
  // (two-equation models: k gains its ambient destruction, epsilon or omega theirs), so
  // that a uniform free stream is an exact solution and its turbulence reaches a body
  // 15 lengths away undecayed instead of dying out on the way (a low-Re k-epsilon's
  // boundary layers then turn turbulent as the free stream's do). Near a body the
  // added terms are the size of the ambient destruction, small beside the boundary
  // layer's.
  bool sustain_freestream = false;
  // SST's wall value of omega, 60 nu / (beta_1 dy1^2) (Menter 1994): dy1 the wall cell's
  // height ("cell_height", the first node off the wall of a vertex-centred grid: its skin
  // friction does not depend on the wall cells' y+ up to 1), or the distance of its centre
  // ("cell_centre", 4 times the value, close to OpenFOAM's omegaWallFunction, for
  // comparisons with simpleFoam). Why and the measurements: solver/turbulence/DESIGN.md.
  std::string omega_wall = "cell_height";
  // Baldwin-Lomax: F_max from the first peak (Degani-Schiff cut-off, for bodies at
  // incidence with off-body vortices) instead of the line's global maximum.
  bool degani_schiff = false;
  NonlinearCoefficients nonlinear;  // quadratic-stress coefficients of the non-linear k-epsilon (§8.5)
  TurbulenceStart start;            // the start's scheme and when it ends
};

struct TurbulenceNorms {
  Real l2[2] = {0.0, 0.0};  // RMS of R/V per variable
};

class TurbulenceModel {
 public:
  virtual ~TurbulenceModel() = default;
  virtual std::string name() const = 0;
  virtual int num_variables() const = 0;
  virtual std::string variable_name(int m) const = 0;
  virtual std::string cgns_name(int m) const = 0;  // CGNS SIDS data-array name
  // Free stream everywhere (or keep restart values when `keep` and sized).
  virtual void initialize(const Grid& g, FlowField& f, const FlowParams& fp, bool keep) = 0;
  // One loosely coupled update at the pseudo-time CFL of the mean flow.
  virtual TurbulenceNorms advance(Grid& g, FlowField& f, const FlowParams& fp, Real cfl) = 0;
  // The update's under-relaxation and iterations per call from now on (the start's
  // scheme and the converging one, TurbulenceStart).
  virtual void set_update(Real relaxation, int iterations) = 0;
  // nu = 1/Re + nu_t from the model's variables (flow ghosts filled).
  virtual void update_viscosity(const Grid& g, FlowField& f, const FlowParams& fp) = 0;
  // Cell eddy viscosity nu_t (nondimensional) for output.
  virtual Real eddy_viscosity(const FlowField& f, const FlowParams& fp, int ib, const Index3& c) const = 0;
  // Where variable m's residual of the latest update is largest ("block 'b' cell
  // (i, j, k), k equation: |R|/V = ..."); empty for models without equations.
  // Collective over `comm`.
  virtual std::string describe_largest_residual(const Grid& /*g*/, int /*m*/, const Communicator& /*comm*/) const {
    return "";
  }
  // A dual-time run's physical-time term (the finest level's, holding the old levels):
  // the transport models add their variables' share to each update (§6.1, §8.6);
  // algebraic models have no variables. nullptr: steady.
  virtual void use_physical_time(const PhysicalTimeTerm* /*term*/) {}
  // The grid's walls moved relative to its cells (a control surface turned, the grid
  // deformed about it): what the model keeps of the geometry (wall distances) made again.
  // A rigid motion of the whole grid needs no call.
  virtual void walls_moved(const Grid& /*g*/) {}
};

struct TurbulenceModelInfo {
  std::string name, summary;
  // Defaults of TurbulenceSettings::smoother and ::coupling. The low-Re k-epsilon
  // models keep points; they couple inside the smoothing after their start (their
  // plate solutions depend on the iteration's path, and from a uniform start the
  // fast scheme reaches the laminar one: turbulence/DESIGN.md).
  std::string smoother = "points", coupling = "cycle";
  // Default of TurbulenceSettings::relaxation: 0.7, with which no plate or duct run
  // oscillates; SST takes full steps (TMR plate levels 35 to 273: 208, 199, 197 and
  // 144 cycles against 298, 291, 333 and 164), SA does not (full steps oscillate
  // with period 2 on the 35 level and take 86 cycles instead of 21 on the 69).
  Real relaxation = 0.7;
  // Default of TurbulenceSettings::iterations (linearize, relax, update per call):
  // 1; SST 2, whose k residual decides its convergence. TMR plate levels 35 to 273
  // with 1, 2, 3: 208/102/65, 199/95/69, 197/143/105, 144/121/101 cycles; wall time
  // equal on the 137 level, 1.13x (2) and 1.30x (3) on the 273 (medians of three).
  // SA's cycles grow with more (137 level: 28, 35, 41).
  int iterations = 1;
  // Defaults of TurbulenceSettings::start: none (force_span 0) but for the low-Re
  // k-epsilon models (model.cpp).
  TurbulenceStart start{"cycle", 0.7, 1, 0.0, 25};
};

// The entry of that model name (nullptr when unknown).
const TurbulenceModelInfo* find_turbulence_model(const std::string& name);

// The settings with every scheme choice left open (smoother, coupling, relaxation,
// iterations, and those of the start) taken from the model's TurbulenceModelInfo; the one place these defaults resolve
// (the case reader and the models' constructors both call it).
TurbulenceSettings with_model_defaults(TurbulenceSettings s);

// Every selectable model, "laminar" (none) first.
const std::vector<TurbulenceModelInfo>& turbulence_models();

// The model of that name on this grid (wall distance computed here), or nullptr
// for "laminar"; an unknown name throws, listing the valid ones.
// `comm`: the ranks the grid's blocks are distributed over; the transport models gather
// the wall faces' friction velocities over it each iteration.
std::unique_ptr<TurbulenceModel> make_turbulence_model(const TurbulenceSettings& s, const Grid& g,
                                                       const Communicator& comm);

}  // namespace narwhal
