#include "app/driver.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "bc/boundary.hpp"
#include "io/cgns_writer.hpp"
#include "io/monitors.hpp"
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

std::string json_escape(const std::string& s) {
  std::string o;
  for (char ch : s) {
    switch (ch) {
      case '"': o += "\\\""; break;
      case '\\': o += "\\\\"; break;
      case '\n': o += "\\n"; break;
      case '\t': o += "\\t"; break;
      default:
        if (static_cast<unsigned char>(ch) < 0x20) o += fmt::format("\\u{:04x}", static_cast<int>(ch));
        else o += ch;
    }
  }
  return o;
}

void write_run_json(const std::string& path, const CaseConfig& c, const Grid& g, const RunSummary& s,
                    const IterationNorms& last, const std::map<std::string, ForceCoefficients>& forces,
                    const Vec3& body_force, int ranks) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) fail("cannot write '{}'", path);
  fmt::print(f, "{{\n  \"case\": \"{}\",\n  \"title\": \"{}\",\n", json_escape(c.file), json_escape(c.title));
  fmt::print(f, "  \"status\": \"{}\",\n  \"message\": \"{}\",\n", to_string(s.status), json_escape(s.message));
  fmt::print(f, "  \"iterations\": {},\n  \"wall_seconds\": {:.6f},\n  \"cells\": {},\n  \"blocks\": {},\n  \"ranks\": {},\n",
             s.iterations, s.wall_seconds, g.cells(), g.blocks.size(), ranks);
  fmt::print(f, "  \"residual_drop\": {:.6e},\n  \"final_residual\": {{\"p\": {:.6e}, \"u\": {:.6e}, \"v\": {:.6e}, \"w\": {:.6e}}},\n",
             s.residual_drop, last.l2[0], last.l2[1], last.l2[2], last.l2[3]);
  fmt::print(f, "  \"settings\": {{\"reynolds\": {:.9g}, \"beta\": {:.9g}, \"viscous\": \"{}\", \"muscl_kappa\": {:.9g}, "
                "\"muscl_phi\": {:.9g}, \"cfl_start\": {:.9g}, \"cfl_max\": {:.9g}, \"sgs_iterations\": {}, "
                "\"max_iterations\": {}, \"residual_drop_target\": {:.3e}, \"multigrid_levels\": {}, \"multigrid_cycle\": \"{}\"}},\n",
             c.flow.reynolds, c.flow.beta,
             c.flow.viscous == ViscousForm::Full ? "full" : (c.flow.viscous == ViscousForm::ThinLayer ? "thin-layer" : "inviscid"),
             c.flow.muscl.kappa, c.flow.muscl.phi, c.solver.newton.cfl_start, c.solver.newton.cfl_max,
             c.solver.newton.sgs_iterations, c.solver.max_iterations, c.solver.residual_drop, c.solver.multigrid.levels,
             c.solver.multigrid.gamma == 2 ? "W" : "V");
  fmt::print(f, "  \"body_force\": [{:.12e}, {:.12e}, {:.12e}],\n", body_force[0], body_force[1], body_force[2]);
  fmt::print(f, "  \"forces\": {{");
  bool first = true;
  for (const auto& [name, fc] : forces) {
    fmt::print(f, "{}\n    \"{}\": {{\"cfx\": {:.12e}, \"cfy\": {:.12e}, \"cfz\": {:.12e}, \"cmx\": {:.12e}, \"cmy\": {:.12e}, \"cmz\": {:.12e}}}",
               first ? "" : ",", json_escape(name), fc.force[0], fc.force[1], fc.force[2], fc.moment[0], fc.moment[1],
               fc.moment[2]);
    first = false;
  }
  fmt::print(f, "{}}},\n", forces.empty() ? "" : "\n  ");
  fmt::print(f, "  \"provenance\": {{\"version\": \"{}\", \"git_sha\": \"{}\", \"compiler\": \"{}\", \"flags\": \"{}\"}}\n}}\n",
             kVersion, kGitSha, kCompiler, kBuildFlags);
  std::fclose(f);
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
  if (root) fs::create_directories(opt.out_dir);
  comm.barrier();
  const std::string restart_path = (fs::path(opt.out_dir) / "restart.h5").string();

  RestartInfo info;
  if (opt.restart) {
    // Every rank reads the file (written in the case's layout) and keeps its pieces.
    if (pieces) {
      FlowField w;
      w.allocate(whole, fp, c.initial);
      info = read_restart(*opt.restart, whole, w);
      copy_between_layouts(g, field, whole, w, false);
    } else {
      info = read_restart(*opt.restart, g, field);
    }
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
    history = std::make_unique<HistoryWriter>((fs::path(opt.out_dir) / "history.csv").string(), groups,
                                              opt.restart.has_value(), turb_names);
  std::vector<Real> turb_res(turb_names.size(), 0.0), turb_ref(turb_names.size(), -1.0);
  for (std::size_t m = 0; m < turb_ref.size() && opt.restart; ++m) turb_ref[m] = info.turbulence_reference[m];
  auto restart_info = [&](int it, Real wall) {
    RestartInfo r{it, solver.reference_norm(), wall, {-1.0, -1.0}, flow_rate ? flow_rate->magnitude() : -1.0};
    for (std::size_t m = 0; m < turb_ref.size(); ++m) r.turbulence_reference[m] = turb_ref[m];
    return r;
  };
  Real turb_drop = 0.0;  // largest drop of the model's residuals

  const int max_it = opt.max_iterations.value_or(c.solver.max_iterations);
  RunSummary s;
  s.iterations = info.iteration;
  const auto t0 = clock::now();
  auto elapsed = [&] { return info.wall_seconds + std::chrono::duration<Real>(clock::now() - t0).count(); };
  IterationNorms last;
  std::map<std::string, ForceCoefficients> forces;
  std::map<std::string, std::vector<WallFace>> faces;  // reused every iteration
  auto last_print = clock::now();
  if (!opt.progress && root)
    fmt::print("narwhal: {} — {} blocks, {} cells{}, up to {} {}\n", c.title, g.blocks.size(), g.cells(),
               comm.size() > 1 ? fmt::format(", {} ranks", comm.size()) : std::string(), max_it,
               mg ? fmt::format("{}-cycles on {} levels", c.solver.multigrid.gamma == 2 ? "W" : "V", mg->levels())
                  : std::string("iterations"));

  try {
    while (s.iterations < max_it) {
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
        if (history) history->flush();
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
  if (s.status == RunStatus::MaxIterations && s.iterations > 0)
    s.message = fmt::format("not converged (mean-flow drop {:.2e}{}); largest residual at {}", s.residual_drop,
                            turb ? fmt::format(", turbulence drop {:.2e}", turb_drop) : std::string(),
                            solver.describe_largest_residual());
  if (opt.progress && root) fmt::print("\n");
  s.wall_seconds = comm.max(elapsed());
  if (history) history->flush();
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
    s.message += fs::exists(restart_path) ? "; the last good restart.h5 is kept" : "; no restart was written before";
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
