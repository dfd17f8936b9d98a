// Kernel benchmarks (Google Benchmark). Rates are reported per face or per cell
// ("items_per_second"); the laminar flat plate of the R1 rung is the test grid.
// Run: build/benchmarks/narwhal_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <vector>

#include "app/driver.hpp"
#include "app/grid_shapes.hpp"
#include "app/turbulence_coupling.hpp"
#include "bc/boundary.hpp"
#include "implicit/jacobian.hpp"
#include "multigrid/fas.hpp"
#include "physics/ac_flux.hpp"
#include "physics/invariant_direction.hpp"
#include "physics/residual.hpp"
#include "turbulence/model.hpp"
#include "turbulence/wall_distance.hpp"

using namespace narwhal;

namespace {

struct FaceSet {
  std::vector<State> q;  // 4 cells per face: i-1, i, i+1, i+2
  std::vector<FaceGeom> f;
};

FaceSet random_faces(int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<Real> U(-1.0, 1.0);
  FaceSet s;
  for (int m = 0; m < 4 * n; ++m) s.q.emplace_back(0.1 * U(rng), 1.0 + 0.2 * U(rng), 0.2 * U(rng), 0.2 * U(rng));
  for (int m = 0; m < n; ++m) s.f.push_back({Vec3(U(rng), U(rng), U(rng)), 0.0});
  return s;
}

void BM_RoeFluxMuscl(benchmark::State& st) {
  const int n = 4096;
  const FaceSet s = random_faces(n);
  MusclParams mp;
  for (auto _ : st) {
    for (int m = 0; m < n; ++m) {
      const State* q = &s.q[4 * m];
      const State qL = muscl_left<State>(q[0], q[1], q[2], mp), qR = muscl_right<State>(q[1], q[2], q[3], mp);
      benchmark::DoNotOptimize(roe_flux<Real>(qL, qR, s.f[m], 5.0));
    }
  }
  st.SetItemsProcessed(st.iterations() * n);
}
BENCHMARK(BM_RoeFluxMuscl);

void BM_NumericalJacobianPerFace(benchmark::State& st) {
  const int n = 4096;
  const FaceSet s = random_faces(n);
  for (auto _ : st) {
    for (int m = 0; m < n; ++m) {
      const State& qL = s.q[4 * m + 1];
      const State& qR = s.q[4 * m + 2];
      const State F0 = roe_flux<Real>(qL, qR, s.f[m], 5.0);
      benchmark::DoNotOptimize(numerical_jacobian([&](const State& q) { return roe_flux<Real>(q, qR, s.f[m], 5.0); }, qL, F0, 1e-7));
      benchmark::DoNotOptimize(numerical_jacobian([&](const State& q) { return roe_flux<Real>(qL, q, s.f[m], 5.0); }, qR, F0, 1e-7));
    }
  }
  st.SetItemsProcessed(st.iterations() * n);
}
BENCHMARK(BM_NumericalJacobianPerFace);

// The R1 flat plate, advanced a few iterations so the state is a real flow.
// `planar`: skip the symmetry planes as `narwhal run` does for this case
// (physics/invariant_direction.hpp); the sweep benchmarks keep the full 3-D path, whose bytes
// per cell the roofline in benchmarks/README.md counts.
struct Plate {
  CaseConfig c;
  Grid g;
  FlowField f;
  FlowParams fp;
  explicit Plate(std::vector<std::string> sets = {}, bool planar = true) {
    c = load_case(std::string(NARWHAL_SOURCE_DIR) + "/validation/cases/flat_plate_laminar/flat_plate.toml", sets);
    g = build_grid(c);
    fp = flow_params(c);
    f.allocate(g, fp, c.initial);
    if (planar) {
      mark_invariant_directions(g, f, fp);
      if (g.blocks[0].invariant_dir < 0) throw std::runtime_error("the R1 plate should be a planar slab");
    }
  }
};

void BM_ResidualPerCell(benchmark::State& st) {
  Plate p;
  std::vector<GhostArray<State>> R;
  for (auto _ : st) {
    fill_ghosts(p.g, p.f, p.fp);
    compute_residual(p.g, p.f, p.fp, R);
  }
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_ResidualPerCell)->Unit(benchmark::kMillisecond);

void BM_NewtonIterationPerCell(benchmark::State& st) {
  Plate p({"solver.sgs_iterations=1"});
  NewtonSolver s(p.g, p.f, p.fp, p.c.solver.newton, Communicator::world());
  for (int i = 0; i < 10; ++i) s.iterate();
  for (auto _ : st) s.iterate();  // residual, Jacobians, one SGS pair, update
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_NewtonIterationPerCell)->Unit(benchmark::kMillisecond);

// The same on a 3-D grid (manufactured-solution box, 24^3 cells), where boundary
// faces are a small share of all faces, as in production grids.
void BM_NewtonIterationPerCell3D(benchmark::State& st) {
  const CaseConfig c = load_case(std::string(NARWHAL_SOURCE_DIR) + "/validation/cases/mms/mms.toml",
                                 {"grid.cells=24", "solver.sgs_iterations=1"});
  Grid g = build_grid(c);
  const FlowParams fp = flow_params(c);
  FlowField f;
  f.allocate(g, fp, c.initial);
  NewtonSolver s(g, f, fp, c.solver.newton, Communicator::world());
  for (int i = 0; i < 10; ++i) s.iterate();
  for (auto _ : st) s.iterate();
  st.SetItemsProcessed(st.iterations() * g.cells());
}
BENCHMARK(BM_NewtonIterationPerCell3D)->Unit(benchmark::kMillisecond);

void BM_SgsSweepPairPerCell(benchmark::State& st) {
  Plate p({}, false);
  NewtonSolver s(p.g, p.f, p.fp, p.c.solver.newton, Communicator::world());
  for (int i = 0; i < 10; ++i) s.iterate();
  for (auto _ : st) s.sweeps_only(1);  // one forward + one backward sweep
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_SgsSweepPairPerCell)->Unit(benchmark::kMillisecond);

// The check of every correction (NewtonSolver::relax_and_update): R + A dQ over all cells,
// to set beside a sweep pair's cost.
void BM_LinearResidualCheckPerCell(benchmark::State& st) {
  Plate p({}, false);
  NewtonSolver s(p.g, p.f, p.fp, p.c.solver.newton, Communicator::world());
  for (int i = 0; i < 10; ++i) s.iterate();
  for (auto _ : st) benchmark::DoNotOptimize(s.linear_residual_ratio_collective(1.0));
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_LinearResidualCheckPerCell)->Unit(benchmark::kMillisecond);

// The 2x finer plate (32768 cells): the block matrices (~32 MB) no longer fit in
// cache, so this sweep is the one compared with the memory-bandwidth bound.
void BM_SgsSweepPairPerCellFine(benchmark::State& st) {
  Plate p({"grid.cells_runup=64", "grid.cells_plate=192", "grid.cells_normal=128", "grid.dx_leading_edge=1.0e-3",
           "grid.dy_wall=5.0e-5"},
          false);
  NewtonSolver s(p.g, p.f, p.fp, p.c.solver.newton, Communicator::world());
  for (int i = 0; i < 3; ++i) s.iterate();
  for (auto _ : st) s.sweeps_only(1);
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_SgsSweepPairPerCellFine)->Unit(benchmark::kMillisecond);

void BM_MultigridVCyclePerCell(benchmark::State& st) {
  Plate p;
  MultigridSettings ms;
  ms.levels = 4;
  ms.gamma = 1;
  Multigrid mg(p.g, p.f, p.fp, p.c.solver.newton, ms, Communicator::world());
  for (int i = 0; i < 5; ++i) mg.cycle();
  for (auto _ : st) mg.cycle();
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_MultigridVCyclePerCell)->Unit(benchmark::kMillisecond);

// A turbulent case of the ladder (path under validation/cases/, with --set values), set
// up as `narwhal run` does (planar where a direction is invariant); cycle() advances it
// one multigrid cycle with the model updated.
struct TurbulentCase {
  CaseConfig c;
  Grid g;
  FlowField f;
  FlowParams fp;
  std::unique_ptr<Multigrid> mg;
  std::unique_ptr<TurbulenceCoupling> coupling;
  TurbulenceModel* model = nullptr;
  TurbulentCase(const std::string& case_path, const std::vector<std::string>& sets) {
    c = load_case(std::string(NARWHAL_SOURCE_DIR) + "/validation/cases/" + case_path, sets);
    g = build_grid(c);
    fp = flow_params(c);
    f.allocate(g, fp, c.initial);
    mark_invariant_directions(g, f, fp);
    mg = std::make_unique<Multigrid>(g, f, fp, c.solver.newton, c.solver.multigrid, Communicator::world());
    coupling = std::make_unique<TurbulenceCoupling>(c.turbulence, g, f, fp, mg.get(), false, Communicator::world());
    model = coupling->model();
  }
  void cycle() { coupling->after_mean_flow_step(mg->cycle().cfl); }
};

// The TMR plate's 137 x 97 level with a turbulence model (planar).
struct TurbulentPlate : TurbulentCase {
  TurbulentPlate(const std::string& model_name, std::vector<std::string> sets)
      : TurbulentCase("tmr_flat_plate/flat_plate_" + model_name + ".toml", with_coarsening(std::move(sets))) {}
  static std::vector<std::string> with_coarsening(std::vector<std::string> sets) {
    sets.push_back("grid.coarsen=1");
    return sets;
  }
};

// One turbulent V-cycle (SA, its default scheme: the model updated after every
// fine-level smoothing step with line relaxation), per cell of the finest level. Four
// mean-flow Gauss-Seidel pairs, fixed, so that the history measures the kernels (the
// plate case took four until it took 32, issue 15; whole runs are timed in run.json).
void BM_TurbulentVCyclePerCell(benchmark::State& st) {
  TurbulentPlate p("sa", {"solver.sgs_iterations=4"});
  for (int i = 0; i < 10; ++i) p.cycle();
  for (auto _ : st) p.cycle();
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_TurbulentVCyclePerCell)->Unit(benchmark::kMillisecond);

// One model update (assembly, 8 sweep pairs, update) of SA, with the line (arg 1)
// or the point (arg 0) smoother: what a line costs against a point.
void BM_TurbulenceUpdatePerCell(benchmark::State& st) {
  TurbulentPlate p("sa", {st.range(0) ? "turbulence.smoother=\"lines\"" : "turbulence.smoother=\"points\""});
  for (int i = 0; i < 10; ++i) p.cycle();
  for (auto _ : st) p.model->advance(p.g, p.f, p.fp, 1e6);
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_TurbulenceUpdatePerCell)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// One SST update with line relaxation (assembly, 8 sweep pairs, update) on the quick
// appended SUBOFF member (AFF-8, scale 0.25 of appended.toml, 154 k cells): a 3-D grid whose
// blocks relax along each of the three index directions (turbulence/DESIGN.md, "Lines in
// memory order"). Started from five cycles of the case.
void BM_TurbulenceUpdateAppendedPerCell(benchmark::State& st) {
  TurbulentCase p("suboff_appended/appended.toml", {"grid.scale=0.25"});
  for (int i = 0; i < 5; ++i) p.cycle();
  for (auto _ : st) p.model->advance(p.g, p.f, p.fp, 1e6);
  st.SetItemsProcessed(st.iterations() * p.g.cells());
}
BENCHMARK(BM_TurbulenceUpdateAppendedPerCell)->Unit(benchmark::kMillisecond);

// The wall distance of every cell of the quick appended SUBOFF member (AFF-8, scale 0.25 of
// appended.toml: 154 k cells, 6 walls), as each turbulent run's start pays it.
void BM_WallDistancePerCell(benchmark::State& st) {
  const CaseConfig c = load_case(std::string(NARWHAL_SOURCE_DIR) + "/validation/cases/suboff_appended/appended.toml",
                                 {"grid.scale=0.25"});
  const Grid g = build_grid(c);
  for (auto _ : st) benchmark::DoNotOptimize(compute_wall_distance(g));
  st.SetItemsProcessed(st.iterations() * g.cells());
}
BENCHMARK(BM_WallDistancePerCell)->Unit(benchmark::kMillisecond);

// The grids of R7c's manoeuvring vehicle (209 k cells) rebuilt with its stern planes
// turned, as a manoeuvre on two ranks does whenever a surface moves: the pieces for two
// ranks and the case's own blocks (app/grid_shapes.hpp), per cell. (Its grid at half the
// cell counts folds a cell of the stern planes' boxes at any deflection.)
void BM_ControlSurfaceRebuildPerCell(benchmark::State& st) {
  const CaseConfig c =
      load_case(std::string(NARWHAL_SOURCE_DIR) + "/validation/cases/suboff_manoeuvres/vehicle_grid.toml", {});
  const GridShapes shapes(c, 2, 1, true);
  Real angle = 0.0;
  for (auto _ : st) {
    angle += 1.0e-3;  // a new angle each time, as the autopilot's
    benchmark::DoNotOptimize(shapes.at(suboff::Deflections{0.0, angle, 0.0}));
  }
  st.SetItemsProcessed(st.iterations() * build_grid(c).cells());
}
BENCHMARK(BM_ControlSurfaceRebuildPerCell)->Unit(benchmark::kMillisecond)->Iterations(3);

// STREAM-like triad a = b + s c over arrays far larger than the caches: the
// machine's sustainable memory bandwidth (bytes_per_second: 3 x 8 bytes per element).
void BM_StreamTriad(benchmark::State& st) {
  const std::size_t n = 1u << 25;  // 32 M doubles per array, 768 MB in all
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  for (auto _ : st) {
    for (std::size_t i = 0; i < n; ++i) a[i] = b[i] + 3.0 * c[i];
    benchmark::ClobberMemory();
  }
  st.SetBytesProcessed(st.iterations() * n * 3 * sizeof(double));
}
BENCHMARK(BM_StreamTriad)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
