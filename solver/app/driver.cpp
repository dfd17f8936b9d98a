#include "app/driver.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/control_surfaces.hpp"
#include "app/dual_time.hpp"
#include "app/force_steadiness.hpp"
#include "app/stall_detector.hpp"
#include "app/turbulence_coupling.hpp"
#include "bc/boundary.hpp"
#include "io/cgns_writer.hpp"
#include "io/monitors.hpp"
#include "io/output_directory.hpp"
#include "io/text_file.hpp"
#include "app/run_motion.hpp"
#include "motion/grid_axes.hpp"
#include "io/restart.hpp"
#include "parallel/communicator.hpp"
#include "parallel/distribution.hpp"
#include "physics/flow_rate.hpp"
#include "physics/invariant_direction.hpp"
#include "physics/wall_forces.hpp"
#include "app/propulsion_control.hpp"
#include "turbulence/model.hpp"
#include "version.hpp"

namespace narwhal {

const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::Converged: return "converged";
    case RunStatus::MaxIterations: return "max_iterations";
    case RunStatus::Stalled: return "stalled";
    case RunStatus::Diverged: return "diverged";
    case RunStatus::Completed: return "completed";
  }
  return "?";
}

FlowParams flow_params(const CaseConfig& c) {
  FlowParams fp = c.flow;
  const Vec3 g = c.body_force;
  if (c.manufactured) {
    const ManufacturedSolution ms = c.mms;
    fp.sources.push_back(position_source("manufactured solution's forcing",
                                         [ms, g](const Vec3& x) { return Vec3(ms.momentum_source(x) + g); }));
    fp.exact = [ms](const Vec3& x) { return ms.exact(x); };
  } else if (g.squaredNorm() > 0.0) {
    fp.sources.push_back(position_source("body force", [g](const Vec3&) { return g; }));
  }
  return fp;
}

namespace {

const char* viscous_name(ViscousForm v) {
  return v == ViscousForm::Full ? "full" : (v == ViscousForm::ThinLayer ? "thin-layer" : "inviscid");
}

// run.json: what the harness reads of a run. Non-finite numbers become null (valid JSON).
void write_run_json(const std::string& path, const CaseConfig& c, const Grid& g, const RunSummary& s,
                    const IterationNorms& last, const std::map<std::string, ForceCoefficients>& forces,
                    const Vec3& body_force, int ranks, const PropulsionControl* propulsion,
                    const CoupledBody* body) {
  nlohmann::ordered_json j;
  j["case"] = c.file;
  j["title"] = c.title;
  j["status"] = to_string(s.status);
  j["message"] = s.message;
  j["iterations"] = s.iterations;
  j["wall_seconds"] = s.wall_seconds;
  j["cells"] = g.cells();
  j["blocks"] = g.blocks.size();
  j["ranks"] = ranks;
  j["residual_drop"] = s.residual_drop;
  nlohmann::ordered_json drops = {{"p", s.equation_drops[0]}, {"u", s.equation_drops[1]},
                                  {"v", s.equation_drops[2]}, {"w", s.equation_drops[3]}};
  for (const auto& [name, d] : s.turbulence_drops) drops[name] = d;
  j["equation_drops"] = drops;  // each against the largest residual it has had
  j["turbulence_drop"] = s.turbulence_drop;
  if (s.force_span >= 0.0 && std::isfinite(s.force_span)) j["force_span"] = s.force_span;
  if (s.turbulence_start_ended > 0) j["turbulence_start_ended"] = s.turbulence_start_ended;
  j["cost"] = {{"seconds_per_cycle", s.seconds_per_cycle}, {"peak_bytes_per_cell", s.peak_bytes_per_cell}};
  j["cfl_cuts"] = s.cfl_cuts;
  j["cfl_ceiling_cuts"] = s.cfl_ceiling_cuts;
  j["retreats"] = nlohmann::ordered_json::array();
  for (const RetreatRecord& r : s.retreats)
    j["retreats"].push_back(
        {{"diverged_at", r.diverged_at}, {"back_to", r.back_to}, {"cfl_ceiling", r.cfl_ceiling}, {"reason", r.reason}});
  j["final_residual"] = {{"p", last.l2[0]}, {"u", last.l2[1]}, {"v", last.l2[2]}, {"w", last.l2[3]}};
  j["settings"] = {{"reynolds", c.flow.reynolds},
                   {"beta", c.flow.beta},
                   {"viscous", viscous_name(c.flow.viscous)},
                   {"muscl_kappa", c.flow.muscl.kappa},
                   {"muscl_phi", c.flow.muscl.phi},
                   {"cfl_start", c.solver.newton.cfl_start},
                   {"cfl_max", c.solver.newton.cfl_max},
                   {"cfl_growth", c.solver.newton.cfl_growth},
                   {"sgs_iterations", c.solver.newton.sgs_iterations},
                   {"max_iterations", c.solver.max_iterations},
                   {"residual_drop_target", c.solver.residual_drop},
                   {"multigrid_levels", c.solver.multigrid.levels},
                   {"multigrid_min_cells", c.solver.multigrid.min_cells},
                   {"multigrid_cycle", c.solver.multigrid.gamma == 2 ? "W" : "V"},
                   {"turbulence_model", c.turbulence.model},
                   {"turbulence_smoother", c.turbulence.smoother},
                   {"turbulence_coupling", c.turbulence.coupling},
                   {"turbulence_iterations", c.turbulence.iterations.value_or(0)},
                   {"turbulence_relaxation", c.turbulence.relaxation.value_or(0.0)},
                   {"turbulence_start_force_span", c.turbulence.start.force_span.value_or(0.0)},
                   {"turbulence_sustain_freestream", c.turbulence.sustain_freestream},
                   {"turbulence_omega_wall", c.turbulence.omega_wall},
                   {"retreats", c.solver.retreats},
                   {"stall_window", c.solver.stall_window},
                   {"stall_factor", c.solver.stall_factor},
                   {"turbulence_drop", c.solver.turbulence_target()},
                   {"force_tolerance", c.solver.force_tolerance},
                   {"force_window", c.solver.force_window}};
  j["body_force"] = {body_force[0], body_force[1], body_force[2]};
  if (propulsion) j["propulsor"] = propulsion->report(c.output.moment_centre);
  if (body && c.free_body->trim.any())  // flow units (rho = 1): weight, and its first moment along x_B
    j["trim"] = {{"weight", body->trim().weight}, {"first_moment", body->trim().first_moment}};
  nlohmann::ordered_json f = nlohmann::ordered_json::object();
  auto coefficients = [](const Vec3& force, const Vec3& moment) {
    return nlohmann::ordered_json{{"cfx", force[0]},  {"cfy", force[1]},  {"cfz", force[2]},
                                  {"cmx", moment[0]}, {"cmy", moment[1]}, {"cmz", moment[2]}};
  };
  for (const auto& [name, fc] : forces) {
    f[name] = coefficients(fc.force, fc.moment);
    f[name]["pressure"] = coefficients(fc.pressure_force, fc.pressure_moment);
    f[name]["friction"] = coefficients(fc.friction_force(), fc.friction_moment());
    // X, Y, Z and the roll, pitch and yaw moments K, M, N (motion/grid_axes.hpp).
    const Vec3 force = grid_to_body_axes(fc.force), moment = grid_to_body_axes(fc.moment);
    f[name]["body_axes"] = {{"X", force[0]},  {"Y", force[1]},  {"Z", force[2]},
                            {"K", moment[0]}, {"M", moment[1]}, {"N", moment[2]}};
  }
  j["forces"] = f;
  j["provenance"] = {{"version", kVersion}, {"git_sha", kGitSha}, {"compiler", kCompiler}, {"flags", kBuildFlags}};
  write_file_atomically(path, j.dump(2) + "\n");
}

}  // namespace

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// Residual monitors of the latest iteration: what convergence is judged on, what the
// history and run.json report, and what a restart carries so that a resumed run
// continues (or ends) exactly as the uninterrupted one.
struct Monitors {
  IterationNorms last;           // mean-flow residual norms of the latest iteration
  Real drop = 1.0;               // |R| / |R_0| of the mean flow
  // The lowest `drop` has been in this process's run: a resumed run measures regrowth
  // from where it resumed, so a restart into other conditions (another drift angle)
  // starts afresh rather than counting its first residual as a regrowth.
  Real lowest_drop = std::numeric_limits<Real>::infinity();
  // The largest residual each equation has had: its reference for the per-equation drop
  // (the first residual can be zero, as continuity's is from a uniform start).
  std::array<Real, kNumEq> reference_l2{-1.0, -1.0, -1.0, -1.0};
  std::vector<Real> turb_res;    // the turbulence model's residuals
  std::vector<Real> turb_ref;    // the largest each has had (its reference)
  Real turb_drop = 0.0;          // the largest drop of the model's residuals

  explicit Monitors(std::size_t turbulence_variables)
      : turb_res(turbulence_variables, 0.0), turb_ref(turbulence_variables, -1.0) {}

  void take_mean_flow(const IterationNorms& n, Real reference_norm) {
    last = n;
    drop = n.total / reference_norm;
    lowest_drop = std::min(lowest_drop, drop);
    for (int m = 0; m < kNumEq; ++m) reference_l2[m] = std::max(reference_l2[m], n.l2[m]);
  }
  std::array<Real, kNumEq> equation_drops() const {
    std::array<Real, kNumEq> d{};
    for (int m = 0; m < kNumEq; ++m) d[m] = reference_l2[m] > 0.0 ? last.l2[m] / reference_l2[m] : 0.0;
    return d;
  }
  // The turbulence variable m's drop, measured as equation_drops() measures theirs.
  Real turbulence_drop(std::size_t m) const { return turb_ref[m] > 0.0 ? turb_res[m] / turb_ref[m] : 0.0; }
  void take_turbulence(const TurbulenceNorms& n) {
    turb_drop = 0.0;
    for (std::size_t m = 0; m < turb_res.size(); ++m) {
      turb_res[m] = n.l2[m];
      // Measured against the largest residual the model has had: from a free-stream
      // start the first residual of k is tiny, and a drop relative to it would ask for
      // far more than the mean flow's criterion does.
      turb_ref[m] = std::max(turb_ref[m], turb_res[m]);
      turb_drop = std::max(turb_drop, turb_res[m] / std::max(turb_ref[m], 1e-300));
    }
  }
  void restore(const RestartInfo& info) {
    last.l2 = info.residual;
    last.total = info.residual_total;
    last.cfl = info.cfl;
    drop = info.residual_drop;
    reference_l2 = info.residual_reference;
    turb_drop = info.turbulence_drop;
    for (std::size_t m = 0; m < turb_res.size(); ++m) {
      turb_res[m] = info.turbulence_residual[m];
      turb_ref[m] = info.turbulence_reference[m];
    }
  }
  void store(RestartInfo& r) const {
    for (std::size_t m = 0; m < turb_ref.size(); ++m) {
      r.turbulence_reference[m] = turb_ref[m];
      r.turbulence_residual[m] = turb_res[m];
    }
    r.residual = last.l2;
    r.residual_total = last.total;
    r.cfl = last.cfl;
    r.residual_drop = drop;
    r.residual_reference = reference_l2;
    r.turbulence_drop = turb_drop;
  }
  bool converged(Real mean_flow_target, Real turbulence_target) const {
    return drop < mean_flow_target && turb_drop < turbulence_target;
  }
};

// How a physical step's sub-iterations ended.
struct StepConvergence {
  int subiterations = 0;
  Real drop = 1.0;             // |R*| / |R*_0| reached (the largest of the mean flow's and each turbulence variable's)
  Real coupling_change = 0.0;  // a free body's last velocity change
  Real force_change = 1.0;     // the wall forces' last change, relative (TimeConfig::force_change)
};

// The largest change of any wall group's force or moment coefficient between two
// measurements, relative to the largest force component of `now` (TimeConfig::force_change).
Real largest_force_change(const std::map<std::string, ForceCoefficients>& before,
                          const std::map<std::string, ForceCoefficients>& now) {
  Real scale = 0.0, change = 0.0;
  for (const auto& [name, fc] : now) {
    scale = std::max(scale, fc.force.cwiseAbs().maxCoeff());
    const auto b = before.find(name);
    if (b == before.end()) return 1.0;
    change = std::max({change, (fc.force - b->second.force).cwiseAbs().maxCoeff(),
                       (fc.moment - b->second.moment).cwiseAbs().maxCoeff()});
  }
  return scale > 0.0 ? change / scale : (change > 0.0 ? 1.0 : 0.0);
}

// One steady run, phase by phase: grids, output directory, restart, solvers, then
// iterations (step, monitors, convergence, checkpoint) and the final outputs.
class SteadyRun {
 public:
  SteadyRun(const CaseConfig& c, const RunOptions& opt)
      : c_(c), opt_(opt), comm_(Communicator::world()), root_(comm_.is_root()),
        max_it_(opt.max_iterations.value_or(c.solver.max_iterations)) {}

  RunSummary execute() {
    prepare_grids();
    prepare_output_directory();
    restore_state();
    build_solvers();
    open_monitors();
    announce();
    if (c_.time.unsteady())
      march();
    else
      iterate();
    finish();
    return s_;
  }

 private:
  // The case's own blocks (the layout of every file), and the blocks the run computes
  // on: cut into pieces until they share out over the ranks (parallel/partition.hpp).
  void prepare_grids() {
    split_for_ = c_.split_for > 0 ? c_.split_for : comm_.size();
    pieces_ = split_for_ > 1;
    Grid generated = generate_grid(c_);
    g_ = finish_grid(c_, generated, split_for_);
    if (pieces_) whole_ = finish_grid(c_, std::move(generated));
    distribute(g_, comm_.size(), comm_.rank());
    fp_ = flow_params(c_);
    if (c_.bulk_velocity > 0.0) {
      flow_rate_ = std::make_unique<FlowRateControl>(comm_, g_, c_.body_force, c_.bulk_velocity);
      fp_.sources = {position_source("flow-rate control", flow_rate_->source())};  // it adjusts the body force
    }
    add_propulsor();
    field_.allocate(g_, fp_, c_.initial);
  }

  // §9: the propulsor (app/propulsion_control.hpp), one more entry of the source list.
  void add_propulsor() {
    if (!c_.propulsor) return;
    propulsion_ = std::make_unique<PropulsionControl>(c_, g_, comm_);  // collective: the disk's cells on every rank
    fp_.sources.push_back(propulsion_->source());
  }

  // A run from a restart continues the directory's history; restarting from the
  // directory's own restart.h5 keeps that file as the last good state until the next.
  void prepare_output_directory() {
    continuing_ = opt_.restart.has_value();
    own_restart_ = continuing_ && restart_is_in(*opt_.restart, opt_.out_dir);
    if (root_) {
      out_dir_ = std::make_unique<OutputDirectory>(opt_.out_dir, continuing_, own_restart_);
      if (!out_dir_->cleared().empty())
        fmt::print("narwhal: removed the previous run's outputs from '{}' ({} files)\n", opt_.out_dir,
                   out_dir_->cleared().size());
    }
    comm_.barrier();
    restart_path_ = file("restart.h5");
  }

  // Every rank reads the restart (written in the case's layout) and keeps its pieces.
  void restore_state() {
    if (!opt_.restart) return;
    // A dual-time run also reads Q^{n-1} (restored into the time levels in march()).
    const bool unsteady = c_.time.unsteady();
    if (unsteady) restored_previous_.allocate_states(g_, c_.initial);
    if (pieces_) {
      FlowField w, w_previous;
      w.allocate(whole_, fp_, c_.initial);
      if (unsteady) w_previous.allocate_states(whole_, c_.initial);
      info_ = read_restart(*opt_.restart, whole_, w, c_.turbulence.model, unsteady ? &w_previous : nullptr);
      copy_between_layouts(g_, field_, whole_, w, false);
      if (unsteady) copy_between_layouts(g_, restored_previous_, whole_, w_previous, false);
    } else {
      info_ = read_restart(*opt_.restart, g_, field_, c_.turbulence.model, unsteady ? &restored_previous_ : nullptr);
    }
    if (info_.time_step > 0 && info_.time_step_size != c_.time.step)
      fail("{}: the run was written with time steps of {:g}; this case's time.step is {:g} (a BDF2 run continues "
           "with the step it had)", *opt_.restart, info_.time_step_size, c_.time.step);
    if (own_restart_) last_restart_ = info_.iteration;
  }

  // Single grid: one Newton-SGS iteration per step; multigrid: one FAS cycle. The
  // turbulence model is loosely coupled (§8.6): one update after every mean-flow
  // step, or with coupling "smoothing" after every fine-level smoothing step.
  void build_solvers() {
    // A moving grid may turn its invariant layers out of their plane (the shortcut is
    // decided once, on the grid as built).
    if (c_.solver.invariant_shortcut && !c_.grid_moves()) {
      const std::string note = mark_invariant_directions(g_, field_, fp_);
      if (!note.empty() && root_) fmt::print("narwhal: {}\n", note);
    }
    if (c_.solver.multigrid.levels > 1) {
      mg_ = std::make_unique<Multigrid>(g_, field_, fp_, c_.solver.newton, c_.solver.multigrid, comm_);
      if (!mg_->level_note().empty() && root_) fmt::print("narwhal: {}\n", mg_->level_note());
    } else {
      single_ = std::make_unique<NewtonSolver>(g_, field_, fp_, c_.solver.newton, comm_);
    }
    coupling_ = std::make_unique<TurbulenceCoupling>(c_.turbulence, g_, field_, fp_, mg_.get(),
                                                     opt_.restart.has_value(), comm_);
    turb_ = coupling_->model();
    fill_ghosts(g_, field_, fp_);
  }

  // Wall groups are known from the patches; forces appear in the history per group.
  void open_monitors() {
    for (const auto& [name, list] : wall_faces(g_, field_, fp_)) groups_.push_back(name);  // every rank: all groups
    for (int m = 0; turb_ && m < turb_->num_variables(); ++m) turb_names_.push_back(turb_->variable_name(m));
    monitors_ = Monitors(turb_names_.size());
    if (root_)
      history_ = std::make_unique<HistoryWriter>(file("history.csv"), groups_, turb_names_,
                                                 continuing_ ? std::optional<int>(info_.iteration) : std::nullopt);
    if (root_ && propulsion_)
      propulsor_csv_ = std::make_unique<PropulsorWriter>(
          file("propulsor.csv"), continuing_ ? std::optional<int>(info_.iteration) : std::nullopt);
    s_.iterations = info_.iteration;
    if (!opt_.restart) return;
    // The restored state's monitors are those of the iteration that wrote it; a run
    // resumed from the restart its converged end wrote has nothing left to do.
    restore_run_state(info_);
    measure_forces();
    // (A dual-time run has its steps to take, whatever state it starts from: a steady
    // run's converged end is where a release begins.)
    if (!c_.time.unsteady() && info_.iteration > 0 && converged()) s_.status = RunStatus::Converged;
  }

  // The monitors and every controller as `r` carries them (run_state() writes it): from a
  // restart, or from the state a retreat returns to. The controls of a dual-time run are
  // restored with its time levels (march()), as they turn the grid.
  void restore_run_state(const RestartInfo& r) {
    monitors_.restore(r);
    stall_.restore(r.stall_anchor, r.stall_anchor_iteration);
    force_steadiness_.restore(r.force_window, r.force_components);
    solver().restore_cfl_control(r.cfl_control);
    coupling_->restore({r.turbulence_starting, r.turbulence_start_ended, r.start_window, r.start_components});
    if (flow_rate_ && r.body_force > 0.0) flow_rate_->set_magnitude(r.body_force);
    if (propulsion_) propulsion_->restore(r.propulsor_state);
    s_.residual_drop = monitors_.drop;
  }

  void announce() const {
    if (opt_.progress || !root_) return;
    if (propulsion_) fmt::print("narwhal: {}\n", propulsion_->describe());
    if (c_.time.unsteady()) {
      fmt::print("narwhal: {} — {} blocks, {} cells{}, {} steps of {} ({}), up to {} {} each\n", c_.title,
                 g_.blocks.size(), g_.cells(), comm_.size() > 1 ? fmt::format(", {} ranks", comm_.size()) : std::string(),
                 c_.time.steps, c_.time.step, c_.time.scheme == TimeConfig::Scheme::Bdf2 ? "BDF2" : "BDF1",
                 c_.time.max_subiterations, mg_ ? "cycles" : "Newton iterations");
      return;
    }
    fmt::print("narwhal: {} — {} blocks, {} cells{}, up to {} {}\n", c_.title, g_.blocks.size(), g_.cells(),
               comm_.size() > 1 ? fmt::format(", {} ranks", comm_.size()) : std::string(), max_it_,
               mg_ ? fmt::format("{}-cycles on {} levels", c_.solver.multigrid.gamma == 2 ? "W" : "V", mg_->levels())
                   : std::string("iterations"));
  }

  void iterate() {
    started_ = Clock::now();
    while (s_.status == RunStatus::MaxIterations && s_.iterations < max_it_) {
      const int it = s_.iterations + 1;
      try {
        advance(it);
        if (s_.status == RunStatus::MaxIterations) {
          keep_last_good(it);
          if (c_.output.restart_interval > 0 && it % c_.output.restart_interval == 0) checkpoint(it);
        }
      } catch (const DivergenceError& e) {
        s_.status = RunStatus::Diverged;
        s_.message = fmt::format("iteration {}: {}", it, e.what());
      }
      if (s_.status == RunStatus::Diverged && retreat(it)) continue;
      if (s_.status != RunStatus::MaxIterations) break;
      show_progress(it);
    }
    // A resumed run that had nothing left to do has no residual of its own to locate.
    if (s_.status == RunStatus::MaxIterations && s_.iterations > info_.iteration &&
        monitors_.converged(c_.solver.residual_drop, c_.solver.turbulence_target()))
      s_.message = fmt::format("not converged: the residuals are down, the forces moved by {:.2e} of the largest over "
                               "the last {} iterations (solver.force_tolerance {:.1e})",
                               force_steadiness_.span(), force_steadiness_.window(), force_steadiness_.tolerance());
    else if (s_.status == RunStatus::MaxIterations && s_.iterations > info_.iteration)
      s_.message = fmt::format("not converged (mean-flow drop {:.2e}{}); {}", s_.residual_drop,
                               turb_ ? fmt::format(", turbulence drop {:.2e}", monitors_.turb_drop) : std::string(),
                               describe_slowest_equation());
    close_loop();
  }

  // One iteration (a cycle with multigrid): the update, forces, controllers, history, and
  // the verdict (s_.status).
  void advance(int it) {
    step();
    measure_forces();
    if (propulsion_) record_propulsion(it);
    force_steadiness_.observe(forces_);
    const std::string turned = coupling_->observe_forces(it, forces_);
    if (!turned.empty() && root_ && !opt_.progress) fmt::print("narwhal: {}\n", turned);
    if (flow_rate_) flow_rate_->update(g_, field_, faces_);
    if (history_) history_->write(it, elapsed(), monitors_.last, forces_, monitors_.turb_res);
    s_.iterations = it;
    s_.residual_drop = monitors_.drop;
    judge_convergence(it);
  }

  // The state at the lowest mean-flow residual so far, for a retreat (app/retreat.hpp).
  // Iteration it's residual is that of the state iteration it - 1 left (the candidate):
  // only now is that state known to be good. Its monitors are those of iteration it - 1,
  // as a restart written there would carry them. What is kept is what a restart keeps.
  void keep_last_good(int it) {
    if (c_.solver.retreats == 0) return;
    if (candidate_ && monitors_.drop <= monitors_.lowest_drop) std::swap(last_good_, candidate_);
    if (!candidate_) candidate_.emplace();
    candidate_->iteration = it;
    candidate_->Q = field_.Q;  // same sizes after the first: copied in place
    candidate_->turb = field_.turb;
    candidate_->info = run_state(it);
    candidate_->forces = forces_;
  }

  // After a divergence at iteration `it` (s_.message says what): back to the last good
  // state with the CFL ceiling lowered, unless solver.retreats are used up or there is
  // none. True when the run goes on.
  bool retreat(int it) {
    if (!last_good_ || static_cast<int>(s_.retreats.size()) >= c_.solver.retreats) return false;
    const LastGoodState& last = *last_good_;
    const Real ceiling = kRetreatCflFactor * std::min(last.info.cfl, solver().rise_guard().ceiling());
    return_to(last);
    solver().lower_cfl_ceiling(ceiling);
    s_.retreats.push_back({it, last.iteration, ceiling, s_.message});
    if (root_)
      fmt::print("{}narwhal: {}; back to the state of iteration {} (the lowest residual so far), the CFL at most "
                 "{:.3g} from here (retreat {} of solver.retreats {})\n",
                 opt_.progress ? "\n" : "", s_.message, last.iteration, ceiling, s_.retreats.size(),
                 c_.solver.retreats);
    *candidate_ = last;  // the next iteration's residual is that of this state again
    s_.iterations = it;  // the diverged iteration was work done: the count goes on
    s_.status = RunStatus::MaxIterations;
    s_.message.clear();
    return true;
  }

  // Back to `last` as a restart written there would bring the run back: its variables,
  // the viscosity derived from them, its monitors and controllers.
  void return_to(const LastGoodState& last) {
    field_.Q = last.Q;
    field_.turb = last.turb;
    derive_viscosity();
    restore_run_state(last.info);
    forces_ = last.forces;
  }

  // The eddy viscosity (and non-linear stress) of the variables as they are now, after
  // they were set or the grid moved other than by an iteration. (The next residual
  // evaluation fills the ghosts of the viscosity.)
  void derive_viscosity() {
    fill_ghosts(g_, field_, fp_);
    if (turb_) turb_->update_viscosity(g_, field_, fp_);
  }

  // The propulsor after an iteration (collective: its inflow, the controller's step on the
  // resistance), then propulsor.csv.
  void record_propulsion(int it) {
    propulsion_->after_cycle(it, g_, field_, forces_);
    write_propulsor_row(it);
  }

  void write_propulsor_row(int it) {
    if (!propulsor_csv_) return;
    const BodyForcePropulsor& p = propulsion_->propulsor();
    const PropulsorLoads& l = p.loads();
    propulsor_csv_->write(it, p.spec().rps, l.advance_speed, l.advance_ratio, l.thrust, l.torque,
                          propulsion_->resistance());
  }

  // A dual-time run (§6.8): physical steps, each moving the time levels on and
  // sub-iterating in pseudo time on R* = 0 (§6.7), its forces written to steps.csv.
  void march() {
    started_ = Clock::now();
    dual_time_ = std::make_unique<DualTime>(g_, c_.time);
    if (mg_)
      mg_->use_physical_time(&dual_time_->term());
    else
      single_->set_physical_time(&dual_time_->term());
    if (turb_) turb_->use_physical_time(&dual_time_->term());
    if (root_)
      steps_ = std::make_unique<StepsWriter>(file("steps.csv"), groups_,
                                             continuing_ ? std::optional<int>(info_.time_step) : std::nullopt);
    prepare_motion();
    restore_time_levels();
    try {
      while (s_.status == RunStatus::MaxIterations && dual_time_->step() < c_.time.steps) {
        dual_time_->begin_step(g_, field_);
        move_grids();
        for (auto& source : fp_.sources) source->at_time(dual_time_->time());
        const StepConvergence done = sub_iterate();
        if (s_.status == RunStatus::Diverged) break;
        if (steps_) steps_->write(dual_time_->step(), dual_time_->time(), done.subiterations, done.drop, forces_);
        if (motion_csv_) write_motion_row(done);
        if (controls_csv_) {
          const suboff::Deflections& a = controls_->angles();
          controls_csv_->write(dual_time_->step(), dual_time_->time(), a.rudder, a.stern_planes, a.sail_planes,
                               controls_->pitch_command());
        }
        if (c_.output.restart_interval > 0 && dual_time_->step() % c_.output.restart_interval == 0)
          checkpoint(s_.iterations);
        show_step_progress(done.subiterations, done.drop);
      }
      if (s_.status == RunStatus::MaxIterations) s_.status = RunStatus::Completed;
    } catch (const DivergenceError& e) {
      s_.status = RunStatus::Diverged;
      s_.message = fmt::format("step {}, iteration {}: {}", dual_time_->step(), s_.iterations + 1, e.what());
    }
    close_loop();
  }

  // Every grid the run keeps moves together (app/run_motion.hpp): each multigrid level
  // and the case's own blocks when the run computes on pieces of them (moved last: the
  // files' layout). A free body starts from the flow's loads on the initial state.
  void prepare_motion() {
    if (!c_.grid_moves()) return;
    std::vector<Grid*> grids;
    if (mg_)
      for (int l = 0; l < mg_->levels(); ++l) grids.push_back(&mg_->grid(l));
    else
      grids.push_back(&g_);
    if (pieces_) grids.push_back(&whole_);
    // The files describe the case's blocks: the whole when the run computes on pieces,
    // else the finest level (not the coarsest: its nodes sample a curved far field more
    // coarsely, and a restart's block extents would not match).
    motion_ = std::make_unique<RunMotion>(c_, grids, pieces_ ? grids.size() - 1 : 0);
    if (c_.controls || c_.autopilot || c_.zigzag) {
      controls_ = std::make_unique<ControlSurfaces>(c_, split_for_, mg_ ? mg_->levels() : 1, pieces_);
      if (controls_->start(*motion_)) walls_moved_pending_ = true;
      if (root_)
        controls_csv_ = std::make_unique<ControlsWriter>(file("controls.csv"),
                                                         continuing_ ? std::optional<int>(info_.time_step) : std::nullopt);
    }
    carry_propulsor();
    motion_->place_at_start();
    after_walls_moved();
    measure_forces();
    motion_->start(body_loads());
    if (root_ && motion_->free_body())
      motion_csv_ = std::make_unique<MotionWriter>(file("motion.csv"),
                                                   continuing_ ? std::optional<int>(info_.time_step) : std::nullopt);
  }

  // A dual-time restart continues at step n as if never stopped: the grids placed at
  // t^{n-1} give the time levels V^{n-1} (with Q^{n-1} from the file), then move to t^n
  // as step n moved them (the face speeds and swept volumes BDF2 goes on from).
  void restore_time_levels() {
    if (!opt_.restart || info_.time_step == 0) return;
    const int n = info_.time_step;
    if (controls_) {
      controls_->restore(info_.control_state);
      if (controls_->to_previous_level(*motion_)) walls_moved_pending_ = true;
    }
    if (motion_) motion_->place_at_previous_level(info_, c_.time.step);
    dual_time_->restore(g_, restored_previous_, n, info_.time);
    if (controls_ && controls_->to_present_level(*motion_)) walls_moved_pending_ = true;
    if (motion_) motion_->move_to_present_level(info_, c_.time.step, dual_time_->coefficients_of_step(n));
    carry_propulsor();
    after_walls_moved();
    restored_previous_ = FlowField{};
  }

  // The control surfaces turned (the grids deformed about them): what depends on where
  // the walls are made again on the grid's present nodes (collective: the propulsor's
  // disk cells).
  void after_walls_moved() {
    if (!walls_moved_pending_) return;
    walls_moved_pending_ = false;
    if (turb_) turb_->walls_moved(g_);
    if (propulsion_) propulsion_->walls_moved(g_);
  }

  // The propulsor's disk goes where the grid is, its surge speed the motion's (§9.1).
  void carry_propulsor() {
    if (propulsion_ && motion_) propulsion_->follow(motion_->sample(), motion_->pivot());
  }

  // §6.8 steps 1-2: the grids to the pose of t^{n+1} (a free body's predicted), their
  // metrics and face speeds; the eddy viscosity of Q^n made again on them. It was made
  // on the grid of t^n, with the face speeds there (a wall's ghost velocity): a restart
  // cannot rebuild those speeds without the step before, so nothing carries them over.
  void move_grids() {
    if (!motion_) return;
    const Real dt = dual_time_->step_size();
    // The surfaces' angles for t^{n+1}, from the vehicle at t^n (before it moves on).
    if (controls_ && controls_->begin_step(dual_time_->time(), dt, read_vehicle(motion_->sample()), *motion_))
      walls_moved_pending_ = true;
    motion_->begin_step(dual_time_->time() - dt, dt, dual_time_->term().coefficients());
    carry_propulsor();
    after_walls_moved();
    if (turb_) derive_viscosity();
  }

  // The flow's loads on a free body: every wall group's and the propulsor's (§9.5), in
  // grid (earth) axes, about the body origin, in flow units (the coefficients' reference
  // area and length undone).
  BodyLoads body_loads() const {
    const Real area = c_.output.reference_area, length = c_.output.reference_length;
    const Vec3 arm = moment_centre() - motion_->origin();
    BodyLoads total;
    for (const auto& [name, fc] : forces_) {
      const Vec3 f = 0.5 * area * fc.force;
      total.force += f;
      total.moment += 0.5 * area * length * fc.moment + arm.cross(f);
    }
    if (propulsion_) total += propulsion_->vehicle_loads(motion_->origin());
    return total;
  }

  // The point moments are reported about: the case's, moving with the body.
  Vec3 moment_centre() const { return motion_ ? motion_->now(c_.output.moment_centre) : c_.output.moment_centre; }

  void write_motion_row(const StepConvergence& done) {
    const CoupledBody& b = motion_->body();
    motion_csv_->write(dual_time_->step(), dual_time_->time(), b.state(), b.turn_since_release(b.state()),
                       b.flow_loads(), done.subiterations, done.coupling_change);
  }

  // One physical step's pseudo-time iterations (§6.7): until |R*| / |R*_0| falls below
  // time.subiteration_drop, at least min and at most max of them, and, with a free body,
  // until its motion has converged too (corrected after each, §11.7). Each iteration's
  // residual is that of the state entering it.
  StepConvergence sub_iterate() {
    Real first = 0.0;
    Real first_turbulence[2] = {0.0, 0.0};
    StepConvergence done;
    const bool free = motion_ && motion_->free_body();
    while (done.subiterations < c_.time.max_subiterations) {
      const int it = s_.iterations + 1;
      const Real cfl = c_.time.pseudo_cfl;
      const IterationNorms n = mg_ ? mg_->cycle_with_cfl(cfl) : solver().iterate_with_cfl(cfl);
      if (++done.subiterations == 1) first = n.total;
      done.drop = first > 0.0 ? n.total / first : 0.0;
      monitors_.take_mean_flow(n, first > 0.0 ? first : 1.0);
      if (turb_) {
        // A transport model's variables converge within the step too: their own drops
        // count (a uniform mean flow has no residual to drop while k and epsilon decay).
        const TurbulenceNorms t = coupling_->after_mean_flow_step(cfl);
        monitors_.take_turbulence(t);
        for (int m = 0; m < 2; ++m) {
          if (done.subiterations == 1) first_turbulence[m] = t.l2[m];
          if (first_turbulence[m] > 0.0) done.drop = std::max(done.drop, t.l2[m] / first_turbulence[m]);
        }
      }
      const std::map<std::string, ForceCoefficients> before = forces_;
      measure_forces();
      done.force_change = done.subiterations > 1 ? largest_force_change(before, forces_) : 1.0;
      if (propulsion_) {
        propulsion_->after_subiteration(g_, field_);  // collective
        write_propulsor_row(it);
      }
      if (free) {
        done.coupling_change =
            motion_->correct(body_loads(), dual_time_->step_size(), dual_time_->term().coefficients());
        carry_propulsor();
      }
      if (history_) history_->write(it, elapsed(), monitors_.last, forces_, monitors_.turb_res);
      s_.iterations = it;
      s_.residual_drop = done.drop;
      if (!std::isfinite(n.total) || done.drop > c_.solver.divergence_factor) {
        s_.status = RunStatus::Diverged;
        s_.message = fmt::format("step {}, iteration {}: residual grew by {:.2e} within the step (limit {:.1e}); "
                                 "largest at {}", dual_time_->step(), it, done.drop, c_.solver.divergence_factor,
                                 solver().describe_largest_residual());
        break;
      }
      const bool settled = done.drop < c_.time.subiteration_drop ||
                           (c_.time.force_change > 0.0 && done.force_change < c_.time.force_change);
      if (done.subiterations >= c_.time.min_subiterations && settled && motion_coupled(done.coupling_change))
        break;
    }
    return done;
  }

  bool motion_coupled(Real change) const { return !motion_ || motion_->coupled(change); }

  void show_step_progress(int subiterations, Real drop) {
    if (!opt_.progress || !root_ || Clock::now() - last_print_ < std::chrono::milliseconds(200)) return;
    last_print_ = Clock::now();
    std::string f;
    for (const auto& [name, fc] : forces_) f += fmt::format("  {} CF=({:.5f},{:.5f})", name, fc.force[0], fc.force[1]);
    fmt::print("\r  step {:6d} of {}  t {:.4g}  {:2d} sub-iterations, drop {:.1e}{}   ", dual_time_->step(),
               c_.time.steps, dual_time_->time(), subiterations, drop, f);
    std::fflush(stdout);
  }

  // Collective: what every loop ends with.
  void close_loop() {
    if (opt_.progress && root_) fmt::print("\n");
    s_.wall_seconds = comm_.max(elapsed());
    s_.turbulence_start_ended = coupling_->start_state().ended_at;
    s_.cfl_cuts = solver().cfl_cuts();
    s_.cfl_ceiling_cuts = solver().rise_guard().cuts();
    measure_cost();
  }

  // Collective (every rank takes part): the slowest rank's time, all ranks' memory.
  void measure_cost() {
    const int ran = s_.iterations - info_.iteration;
    const Real seconds = comm_.max(std::chrono::duration<Real>(Clock::now() - started_).count());
    s_.seconds_per_cycle = ran > 0 ? seconds / ran : 0.0;
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const long long bytes = comm_.sum(static_cast<long long>(usage.ru_maxrss) * 1024);  // ru_maxrss is in KiB
    s_.peak_bytes_per_cell = static_cast<Real>(bytes) / static_cast<Real>(std::max<std::size_t>(g_.cells(), 1));
  }

  // The residual of the state entering this iteration (or cycle), then the update.
  void step() {
    const IterationNorms n = mg_ ? mg_->cycle() : solver().iterate();
    monitors_.take_mean_flow(n, solver().reference_norm());
    if (!turb_) return;
    monitors_.take_turbulence(coupling_->after_mean_flow_step(monitors_.last.cfl));
  }

  void measure_forces() {
    wall_faces(g_, field_, fp_, faces_);
    forces_ = integrate_forces(comm_, g_, faces_, c_.output.reference_area, c_.output.reference_length, moment_centre());
  }

  // Residuals down by solver.residual_drop and, when the case asks, forces steady.
  bool converged() const {
    return monitors_.converged(c_.solver.residual_drop, c_.solver.turbulence_target()) && force_steadiness_.steady() &&
           (!propulsion_ || propulsion_->settled());
  }

  // True when the run stops here: diverged or converged.
  bool judge_convergence(int it) {
    if (!std::isfinite(monitors_.last.total) || monitors_.drop > c_.solver.divergence_factor) {
      s_.status = RunStatus::Diverged;
      s_.message = fmt::format("iteration {}: residual grew by {:.2e} (limit {:.1e}); largest at {}", it,
                               monitors_.drop, c_.solver.divergence_factor, solver().describe_largest_residual());
      return true;
    }
    if (monitors_.drop > c_.solver.regrowth_factor * monitors_.lowest_drop) {
      s_.status = RunStatus::Diverged;
      s_.message = fmt::format("iteration {}: residual grew by {:.2e} above its lowest ({:.2e} of its start; "
                               "solver.regrowth_factor {:.1e}); largest at {}",
                               it, monitors_.drop / monitors_.lowest_drop, monitors_.lowest_drop,
                               c_.solver.regrowth_factor, solver().describe_largest_residual());
      return true;
    }
    if (converged()) {
      s_.status = RunStatus::Converged;
      return true;
    }
    if (stall_.observe(it, std::max(monitors_.drop, monitors_.turb_drop))) {
      s_.status = RunStatus::Stalled;
      s_.message = describe_stall(it);
      return true;
    }
    return false;
  }

  // Collective: "the slowest equation is k (drop ...), its largest residual at ...": the
  // equation with the largest drop against its own largest residual.
  std::string describe_slowest_equation() {
    const std::array<Real, kNumEq> drops = monitors_.equation_drops();
    std::string slowest = kEquationNames[0];
    Real worst = drops[0];
    int mean_flow_equation = 0, turbulence_variable = -1;
    for (int m = 1; m < kNumEq; ++m)
      if (drops[m] > worst) {
        worst = drops[m];
        slowest = kEquationNames[m];
        mean_flow_equation = m;
      }
    for (std::size_t m = 0; m < turb_names_.size(); ++m) {
      const Real d = monitors_.turbulence_drop(m);
      if (d > worst) {
        worst = d;
        slowest = turb_names_[m];
        turbulence_variable = static_cast<int>(m);
      }
    }
    const std::string where = turbulence_variable >= 0
                                  ? turb_->describe_largest_residual(g_, turbulence_variable, comm_)
                                  : solver().describe_largest_residual(mean_flow_equation);
    return fmt::format("the slowest equation is {} (drop {:.2e}), its largest residual at {}", slowest, worst, where);
  }

  std::string describe_stall(int it) {
    return fmt::format("the residuals have not fallen by a factor {:g} in {} iterations (since iteration {}, drop "
                       "{:.2e}); {}",
                       stall_.fall(), it - stall_.anchor_iteration(), stall_.anchor_iteration(), stall_.anchor(),
                       describe_slowest_equation());
  }

  void checkpoint(int it) {
    solver().check_finite();
    RestartInfo r = run_state(it);
    FlowField& out = assemble();
    const FlowField* previous = dual_time_ ? &assemble_previous_level(r) : nullptr;
    if (root_) write_restart(restart_path_, pieces_ ? whole_ : g_, out, r, c_.text, previous);
    last_restart_ = it;
  }

  // What a restart carries besides the fields: the monitors and every controller's state.
  RestartInfo run_state(int it) {
    RestartInfo r{it, elapsed(), {-1.0, -1.0}, flow_rate_ ? flow_rate_->magnitude() : -1.0, c_.turbulence.model};
    monitors_.store(r);
    r.cfl_control = solver().cfl_control();
    r.stall_anchor = stall_.anchor();
    r.stall_anchor_iteration = stall_.anchor_iteration();
    r.force_window = force_steadiness_.state();
    r.force_components = 3 * static_cast<int>(forces_.size());
    const TurbulenceStartState start = coupling_->start_state();
    r.turbulence_starting = start.starting;
    r.turbulence_start_ended = start.ended_at;
    r.start_window = start.window;
    r.start_components = start.components;
    if (propulsion_) r.propulsor_state = propulsion_->checkpoint();
    if (controls_) r.control_state = controls_->checkpoint();
    return r;
  }

  void show_progress(int it) {
    if (!opt_.progress || !root_ || Clock::now() - last_print_ < std::chrono::milliseconds(200)) return;
    last_print_ = Clock::now();
    // ETA from the mean logarithmic convergence rate so far of the drop convergence waits
    // for (the turbulence model's, when it lags the mean flow's); none once it is met and
    // only the forces' steadiness is awaited.
    const Real worst = std::max(s_.residual_drop, s_.turbulence_drop);
    const Real rate = std::log(std::max(worst, 1e-300)) / it;
    const Real left = rate < 0 && worst > c_.solver.residual_drop ? std::log(c_.solver.residual_drop / worst) / rate : 0.0;
    const Real eta = std::min<Real>(left, max_it_ - it) * elapsed() / it;
    std::string f;
    for (const auto& [name, fc] : forces_) f += fmt::format("  {} CF=({:.5f},{:.5f})", name, fc.force[0], fc.force[1]);
    fmt::print("\r  it {:6d}  drop {:.2e}  cfl {:.1e}{}  ETA {:.0f}s   ", it, worst, monitors_.last.cfl, f, eta);
    std::fflush(stdout);
  }

  // The last restart, surfaces and solution (not after a divergence: the last good
  // restart stays), then run.json and the closing line.
  void finish() {
    if (s_.status != RunStatus::Diverged) {
      checkpoint(s_.iterations);
      if (root_) write_fields();
    } else if (root_) {
      s_.message += last_restart_ >= 0
                        ? fmt::format("; the last good restart.h5 (iteration {}) is kept", last_restart_)
                        : std::string("; no restart was written before");
    }
    s_.equation_drops = monitors_.equation_drops();
    s_.turbulence_drops.clear();
    for (std::size_t m = 0; m < turb_names_.size(); ++m)
      s_.turbulence_drops.emplace_back(
          turb_names_[m], monitors_.turbulence_drop(m));
    s_.turbulence_drop = monitors_.turb_drop;
    if (force_steadiness_.enabled()) s_.force_span = force_steadiness_.span();
    comm_.barrier();
    if (!root_) return;
    write_run_json(file("run.json"), c_, g_, s_, monitors_.last, forces_,
                   flow_rate_ ? flow_rate_->force() : c_.body_force, comm_.size(), propulsion_.get(),
                   motion_ && motion_->free_body() ? &motion_->body() : nullptr);
    std::string drops = fmt::format("p {:.1e}, u {:.1e}, v {:.1e}, w {:.1e}", s_.equation_drops[0],
                                    s_.equation_drops[1], s_.equation_drops[2], s_.equation_drops[3]);
    for (const auto& [name, d] : s_.turbulence_drops) drops += fmt::format(", {} {:.1e}", name, d);
    if (s_.force_span >= 0.0) drops += fmt::format("; force span {:.1e} over {}", s_.force_span,
                                                   force_steadiness_.window());
    fmt::print("narwhal: {} after {} iterations, residual drop {:.2e} ({}), {:.1f} s{}{}\n", to_string(s_.status),
               s_.iterations, s_.residual_drop, drops, s_.wall_seconds, s_.message.empty() ? "" : ": ", s_.message);
    fmt::print("narwhal: cost {:.3g} ms per {}, peak memory {:.3g} kB per cell\n", 1e3 * s_.seconds_per_cycle,
               mg_ ? "cycle" : "iteration", s_.peak_bytes_per_cell / 1024.0);
    if (s_.cfl_cuts > 0)
      fmt::print("narwhal: {} correction(s) rejected and the CFL cut: the SGS sweeps diverged at the CFL of the "
                 "moment (NewtonSolver::relax_and_update)\n",
                 s_.cfl_cuts);
    if (!s_.retreats.empty())
      fmt::print("narwhal: went back {} time(s) from a divergence to the lowest-residual state, the CFL ceiling "
                 "lowered each time (app/retreat.hpp)\n",
                 s_.retreats.size());
    if (s_.cfl_ceiling_cuts > 0)
      fmt::print("narwhal: the residual rose in successive iterations {} time(s); the CFL ceiling is now {:.3g} "
                 "(implicit/cfl_rise_guard.hpp)\n",
                 s_.cfl_ceiling_cuts, solver().rise_guard().ceiling());
  }

  // Surfaces and the solution from the assembled field (checkpoint() gathered it), as a serial run.
  void write_fields() {
    FlowField& out = pieces_ ? whole_field_ : field_;
    Grid& out_grid = pieces_ ? whole_ : g_;
    const std::vector<int> owner = out_grid.owner;
    out_grid.owner.clear();  // the root holds every block now: a serial ghost fill
    out_grid.halo.reset();
    fill_ghosts(out_grid, out, fp_);
    for (const auto& [name, list] : wall_faces(out_grid, out, fp_))
      write_surface_csv(file(fmt::format("surface_{}.csv", name)), list);
    std::vector<std::string> cgns_turb;
    for (int m = 0; turb_ && m < turb_->num_variables(); ++m) cgns_turb.push_back(turb_->cgns_name(m));
    write_cgns_solution(file("solution.cgns"), out_grid, out, cgns_turb, 1.0 / fp_.reynolds);
    out_grid.owner = owner;
    out_grid.halo.reset();
  }

  // Collective: a dual-time run's step, time and Q^{n-1} for its restart, Q^{n-1} in the
  // case's layout on the root (as assemble() does for Q^n).
  FlowField& assemble_previous_level(RestartInfo& r) {
    r.time_step = dual_time_->step();
    r.time = dual_time_->time();
    r.time_step_size = c_.time.step;
    if (motion_) {
      r.reference_extents = motion_->reference_extents();
      r.body_state = motion_->checkpoint();
    }
    if (previous_.Q.empty()) previous_.allocate_states(g_, c_.initial);
    dual_time_->save_previous(g_, previous_);
    gather_to_root(comm_, g_, previous_);
    if (!pieces_) return previous_;
    if (root_) {
      if (whole_previous_.Q.empty()) whole_previous_.allocate_states(whole_, c_.initial);
      copy_between_layouts(g_, previous_, whole_, whole_previous_, true);
    }
    return whole_previous_;
  }

  // The root writes files in the case's layout from every rank's cells.
  FlowField& assemble() {
    gather_to_root(comm_, g_, field_);
    if (!pieces_) return field_;
    if (root_) {
      if (whole_field_.Q.empty()) whole_field_.allocate(whole_, fp_, c_.initial);
      copy_between_layouts(g_, field_, whole_, whole_field_, true);
    }
    return whole_field_;
  }

  NewtonSolver& solver() { return mg_ ? mg_->finest() : *single_; }
  std::string file(const std::string& name) const { return (fs::path(opt_.out_dir) / name).string(); }
  Real elapsed() const {
    return info_.wall_seconds + std::chrono::duration<Real>(Clock::now() - started_).count();
  }

  const CaseConfig& c_;
  const RunOptions& opt_;
  const Communicator comm_;
  const bool root_;
  const int max_it_;

  Grid g_, whole_;  // the computed pieces, and the case's own blocks when they differ
  bool pieces_ = false;
  FlowParams fp_;
  FlowField field_, whole_field_;
  std::unique_ptr<FlowRateControl> flow_rate_;
  std::unique_ptr<PropulsionControl> propulsion_;
  std::unique_ptr<PropulsorWriter> propulsor_csv_;
  std::unique_ptr<ControlSurfaces> controls_;  // [controls], [autopilot], [zigzag]: surfaces turned in time
  std::unique_ptr<ControlsWriter> controls_csv_;
  bool walls_moved_pending_ = false;           // the grids reshaped since after_walls_moved
  int split_for_ = 1;                          // the ranks the run's blocks were cut for

  std::unique_ptr<OutputDirectory> out_dir_;  // the root's lock on the output directory
  bool continuing_ = false, own_restart_ = false;
  std::string restart_path_;
  int last_restart_ = -1;  // iteration of the newest restart.h5 of this run's lineage in the directory
  RestartInfo info_;

  std::unique_ptr<NewtonSolver> single_;
  std::unique_ptr<Multigrid> mg_;
  std::unique_ptr<TurbulenceCoupling> coupling_;  // owns the model; may hook into mg_
  TurbulenceModel* turb_ = nullptr;               // its model (none: laminar)

  std::vector<std::string> groups_;      // the wall groups forces are taken on
  std::vector<std::string> turb_names_;  // the turbulence model's variables
  Monitors monitors_{0};
  std::unique_ptr<HistoryWriter> history_;
  std::unique_ptr<DualTime> dual_time_;      // dual-time runs only
  FlowField restored_previous_;              // Q^{n-1} read from a restart, until the time levels take it
  FlowField previous_, whole_previous_;      // Q^{n-1} gathered for restarts (pieces, case layout)
  std::unique_ptr<RunMotion> motion_;         // a moving grid's motion (and the grids that move)
  std::unique_ptr<MotionWriter> motion_csv_;  // the root's motion.csv (free bodies)
  std::unique_ptr<StepsWriter> steps_;       // the root's steps.csv (dual-time runs)
  std::map<std::string, ForceCoefficients> forces_;
  std::map<std::string, std::vector<WallFace>> faces_;  // reused every iteration
  RunSummary s_;
  std::optional<LastGoodState> last_good_;  // what a retreat returns to (app/retreat.hpp)
  std::optional<LastGoodState> candidate_;  // the latest state, until the next residual judges it
  StallDetector stall_{c_.solver.stall_window, c_.solver.stall_factor};
  ForceSteadiness force_steadiness_{c_.solver.force_window, c_.solver.force_tolerance};
  Clock::time_point started_ = Clock::now(), last_print_ = Clock::now();
};

}  // namespace

RunSummary run_case(const CaseConfig& c, const RunOptions& opt) { return SteadyRun(c, opt).execute(); }

}  // namespace narwhal
