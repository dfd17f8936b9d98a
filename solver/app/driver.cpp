#include "app/driver.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bc/boundary.hpp"
#include "io/cgns_writer.hpp"
#include "io/monitors.hpp"
#include "io/output_directory.hpp"
#include "io/text_file.hpp"
#include "io/restart.hpp"
#include "parallel/communicator.hpp"
#include "parallel/distribution.hpp"
#include "physics/flow_rate.hpp"
#include "physics/planar.hpp"
#include "physics/wall_forces.hpp"
#include "turbulence/model.hpp"
#include "version.hpp"

namespace narwhal {

const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::Converged: return "converged";
    case RunStatus::MaxIterations: return "max_iterations";
    case RunStatus::Diverged: return "diverged";
  }
  return "?";
}

FlowParams flow_params(const CaseConfig& c) {
  FlowParams fp = c.flow;
  const Vec3 g = c.body_force;
  if (c.manufactured) {
    const ManufacturedSolution ms = c.mms;
    fp.momentum_source = [ms, g](const Vec3& x) { return Vec3(ms.momentum_source(x) + g); };
    fp.exact = [ms](const Vec3& x) { return ms.exact(x); };
  } else if (g.squaredNorm() > 0.0) {
    fp.momentum_source = [g](const Vec3&) { return g; };
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
                    const Vec3& body_force, int ranks) {
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
  j["final_residual"] = {{"p", last.l2[0]}, {"u", last.l2[1]}, {"v", last.l2[2]}, {"w", last.l2[3]}};
  j["settings"] = {{"reynolds", c.flow.reynolds},
                   {"beta", c.flow.beta},
                   {"viscous", viscous_name(c.flow.viscous)},
                   {"muscl_kappa", c.flow.muscl.kappa},
                   {"muscl_phi", c.flow.muscl.phi},
                   {"cfl_start", c.solver.newton.cfl_start},
                   {"cfl_max", c.solver.newton.cfl_max},
                   {"sgs_iterations", c.solver.newton.sgs_iterations},
                   {"max_iterations", c.solver.max_iterations},
                   {"residual_drop_target", c.solver.residual_drop},
                   {"multigrid_levels", c.solver.multigrid.levels},
                   {"multigrid_cycle", c.solver.multigrid.gamma == 2 ? "W" : "V"},
                   {"turbulence_model", c.turbulence.model}};
  j["body_force"] = {body_force[0], body_force[1], body_force[2]};
  nlohmann::ordered_json f = nlohmann::ordered_json::object();
  for (const auto& [name, fc] : forces)
    f[name] = {{"cfx", fc.force[0]}, {"cfy", fc.force[1]}, {"cfz", fc.force[2]},
               {"cmx", fc.moment[0]}, {"cmy", fc.moment[1]}, {"cmz", fc.moment[2]}};
  j["forces"] = f;
  j["provenance"] = {{"version", kVersion}, {"git_sha", kGitSha}, {"compiler", kCompiler}, {"flags", kBuildFlags}};
  write_file_atomically(path, j.dump(2) + "\n");
}

}  // namespace

RunSummary run_case(const CaseConfig& c, const RunOptions& opt) {
  namespace fs = std::filesystem;
  using clock = std::chrono::steady_clock;
  const Communicator comm = Communicator::world();
  const bool root = comm.is_root();
  // The case's own blocks (the layout of every file), and the blocks the run computes
  // on: cut into pieces until they share out over the ranks (parallel/partition.hpp).
  const int split_for = c.split_for > 0 ? c.split_for : comm.size();
  const bool pieces = split_for > 1;
  Grid g = build_grid(c, split_for);
  Grid whole;
  if (pieces) whole = build_grid(c);
  distribute(g, comm.size(), comm.rank());
  FlowParams fp = flow_params(c);
  std::unique_ptr<FlowRateControl> flow_rate;
  if (c.bulk_velocity > 0.0) {
    flow_rate = std::make_unique<FlowRateControl>(g, c.body_force, c.bulk_velocity);
    fp.momentum_source = flow_rate->source();
  }
  FlowField field;
  field.allocate(g, fp, c.initial);
  // A run from a restart continues the directory's history; restarting from the
  // directory's own restart.h5 keeps that file as the last good state until the next.
  const bool continuing = opt.restart.has_value();
  const bool own_restart = continuing && restart_is_in(*opt.restart, opt.out_dir);
  std::unique_ptr<OutputDirectory> out_dir;
  if (root) {
    out_dir = std::make_unique<OutputDirectory>(opt.out_dir, continuing, own_restart);
    if (!out_dir->cleared().empty())
      fmt::print("narwhal: removed the previous run's outputs from '{}' ({} files)\n", opt.out_dir,
                 out_dir->cleared().size());
  }
  comm.barrier();
  const std::string restart_path = (fs::path(opt.out_dir) / "restart.h5").string();
  int last_restart = -1;  // iteration of the newest restart.h5 of this run's lineage in out_dir

  RestartInfo info;
  if (opt.restart) {
    // Every rank reads the file (written in the case's layout) and keeps its pieces.
    if (pieces) {
      FlowField w;
      w.allocate(whole, fp, c.initial);
      info = read_restart(*opt.restart, whole, w, c.turbulence.model);
      copy_between_layouts(g, field, whole, w, false);
    } else {
      info = read_restart(*opt.restart, g, field, c.turbulence.model);
    }
    if (own_restart) last_restart = info.iteration;
  }
  // The root writes files in the case's layout from every rank's cells.
  FlowField whole_field;
  auto assemble = [&]() -> FlowField& {
    gather_to_root(g, field);
    if (!pieces) return field;
    if (root) {
      if (whole_field.Q.empty()) whole_field.allocate(whole, fp, c.initial);
      copy_between_layouts(g, field, whole, whole_field, true);
    }
    return whole_field;
  };
  auto save_restart = [&](const RestartInfo& r) {
    FlowField& out = assemble();
    if (root) write_restart(restart_path, pieces ? whole : g, out, r, c.text);
    last_restart = r.iteration;
  };
  if (flow_rate && info.body_force > 0.0) flow_rate->set_magnitude(info.body_force);
  if (c.solver.planar_shortcut) {
    const std::string planar = mark_planar_blocks(g, field, fp);
    if (!planar.empty() && root) fmt::print("narwhal: {}\n", planar);
  }
  // Single grid: one Newton-SGS iteration per step; multigrid: one FAS cycle.
  std::unique_ptr<NewtonSolver> single;
  std::unique_ptr<Multigrid> mg;
  if (c.solver.multigrid.levels > 1) {
    mg = std::make_unique<Multigrid>(g, field, fp, c.solver.newton, c.solver.multigrid);
    if (!mg->level_note().empty() && root) fmt::print("narwhal: {}\n", mg->level_note());
  } else {
    single = std::make_unique<NewtonSolver>(g, field, fp, c.solver.newton);
  }
  NewtonSolver& solver = mg ? mg->finest() : *single;
  if (opt.restart) solver.set_reference_norm(info.reference_norm);
  // Turbulence: loosely coupled, one model update after every mean-flow step (§8.6).
  std::unique_ptr<TurbulenceModel> turb = make_turbulence_model(c.turbulence, g);
  if (turb) {
    turb->initialize(g, field, fp, opt.restart.has_value());
    fill_ghosts(g, field, fp);
    turb->update_viscosity(g, field, fp);
  }
  TurbulenceNorms turb_norms;
  auto step = [&] {
    const IterationNorms n = mg ? mg->cycle() : solver.iterate();
    if (turb) turb_norms = turb->advance(g, field, fp, n.cfl);
    return n;
  };

  // Wall groups are known from the patches; forces appear in the history per group.
  fill_ghosts(g, field, fp);
  std::vector<std::string> groups;
  for (const auto& [name, list] : wall_faces(g, field, fp)) groups.push_back(name);  // every rank: all groups
  std::vector<std::string> turb_names;
  for (int m = 0; turb && m < turb->num_variables(); ++m) turb_names.push_back(turb->variable_name(m));
  std::unique_ptr<HistoryWriter> history;
  if (root)
    history = std::make_unique<HistoryWriter>((fs::path(opt.out_dir) / "history.csv").string(), groups, turb_names,
                                              continuing ? std::optional<int>(info.iteration) : std::nullopt);
  std::vector<Real> turb_res(turb_names.size(), 0.0), turb_ref(turb_names.size(), -1.0);
  for (std::size_t m = 0; m < turb_ref.size() && opt.restart; ++m) turb_ref[m] = info.turbulence_reference[m];
  Real turb_drop = 0.0;  // largest drop of the model's residuals
  const int max_it = opt.max_iterations.value_or(c.solver.max_iterations);
  RunSummary s;
  s.iterations = info.iteration;
  IterationNorms last;
  auto restart_info = [&](int it, Real wall) {
    RestartInfo r{it, solver.reference_norm(), wall, {-1.0, -1.0}, flow_rate ? flow_rate->magnitude() : -1.0,
                  c.turbulence.model};
    for (std::size_t m = 0; m < turb_ref.size(); ++m) {
      r.turbulence_reference[m] = turb_ref[m];
      r.turbulence_residual[m] = turb_res[m];
    }
    r.residual = last.l2;
    r.residual_total = last.total;
    r.cfl = last.cfl;
    r.residual_drop = s.residual_drop;
    r.turbulence_drop = turb_drop;
    return r;
  };
  std::map<std::string, ForceCoefficients> forces;
  std::map<std::string, std::vector<WallFace>> faces;  // reused every iteration
  bool done = false;  // converged already: a run resumed from the restart its converged end wrote
  if (opt.restart) {
    // The monitors of the restored state are those of the iteration that wrote it.
    last.l2 = info.residual;
    last.total = info.residual_total;
    last.cfl = info.cfl;
    s.residual_drop = info.residual_drop;
    turb_drop = info.turbulence_drop;
    for (std::size_t m = 0; m < turb_res.size(); ++m) turb_res[m] = info.turbulence_residual[m];
    wall_faces(g, field, fp, faces);
    forces = integrate_forces(g, faces, c.output.reference_area, c.output.reference_length, c.output.moment_centre);
    done = info.iteration > 0 && s.residual_drop < c.solver.residual_drop && turb_drop < c.solver.residual_drop;
    if (done) s.status = RunStatus::Converged;
  }

  const auto t0 = clock::now();
  auto elapsed = [&] { return info.wall_seconds + std::chrono::duration<Real>(clock::now() - t0).count(); };
  auto last_print = clock::now();
  if (!opt.progress && root)
    fmt::print("narwhal: {} — {} blocks, {} cells{}, up to {} {}\n", c.title, g.blocks.size(), g.cells(),
               comm.size() > 1 ? fmt::format(", {} ranks", comm.size()) : std::string(), max_it,
               mg ? fmt::format("{}-cycles on {} levels", c.solver.multigrid.gamma == 2 ? "W" : "V", mg->levels())
                  : std::string("iterations"));

  try {
    while (!done && s.iterations < max_it) {
      const int it = s.iterations + 1;
      last = step();  // residual of the state entering this iteration (or cycle), then the update
      wall_faces(g, field, fp, faces);
      forces = integrate_forces(g, faces, c.output.reference_area, c.output.reference_length, c.output.moment_centre);
      if (flow_rate) flow_rate->update(g, field, faces);
      turb_drop = 0.0;
      for (std::size_t m = 0; m < turb_res.size(); ++m) {
        turb_res[m] = turb_norms.l2[m];
        // The model's residual is measured against the largest it has had: from a
        // free-stream start the first residual of k is tiny, and a drop relative to it
        // would ask for far more than the mean flow's criterion does.
        turb_ref[m] = std::max(turb_ref[m], turb_res[m]);
        turb_drop = std::max(turb_drop, turb_res[m] / std::max(turb_ref[m], 1e-300));
      }
      if (history) history->write(it, elapsed(), last, forces, turb_res);
      s.iterations = it;
      s.residual_drop = last.total / solver.reference_norm();
      if (!std::isfinite(last.total) || s.residual_drop > c.solver.divergence_factor) {
        s.status = RunStatus::Diverged;
        s.message = fmt::format("iteration {}: residual grew by {:.2e} (limit {:.1e}); largest at {}", it,
                                s.residual_drop, c.solver.divergence_factor, solver.describe_largest_residual());
        break;
      }
      if (s.residual_drop < c.solver.residual_drop && turb_drop < c.solver.residual_drop) {
        s.status = RunStatus::Converged;
        break;
      }
      if (c.output.restart_interval > 0 && it % c.output.restart_interval == 0) {
        solver.check_finite();
        save_restart(restart_info(it, elapsed()));
      }
      if (opt.progress && root && (clock::now() - last_print > std::chrono::milliseconds(200))) {
        last_print = clock::now();
        // ETA from the mean logarithmic convergence rate so far.
        const Real rate = std::log(std::max(s.residual_drop, 1e-300)) / it;
        const Real left = rate < 0 ? std::log(c.solver.residual_drop / s.residual_drop) / rate : 0.0;
        const Real eta = std::min<Real>(left, max_it - it) * elapsed() / it;
        std::string f;
        for (const auto& [name, fc] : forces) f += fmt::format("  {} CF=({:.5f},{:.5f})", name, fc.force[0], fc.force[1]);
        fmt::print("\r  it {:6d}  drop {:.2e}  cfl {:.1e}{}  ETA {:.0f}s   ", it, s.residual_drop, last.cfl, f, eta);
        std::fflush(stdout);
      }
    }
  } catch (const DivergenceError& e) {
    s.status = RunStatus::Diverged;
    s.message = fmt::format("iteration {}: {}", s.iterations + 1, e.what());
  }
  // A resumed run that had nothing left to do has no residual of its own to locate.
  if (s.status == RunStatus::MaxIterations && s.iterations > info.iteration)
    s.message = fmt::format("not converged (mean-flow drop {:.2e}{}); largest residual at {}", s.residual_drop,
                            turb ? fmt::format(", turbulence drop {:.2e}", turb_drop) : std::string(),
                            solver.describe_largest_residual());
  if (opt.progress && root) fmt::print("\n");
  s.wall_seconds = comm.max(elapsed());
  if (s.status != RunStatus::Diverged) {
    save_restart(restart_info(s.iterations, s.wall_seconds));
    if (root) {  // surfaces and the solution from the assembled field, as a serial run
      FlowField& out = pieces ? whole_field : field;
      Grid& out_grid = pieces ? whole : g;
      const std::vector<int> owner = out_grid.owner;
      out_grid.owner.clear();  // the root holds every block now: a serial ghost fill
      out_grid.halo.reset();
      fill_ghosts(out_grid, out, fp);
      for (const auto& [name, list] : wall_faces(out_grid, out, fp))
        write_surface_csv((fs::path(opt.out_dir) / fmt::format("surface_{}.csv", name)).string(), list);
      std::vector<std::string> cgns_turb;
      for (int m = 0; turb && m < turb->num_variables(); ++m) cgns_turb.push_back(turb->cgns_name(m));
      write_cgns_solution((fs::path(opt.out_dir) / "solution.cgns").string(), out_grid, out, cgns_turb,
                          1.0 / fp.reynolds);
      out_grid.owner = owner;
      out_grid.halo.reset();
    }
  } else if (root) {
    s.message += last_restart >= 0 ? fmt::format("; the last good restart.h5 (iteration {}) is kept", last_restart)
                                   : std::string("; no restart was written before");
  }
  comm.barrier();
  if (!root) return s;
  write_run_json((fs::path(opt.out_dir) / "run.json").string(), c, g, s, last, forces,
                 flow_rate ? flow_rate->force() : c.body_force, comm.size());
  fmt::print("narwhal: {} after {} iterations, residual drop {:.2e}, {:.1f} s{}{}\n", to_string(s.status),
             s.iterations, s.residual_drop, s.wall_seconds, s.message.empty() ? "" : ": ", s.message);
  return s;
}

}  // namespace narwhal
