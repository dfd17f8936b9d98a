// Layout micro-benchmarks (issue #4): which storage to use for the block Jacobians
// in the SGS sweep, and whether the flow field should be AoS or SoA. Synthetic,
// diagonally dominant data on one structured block large enough (96 x 96 x 8 cells,
// ~66 MB of matrices) to stream from memory.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "core/types.hpp"
#include "fields/ghost_array.hpp"
#include "physics/ac_flux.hpp"
#include "physics/muscl.hpp"

using namespace narwhal;

namespace {

constexpr int NI = 96, NJ = 96, NK = 8;

Mat4 random_block(std::mt19937_64& rng, Real scale) {
  std::uniform_real_distribution<Real> U(-1.0, 1.0);
  Mat4 m;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m(r, c) = scale * U(rng);
  return m;
}

// (a) Current storage: face Jacobians per direction (AL, AR), inverse diagonal per cell.
struct PerFace {
  std::array<GhostArray<Mat4>, 3> AL, AR;
  GhostArray<Mat4> Dinv;
  GhostArray<State> R, dQ;
  PerFace() {
    std::mt19937_64 rng(3);
    for (int d = 0; d < 3; ++d) {
      Index3 n{NI, NJ, NK};
      n[d] += 1;
      AL[d].resize(n[0], n[1], n[2], 0);
      AR[d].resize(n[0], n[1], n[2], 0);
      for (auto& m : AL[d].raw()) m = random_block(rng, 0.05);
      for (auto& m : AR[d].raw()) m = random_block(rng, 0.05);
    }
    Dinv.resize(NI, NJ, NK, 0);
    for (auto& m : Dinv.raw()) m = Mat4::Identity() + random_block(rng, 0.01);
    R.resize(NI, NJ, NK, 0, State::Ones());
    dQ.resize(NI, NJ, NK, 1, State::Zero());
  }
  void relax(int i, int j, int k) {
    State r = -R(i, j, k);
    r.noalias() -= AR[0](i + 1, j, k) * dQ(i + 1, j, k);
    r.noalias() += AL[0](i, j, k) * dQ(i - 1, j, k);
    r.noalias() -= AR[1](i, j + 1, k) * dQ(i, j + 1, k);
    r.noalias() += AL[1](i, j, k) * dQ(i, j - 1, k);
    r.noalias() -= AR[2](i, j, k + 1) * dQ(i, j, k + 1);
    r.noalias() += AL[2](i, j, k) * dQ(i, j, k - 1);
    dQ(i, j, k) = Dinv(i, j, k) * r;
  }
};

// (b) All seven blocks of a cell packed contiguously, in the order the sweep reads them.
struct PackedCell {
  Mat4 Dinv;
  std::array<Mat4, 6> O;  // -AR(i+1), +AL(i), -AR(j+1), +AL(j), -AR(k+1), +AL(k)
};
struct PerCell {
  std::vector<PackedCell> cells;
  GhostArray<State> R, dQ;
  PerCell() {
    std::mt19937_64 rng(3);
    cells.resize(static_cast<std::size_t>(NI) * NJ * NK);
    for (auto& c : cells) {
      c.Dinv = Mat4::Identity() + random_block(rng, 0.01);
      for (auto& o : c.O) o = random_block(rng, 0.05);
    }
    R.resize(NI, NJ, NK, 0, State::Ones());
    dQ.resize(NI, NJ, NK, 1, State::Zero());
  }
  void relax(int i, int j, int k) {
    const PackedCell& c = cells[(static_cast<std::size_t>(k) * NJ + j) * NI + i];
    State r = -R(i, j, k);
    r.noalias() += c.O[0] * dQ(i + 1, j, k);
    r.noalias() += c.O[1] * dQ(i - 1, j, k);
    r.noalias() += c.O[2] * dQ(i, j + 1, k);
    r.noalias() += c.O[3] * dQ(i, j - 1, k);
    r.noalias() += c.O[4] * dQ(i, j, k + 1);
    r.noalias() += c.O[5] * dQ(i, j, k - 1);
    dQ(i, j, k) = c.Dinv * r;
  }
};

template <class L>
void sweep_pair(L& l) {
  for (int k = 0; k < NK; ++k)
    for (int j = 0; j < NJ; ++j)
      for (int i = 0; i < NI; ++i) l.relax(i, j, k);
  for (int k = NK - 1; k >= 0; --k)
    for (int j = NJ - 1; j >= 0; --j)
      for (int i = NI - 1; i >= 0; --i) l.relax(i, j, k);
}

void BM_Layout_SgsPerFaceJacobians(benchmark::State& st) {
  PerFace l;
  for (auto _ : st) sweep_pair(l);
  st.SetItemsProcessed(st.iterations() * NI * NJ * NK);
}
BENCHMARK(BM_Layout_SgsPerFaceJacobians)->Unit(benchmark::kMillisecond);

void BM_Layout_SgsPackedPerCell(benchmark::State& st) {
  PerCell l;
  for (auto _ : st) sweep_pair(l);
  st.SetItemsProcessed(st.iterations() * NI * NJ * NK);
}
BENCHMARK(BM_Layout_SgsPackedPerCell)->Unit(benchmark::kMillisecond);

// Field layout under the face loop of the residual: MUSCL + Roe along i, the cell
// states fetched by `load` (one array of states, or four arrays of scalars).
template <class Load>
void flux_sweep(benchmark::State& st, Load load) {
  const FaceGeom f{Vec3(1e-2, 0.0, 0.0), 0.0};
  MusclParams mp;
  for (auto _ : st)
    for (int k = 0; k < NK; ++k)
      for (int j = 0; j < NJ; ++j)
        for (int i = 1; i < NI; ++i) {
          const State qL = muscl_left<State>(load(i - 2, j, k), load(i - 1, j, k), load(i, j, k), mp);
          const State qR = muscl_right<State>(load(i - 1, j, k), load(i, j, k), load(i + 1, j, k), mp);
          benchmark::DoNotOptimize(roe_flux<Real>(qL, qR, f, 5.0));
        }
  st.SetItemsProcessed(st.iterations() * (NI - 1) * NJ * NK);
}

void BM_Layout_FluxAoS(benchmark::State& st) {
  GhostArray<State> Q(NI, NJ, NK, 2, State(0.0, 1.0, 0.1, 0.0));
  flux_sweep(st, [&](int i, int j, int k) -> const State& { return Q(i, j, k); });
}
BENCHMARK(BM_Layout_FluxAoS)->Unit(benchmark::kMillisecond);

void BM_Layout_FluxSoA(benchmark::State& st) {
  std::array<GhostArray<Real>, 4> Q;
  const Real init[4] = {0.0, 1.0, 0.1, 0.0};
  for (int m = 0; m < 4; ++m) Q[m].resize(NI, NJ, NK, 2, init[m]);
  flux_sweep(st, [&](int i, int j, int k) { return State(Q[0](i, j, k), Q[1](i, j, k), Q[2](i, j, k), Q[3](i, j, k)); });
}
BENCHMARK(BM_Layout_FluxSoA)->Unit(benchmark::kMillisecond);

}  // namespace
