#pragma once
// The case file (TOML) as typed option structs, one per module, and the grid it
// describes. Every key is documented in README.md ("Case file").
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "config/propulsor_config.hpp"
#include "control/autopilot.hpp"
#include "control/control_schedule.hpp"
#include "control/zigzag.hpp"
#include "implicit/newton.hpp"
#include "mesh/block.hpp"
#include "mesh/appended_suboff.hpp"
#include "mesh/body_of_revolution.hpp"
#include "mesh/generators.hpp"
#include "mesh/setup.hpp"
#include "motion/coupled_body.hpp"
#include "motion/prescribed_motion.hpp"
#include "multigrid/fas.hpp"
#include "physics/flow.hpp"
#include "physics/manufactured.hpp"
#include "turbulence/model.hpp"

namespace narwhal {

struct FilePatch {
  int block = 0;  // 0-based
  int side = 0;
  Index3 lo{0, 0, 0}, hi{0, 0, 0};  // hi < 0: the whole face in that direction
  std::string label;
  std::string key;                       // "grid.patch[i]", for messages
  std::array<std::string, 3> range_key;  // the case key of each given range, for messages
};

struct GridConfig {
  std::string type;  // flat_plate | box | perturbed_box | body_of_revolution | appended_suboff | plot3d | cgns
  FlatPlateSpec plate;
  BodyGridSpec body;
  AppendedSuboffSpec appended;
  std::array<std::vector<Real>, 3> box_nodes;  // box: node coordinates per direction
  int perturbed_cells = 8;
  Real perturbed_amplitude = 0.04;
  std::string grid_file;                // plot3d, cgns
  std::vector<FilePatch> file_patches;  // patches the file does not carry (all of a Plot3D grid's)
  Index3 split{1, 1, 1};
  bool split_rotate = false;
  int coarsen = 0;  // remove every other grid line this many times (nested grid families)
};

struct PeriodicConfig {
  std::string a, b;
  std::optional<Vec3> translation;
  Vec3 axis = Vec3::UnitX();
  Real angle_deg = 0.0;
};

struct SolverConfig {
  NewtonSettings newton;
  MultigridSettings multigrid;  // levels = 1: single grid
  int max_iterations = 1000;
  Real residual_drop = 1e-10;      // converged when |R| / |R_0| falls below
  // The turbulence model's residuals' drop (against the largest each has had) that
  // convergence waits for; 0: residual_drop. A model residual with a floor in a few cells
  // while the forces have settled (the appended hulls' k) is judged by force_tolerance.
  Real turbulence_drop = 0.0;
  Real turbulence_target() const { return turbulence_drop > 0.0 ? turbulence_drop : residual_drop; }
  Real divergence_factor = 1e4;    // diverged when |R| / |R_0| exceeds
  // Diverged, too, when |R| exceeds the lowest it has been in this run by this factor: a
  // run whose residual had fallen 1e4-fold can otherwise regrow 1e8-fold, its state long
  // ruined, before divergence_factor notices. The converging ladder runs regrow at most 245-fold
  // (a turbulent duct's start).
  Real regrowth_factor = 1e3;
  // A steady run that diverges (either factor above, a non-finite state, sweeps that no CFL
  // cut saves) returns to its state at the lowest mean-flow residual so far and goes on
  // with the CFL ceiling halved, at most this many times (app/retreat.hpp; 0: it stops at
  // the first divergence). A run that never diverges is unchanged by it.
  int retreats = 3;
  // Stalled when the convergence measure has not fallen by stall_factor for
  // stall_window iterations (app/stall_detector.hpp; 0: never). 1000: well above the
  // longest such stretch of a ladder run that went on to converge (turbulence/DESIGN.md,
  // "Stall detection").
  int stall_window = 1000;
  Real stall_factor = 2.0;
  // Convergence also waits for the wall forces to settle (app/force_steadiness.hpp):
  // their span over the last force_window iterations within force_tolerance of the
  // largest force (0: residuals alone decide).
  Real force_tolerance = 0.0;
  int force_window = 5;
  bool invariant_shortcut = true;  // skip the cancelling faces of one-cell invariant layers (physics/invariant_direction.hpp)
};

// [time]: physical time by dual time stepping (NUMERICS §6.1, §6.7); without the table a
// run is steady. Each physical step sub-iterates in pseudo time (Newton-SGS or FAS
// cycles) until |R*| / |R*_0| of the step falls below subiteration_drop, within
// [min_subiterations, max_subiterations].
struct TimeConfig {
  enum class Scheme { Steady, Bdf1, Bdf2 };
  Scheme scheme = Scheme::Steady;
  Real step = 0.0;  // dt in units of L / U
  int steps = 0;    // physical steps to take
  // CFL of the local pseudo-time term inside a step (§6.6); infinite: none, the physical
  // time term alone makes the diagonal (§6.2's default for unsteady runs).
  Real pseudo_cfl = std::numeric_limits<Real>::infinity();
  Real subiteration_drop = 1e-2;
  int min_subiterations = 1;
  int max_subiterations = 10;
  // A step also ends once the wall forces and moments change by less than this between
  // sub-iterations (relative to the largest force component over the groups): on grids
  // whose steady residual has a floor (the appended SUBOFF's) a step's residual cannot
  // drop far below where it started, while the loads the body moves by have settled.
  Real force_change = 0.0;
  bool unsteady() const { return scheme != Scheme::Steady; }
};

struct OutputConfig {
  int restart_interval = 100;
  Real reference_area = 1.0;
  Real reference_length = 1.0;
  Vec3 moment_centre = Vec3::Zero();
};

// [motion] type = "free": the body's own equations (NUMERICS §11) coupled to the flow
// (motion/coupled_body.hpp). Everything in the flow's units (fluid density 1, lengths
// in L, velocities in U, NUMERICS §0.2) once read: a case in SI units is converted.
struct FreeBodySpec {
  MassProperties mass;
  AccelerationOptions options;
  CouplingSettings coupling;
  Vec3 origin = Vec3::Zero();            // O in grid coordinates at t = 0 (moments are taken about it)
  Vec3 velocity = Vec3::Zero();          // of O at t = 0, grid axes
  Vec3 angular_velocity = Vec3::Zero();  // at t = 0, grid axes
  std::vector<BallastChange> ballast;    // [[motion.ballast]]: tanks blown or flooded in time
  TrimSpec trim;                         // motion.trim: the loads at release balanced by trim weights
};

struct CaseConfig {
  std::string file, text, title;
  GridConfig grid;
  FlowParams flow;
  State initial = State::Zero();
  // Unit free stream: +x, or from flow.angle_of_attack / flow.drift_angle (body nose at
  // -x of the grid; NUMERICS §0.1 body axes x_B = -x, y_B = -y, z_B = z).
  Vec3 free_stream = Vec3::UnitX();
  std::map<std::string, PatchBc> bcs;
  std::vector<PeriodicConfig> periodic;
  SolverConfig solver;
  TimeConfig time;
  std::optional<PrescribedMotionSpec> motion;  // [motion] prescribed: the grid moves (dual-time runs)
  std::optional<FreeBodySpec> free_body;       // [motion] free: it moves as the body's equations say
  std::optional<ControlScheduleSpec> controls;  // [controls]: control surfaces turned in time (a moving grid)
  std::optional<AutopilotSettings> autopilot;   // [autopilot]: depth, pitch and heading held by the surfaces
  std::optional<ZigzagSettings> zigzag;         // [zigzag]: the rudders or stern planes reversed at an attitude
  bool grid_moves() const { return motion.has_value() || free_body.has_value(); }
  OutputConfig output;
  TurbulenceSettings turbulence;
  Vec3 body_force = Vec3::Zero();  // constant momentum source per unit volume (drives periodic ducts)
  Real bulk_velocity = 0.0;        // > 0: the body force is adjusted to this bulk velocity (physics/flow_rate.hpp)
  std::optional<PropulsorConfig> propulsor;  // [propulsor]: a body-force propulsor (NUMERICS §9)
  bool manufactured = false;
  ManufacturedSolution mms;
  // Blocks are cut into pieces as if for this many ranks (0: the ranks of the run).
  // Runs on different rank counts with the same value use the same blocks, and their
  // answers agree bit for bit (parallel/reduction.hpp).
  int split_for = 0;
};

// `overrides` are "dotted.key=value" assignments applied on top of the file.
CaseConfig load_case(const std::string& path, const std::vector<std::string>& overrides = {});

// The water's velocity far from a vehicle: the far field's (or inflow's) velocity, the
// free stream when the case gives none.
Vec3 far_water_velocity(const CaseConfig& c);
CaseConfig parse_case(const std::string& text, const std::string& display_name, const std::string& base_dir,
                      const std::vector<std::string>& overrides = {});

// Builds the grid (generator or import), applies BCs by label, connects periodic
// pairs and free faces, computes the metrics and checks the result. With
// balance_ranks > 1 the blocks are first cut until they share out over that many
// ranks within 5 % (parallel/partition.hpp), on multigrid-aligned cuts.
Grid build_grid(const CaseConfig& c, int balance_ranks = 1);

// build_grid in its two parts, for a run that keeps the case's blocks beside their
// pieces (or a manoeuvre that rebuilds both) without generating them twice:
//   const Grid generated = generate_grid(c);
//   Grid pieces = finish_grid(c, generated, ranks), whole = finish_grid(c, generated);
// generate_grid: the generator's (or the file's) blocks with their patches, split by
// grid.split; finish_grid: the rest (cut for ranks, BCs, connected, metrics, coarsened).
Grid generate_grid(const CaseConfig& c);
Grid finish_grid(const CaseConfig& c, Grid generated, int balance_ranks = 1);

}  // namespace narwhal
