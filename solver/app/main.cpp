// narwhal: command-line front end. `narwhal run CASE.toml`, `narwhal check CASE.toml`.
#include <cstdlib>
#include <unistd.h>

#include <algorithm>
#include <filesystem>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "app/driver.hpp"
#include "app/simulate.hpp"
#include "core/error.hpp"
#include "io/cgns_writer.hpp"
#include "io/openfoam_writer.hpp"
#include "mesh/grid_quality.hpp"
#include "mesh/plot3d.hpp"
#include "multigrid/coarsen.hpp"
#include "parallel/communicator.hpp"
#include "parallel/halo.hpp"
#include "parallel/partition.hpp"
#include "turbulence/model.hpp"
#include "version.hpp"

using namespace narwhal;

namespace {

int check_case(const std::string& path, const std::vector<std::string>& overrides) {
  const CaseConfig c = load_case(path, overrides);
  const Grid g = build_grid(c);
  fmt::print("{}: OK — {}\n", path, c.title);
  fmt::print("  grid: {} block(s), {} cells, {} interface(s)\n", g.blocks.size(), g.cells(), g.interfaces.size() / 2);
  for (const auto& b : g.blocks) {
    Real vmin = 1e300, vmax = 0;
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i) {
          vmin = std::min(vmin, b.vol(i, j, k));
          vmax = std::max(vmax, b.vol(i, j, k));
        }
    fmt::print("  block '{}': {} x {} x {} cells, volumes {:.3e} .. {:.3e}\n", b.name, b.ni, b.nj, b.nk, vmin, vmax);
    for (const auto& p : b.patches)
      fmt::print("    {:5s} {:>24s}  {}\n", side_name(p.side), p.label, to_string(p.type));
  }
  fmt::print("  flow: Re = {:g}, beta = {:g}\n", c.flow.reynolds, c.flow.beta);
  // The levels a run would build, decided as the run decides them.
  const MultigridSettings& ms = c.solver.multigrid;
  const CoarseLevels coarse = coarse_levels(g, ms.levels, ms.min_cells);
  const std::size_t levels = coarse.grids.size() + 1;
  if (coarse.impossible)
    fail("{}: key 'solver.multigrid_levels': {} levels need {} coarsenings, but coarsening {} fails: {}", path,
         ms.levels, ms.levels - 1, levels, coarse.stop);
  if (coarse.stop.empty())
    fmt::print("  multigrid: {} level(s)\n", levels);
  else
    fmt::print("  multigrid: {} level(s) of {} (solver.multigrid_min_cells: {})\n", levels, ms.levels, coarse.stop);
  return 0;
}

// `narwhal grid`: the case's grid as the solver would run it (generated or read,
// coarsened), written as CGNS (with patch labels) and Plot3D, and its quality report.
// A folded cell is an error, after the files are written so that it can be looked at.
int grid_case(const std::string& path, const std::vector<std::string>& overrides, const std::string& out_dir,
              const std::string& openfoam_dir) {
  const CaseConfig c = load_case(path, overrides);
  const Grid g = build_grid(c);
  std::filesystem::create_directories(out_dir);
  const std::string cgns = (std::filesystem::path(out_dir) / "grid.cgns").string();
  const std::string xyz = (std::filesystem::path(out_dir) / "grid.xyz").string();
  write_cgns_grid(cgns, g);
  write_plot3d_fortran(xyz, g.blocks);
  std::vector<std::string> walls;  // the body's surfaces: no-slip and slip walls
  for (const Block& b : g.blocks)
    for (const Patch& p : b.patches)
      if (p.body_surface && std::find(walls.begin(), walls.end(), p.label) == walls.end())
        walls.push_back(p.label);
  // y+ only where there is a viscous wall layer to resolve
  const GridQuality q = measure_grid_quality(g, walls, c.flow.viscous == ViscousForm::Inviscid ? 0.0 : c.flow.reynolds);
  fmt::print("{}: {} block(s), {} cells; wrote {} (patches labelled) and {} (Plot3D, Fortran unformatted, "
             "double, no patches)\n", path, g.blocks.size(), g.cells(), cgns, xyz);
  for (const Block& b : g.blocks) fmt::print("  block '{}': {} x {} x {} cells\n", b.name, b.ni, b.nj, b.nk);
  fmt::print("quality (walls: {}; Re = {:g} per unit length):\n{}", walls.empty() ? "none" : fmt::format("{}", fmt::join(walls, ", ")),
             c.flow.reynolds, format_grid_quality(q));
  require_unfolded(q, path);
  if (!openfoam_dir.empty()) {
    const OpenFoamMeshCounts n = write_openfoam_mesh(openfoam_dir, g);
    fmt::print("wrote {}/constant/polyMesh (OpenFOAM): {} points, {} cells, {} faces ({} internal)\n", openfoam_dir,
               n.points, n.cells, n.faces, n.internal_faces);
  }
  return 0;
}

// How a case would be distributed over `ranks`: blocks after the balancing cuts,
// cells per rank, and the halo each rank receives per exchange (cells and messages).
int partition_case(const std::string& path, const std::vector<std::string>& overrides, int ranks) {
  const CaseConfig c = load_case(path, overrides);
  const Grid g = build_grid(c, ranks);
  const BlockAssignment a = assign_blocks(g, ranks);
  fmt::print("{}: {} cells in {} block(s) over {} rank(s), load imbalance {:.2f} %\n", path, g.cells(), g.blocks.size(),
             ranks, 100.0 * a.imbalance());
  std::size_t total_halo = 0;
  for (int r = 0; r < ranks; ++r) {
    const ExchangePlan plan = build_exchange_plan(g, a.owner, r);
    std::size_t messages = 0;
    for (const HaloPeer& p : plan.peers) messages += p.rank != r && !p.send.empty();
    int blocks = 0;
    for (int o : a.owner) blocks += o == r;
    fmt::print("  rank {:3d}: {:4d} block(s), {:9d} cells, sends {:8d} halo cells in {:3d} message(s)\n", r, blocks,
               a.cells[r], plan.sent_cells(), messages);
    total_halo += plan.sent_cells();
  }
  fmt::print("  halo per exchange: {} cells, {:.2f} % of the cells\n", total_halo, 100.0 * total_halo / g.cells());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  narwhal::ParallelSession session(argc, argv);  // MPI_Init / MPI_Finalize in MPI builds
  const narwhal::Communicator comm = narwhal::Communicator::world();
  CLI::App app{"Narwhal: implicit artificial-compressibility RANS solver (McDonald & Whitfield 1997 method)"};
  app.set_version_flag("--version", fmt::format("narwhal {} ({}, {})", kVersion, kGitSha,
                                                built_with_mpi() ? "MPI" : "no MPI"));
  // Started by mpirun on several ranks but built without MPI: every process would run
  // the whole case alone and write the same files.
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_SIZE"}) {
    const char* v = std::getenv(var);
    if (!built_with_mpi() && v && std::atoi(v) > 1) {
      fmt::print(stderr, "narwhal: error: started on {} ranks ({}), but this narwhal was built without MPI "
                         "(configure with -DNARWHAL_MPI=ON)\n", v, var);
      return 2;
    }
  }
  app.require_subcommand(1);

  std::string case_path, out_dir = "run", restart;
  int max_iterations = -1;
  std::vector<std::string> overrides;
  auto* run = app.add_subcommand("run", "run a case: writes history.csv, surface_*.csv, solution.cgns, restart.h5, run.json");
  run->add_option("case", case_path, "case file (TOML)")->required();
  run->add_option("--out,-o", out_dir, "output directory")->capture_default_str();
  run->add_option("--restart", restart, "continue from this restart.h5");
  run->add_option("--max-iterations", max_iterations, "override solver.max_iterations")
      ->check(CLI::Range(0, 1000000000));
  run->add_option("--set", overrides, "override a case key, e.g. --set grid.cells_plate=48 (value in TOML syntax)");

  std::string check_path;
  auto* check = app.add_subcommand("check", "validate a case file and its grid without running");
  check->add_option("case", check_path, "case file (TOML)")->required();
  check->add_option("--set", overrides, "override a case key (value in TOML syntax)");

  std::string partition_path;
  int ranks = 2;
  auto* partition = app.add_subcommand("partition", "show how a case's blocks would be cut and shared over MPI ranks");
  partition->add_option("case", partition_path, "case file (TOML)")->required();
  partition->add_option("--ranks,-n", ranks, "number of ranks")->capture_default_str()->check(CLI::PositiveNumber);
  partition->add_option("--set", overrides, "override a case key (value in TOML syntax)");

  std::string grid_path, grid_out = "grid";
  auto* grid = app.add_subcommand("grid", "write a case's grid (grid.cgns, grid.xyz) and print its quality report");
  grid->add_option("case", grid_path, "case file (TOML)")->required();
  grid->add_option("--out,-o", grid_out, "output directory")->capture_default_str();
  grid->add_option("--set", overrides, "override a case key (value in TOML syntax)");
  std::string grid_openfoam;
  grid->add_option("--openfoam", grid_openfoam,
                   "also write the grid as an OpenFOAM case's constant/polyMesh under this directory");

  std::string simulate_path, model_path, simulate_out = "simulation";
  auto* simulate_cmd = app.add_subcommand(
      "simulate", "fly a case's manoeuvre with a manoeuvring model instead of the flow: writes motion.csv, controls.csv");
  simulate_cmd->add_option("case", simulate_path, "case file (TOML) with a free [motion] and [time]")->required();
  simulate_cmd->add_option("--model,-m", model_path, "the manoeuvring model (TOML: [coefficients], [propulsion])")
      ->required();
  simulate_cmd->add_option("--out,-o", simulate_out, "output directory")->capture_default_str();
  simulate_cmd->add_option("--set", overrides, "override a case key (value in TOML syntax)");

  auto* list_models = app.add_subcommand("list-models", "list the turbulence models (turbulence.model = \"name\")");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the message and the usage
    return 2;     // every input error exits 2 (README)
  }
  try {
    if (*list_models) {
      std::size_t width = 0;
      for (const auto& m : turbulence_models()) width = std::max(width, m.name.size());
      for (const auto& m : turbulence_models()) fmt::print("{:<{}}  {}\n", m.name, width, m.summary);
      return 0;
    }
    if (*check) return check_case(check_path, overrides);
    if (*simulate_cmd) {
      const SimulationSummary s =
          simulate(load_case(simulate_path, overrides), load_manoeuvring_model(model_path), simulate_out);
      fmt::print("narwhal: simulated {} steps in {:.2f} s: {}/motion.csv\n", s.steps, s.seconds, simulate_out);
      return 0;
    }
    if (*grid) return grid_case(grid_path, overrides, grid_out, grid_openfoam);
    if (*partition) return partition_case(partition_path, overrides, ranks);
    RunOptions opt;
    opt.out_dir = out_dir;
    if (!restart.empty()) opt.restart = restart;
    if (max_iterations >= 0) opt.max_iterations = max_iterations;
    opt.progress = isatty(STDOUT_FILENO) && comm.is_root();
    const RunSummary s = run_case(load_case(case_path, overrides), opt);
    return s.status == RunStatus::Diverged ? 3 : (s.status == RunStatus::Converged || s.status == RunStatus::Completed ? 0 : 1);
  } catch (const Error& e) {
    fmt::print(stderr, "narwhal: error{}: {}\n", comm.size() > 1 ? fmt::format(" (rank {})", comm.rank()) : "",
               e.what());
    // An error seen by one rank would leave the others waiting in a collective.
    if (comm.size() > 1) comm.abort(2);
    return 2;
  } catch (const std::bad_alloc&) {
    fmt::print(stderr, "narwhal: error: out of memory (the grid or the case asks for more than this machine has)\n");
    if (comm.size() > 1) comm.abort(2);
    return 2;
  } catch (const std::exception& e) {
    // Not a known input error: a defect to report, but still a message and no core dump.
    fmt::print(stderr, "narwhal: internal error: {}\n", e.what());
    if (comm.size() > 1) comm.abort(4);
    return 4;
  }
}
