#include "multigrid/fas.hpp"

#include "bc/boundary.hpp"
#include "core/error.hpp"
#include "mesh/ghost_sweep.hpp"
#include "multigrid/coarsen.hpp"
#include "parallel/halo.hpp"

namespace narwhal {
namespace {

// Ghosts of a coarse-grid correction (§7.3): homogeneous version of each BC.
void fill_correction_ghosts(Grid& g, std::vector<GhostArray<State>>& dq) {
  auto physical = [&](int ib, const Patch& p, int m) {
    const Block& b = g.blocks[ib];
    auto& D = dq[ib];
    const PatchRange r = extended_cell_range(b, p);
    for_each_in(r, [&](Index3 c) {
      const Vec3 n = outward_face(b, p.side, c).S.normalized();
      State q = D(interior_cell(b, p.side, c, m));
      switch (p.type) {
        case BcType::Wall: q.tail<3>() = -q.tail<3>(); break;                      // Dirichlet velocity
        case BcType::Dirichlet: q = -q; break;                                      // all components fixed
        case BcType::Symmetry: q.tail<3>() -= 2.0 * n.dot(q.tail<3>()) * n; break;  // mirror
        default: break;                                                             // characteristic: extrapolate
      }
      D(ghost_cell(b, p.side, c, m)) = q;
    });
  };
  owned_ghost_sweep(g, physical, [&](const ExchangePlan& plan) { exchange(g, plan, dq, RotateVelocity{}); });
}

}  // namespace

Multigrid::Multigrid(Grid& fine, FlowField& field, const FlowParams& fp, const NewtonSettings& ns,
                     MultigridSettings ms, const Communicator& comm)
    : ms_(ms) {
  if (ms.levels < 1) fail("multigrid: the number of levels must be >= 1");
  if (ms.gamma < 1 || ms.gamma > 2) fail("multigrid: gamma must be 1 (V-cycle) or 2 (W-cycle)");
  Level top;
  top.grid = &fine;
  top.field = &field;
  top.fp = fp;
  levels_.push_back(std::move(top));
  CoarseLevels coarse = coarse_levels(fine, ms.levels, ms.min_cells);
  if (!coarse.stop.empty())
    note_ = fmt::format("multigrid: {} level(s) instead of {}: {}", coarse.grids.size() + 1, ms.levels, coarse.stop);
  for (Grid& g : coarse.grids) {
    Level l;
    l.owned = std::make_unique<Grid>(std::move(g));
    l.grid = l.owned.get();
    l.fp = fp;
    l.fp.muscl.phi = 0.0;  // §7.3: first-order inviscid flux on coarse levels
    l.owned_field = std::make_unique<FlowField>();
    l.owned_field->allocate(*l.grid, l.fp, State::Zero());
    l.field = l.owned_field.get();
    levels_.push_back(std::move(l));
  }
  for (auto& l : levels_) {
    l.solver = std::make_unique<NewtonSolver>(*l.grid, *l.field, l.fp, ns, comm);
    l.forcing.resize(l.grid->blocks.size());
    l.q0.resize(l.grid->blocks.size());
    l.correction.resize(l.grid->blocks.size());
    for (std::size_t ib = 0; ib < l.grid->blocks.size(); ++ib) {
      if (!l.grid->owns(ib)) continue;  // other ranks' blocks: no storage
      const Block& b = l.grid->blocks[ib];
      l.forcing[ib].resize(b.ni, b.nj, b.nk, 0, State::Zero());
      l.q0[ib].resize(b.ni, b.nj, b.nk, 0, State::Zero());
      l.correction[ib].resize(b.ni, b.nj, b.nk, kGhost, State::Zero());
    }
  }
  for (std::size_t l = 1; l < levels_.size(); ++l) levels_[l].solver->set_forcing(&levels_[l].forcing);
}

// `fresh`: the residual of the current state was just evaluated; the first
// iteration reuses it instead of evaluating it again.
// Returns the CFL the level accepted (lower than `cfl` when a correction was rejected).
Real Multigrid::smooth(int l, int iterations, Real cfl, const IterationNorms* fresh, bool reuse) {
  for (int it = 0; it < iterations; ++it) {
    if (it == 0 && fresh)
      cfl = levels_[l].solver->relax_and_update(*fresh, cfl, reuse).cfl;
    else
      cfl = levels_[l].solver->iterate_with_cfl(cfl, reuse && it == 0).cfl;
    if (l == 0 && after_fine_smoothing_) after_fine_smoothing_(cfl);
  }
  return cfl;
}

void Multigrid::restrict_to(int l) {
  Level& fine = levels_[l - 1];
  Level& coarse = levels_[l];
  fine.solver->evaluate_residual();  // R_h(Q_h) - f_h at the smoothed state
  const auto& rh = fine.solver->residual();
  for (std::size_t ib = 0; ib < coarse.grid->blocks.size(); ++ib) {
    if (!coarse.grid->owns(ib)) continue;
    const Block& bh = fine.grid->blocks[ib];
    const Block& bH = coarse.grid->blocks[ib];
    const Index3 c = coarsening_factors(bh);
    auto& QH = coarse.field->Q[ib];
    auto& nuH = coarse.field->nu[ib];
    for_each_cell(bH, [&](int I, int J, int K) {
      State q = State::Zero();
      State r = State::Zero();
      Real nu = 0.0, v = 0.0;
      for (int dk = 0; dk < c[2]; ++dk)
        for (int dj = 0; dj < c[1]; ++dj)
          for (int di = 0; di < c[0]; ++di) {
            const int i = c[0] * I + di, j = c[1] * J + dj, k = c[2] * K + dk;
            q += bh.vol(i, j, k) * fine.field->Q[ib](i, j, k);
            r += rh[ib](i, j, k);
            nu += bh.vol(i, j, k) * fine.field->nu[ib](i, j, k);
            v += bh.vol(i, j, k);
          }
      QH(I, J, K) = q / bH.vol(I, J, K);  // volume-weighted solution restriction
      nuH(I, J, K) = nu / v;  // the eddy viscosity, frozen during the cycle (§8.6 loose coupling)
      coarse.q0[ib](I, J, K) = QH(I, J, K);
      coarse.forcing[ib](I, J, K) = -r;    // summed residual, completed below
    });
  }
  // f_H = N_H(Q_H^0) + sum(f_h - N_h(Q_h)) (§7.2 step 4).
  coarse.solver->set_forcing(nullptr);
  coarse.solver->evaluate_residual();
  const auto& RH = coarse.solver->residual();
  for (std::size_t ib = 0; ib < coarse.grid->blocks.size(); ++ib) {
    if (!coarse.grid->owns(ib)) continue;
    auto& f = coarse.forcing[ib].raw();
    const auto& r = RH[ib].raw();
    for (std::size_t n = 0; n < f.size(); ++n) f[n] += r[n];
  }
  coarse.solver->set_forcing(&coarse.forcing);
}

void Multigrid::prolong_from(int l) {
  Level& fine = levels_[l - 1];
  Level& coarse = levels_[l];
  for (std::size_t ib = 0; ib < coarse.grid->blocks.size(); ++ib) {
    if (!coarse.grid->owns(ib)) continue;
    const Block& bH = coarse.grid->blocks[ib];
    for_each_cell(bH, [&](int I, int J, int K) {
      coarse.correction[ib](I, J, K) = coarse.field->Q[ib](I, J, K) - coarse.q0[ib](I, J, K);
    });
  }
  fill_correction_ghosts(*coarse.grid, coarse.correction);
  for (std::size_t ib = 0; ib < fine.grid->blocks.size(); ++ib) {
    if (!fine.grid->owns(ib)) continue;
    const Block& bh = fine.grid->blocks[ib];
    const Index3 c = coarsening_factors(bh);
    const auto& D = coarse.correction[ib];
    auto& Q = fine.field->Q[ib];
    for_each_cell(bh, [&](int i, int j, int k) {
      const Index3 fc{i, j, k};
      Index3 parent, side;
      for (int d = 0; d < 3; ++d) {
        parent[d] = fc[d] / c[d];
        side[d] = (c[d] == 2 && !ms_.injection) ? (fc[d] % 2 == 0 ? -1 : 1) : 0;
      }
      // Trilinear in index space: 3/4 from the parent, 1/4 from the neighbour on
      // the octant's side, per coarsened direction (27/64, 9/64, 3/64, 1/64 in 3-D).
      State dq = State::Zero();
      for (int ok = 0; ok <= (side[2] != 0); ++ok)
        for (int oj = 0; oj <= (side[1] != 0); ++oj)
          for (int oi = 0; oi <= (side[0] != 0); ++oi) {
            const Real w = (side[0] ? (oi ? 0.25 : 0.75) : 1.0) * (side[1] ? (oj ? 0.25 : 0.75) : 1.0) *
                           (side[2] ? (ok ? 0.25 : 0.75) : 1.0);
            dq += w * D(parent[0] + oi * side[0], parent[1] + oj * side[1], parent[2] + ok * side[2]);
          }
      Q(i, j, k) += dq;
    });
  }
}

// Returns the CFL the level's last smoothing accepted (a rejected correction lowers it for
// the rest of the cycle, coarser levels included).
Real Multigrid::visit(int l, Real cfl, const IterationNorms* fresh, bool frozen) {
  const int last = static_cast<int>(levels_.size()) - 1;
  if (l == last) return smooth(l, l == 0 ? 1 : ms_.coarse_smooth, cfl, fresh, frozen);
  cfl = smooth(l, ms_.pre_smooth, cfl, fresh, frozen);
  restrict_to(l + 1);
  for (int g = 0; g < ms_.gamma; ++g) visit(l + 1, cfl, nullptr, frozen);
  prolong_from(l + 1);
  return smooth(l, ms_.post_smooth, cfl, nullptr, ms_.reuse_jacobian);
}

void Multigrid::use_physical_time(const PhysicalTimeTerm* finest) {
  finest_time_ = finest;
  levels_[0].solver->set_physical_time(finest);
  for (std::size_t l = 1; l < levels_.size(); ++l) {
    levels_[l].time = finest ? std::make_unique<PhysicalTimeTerm>(*levels_[l].grid, false) : nullptr;
    levels_[l].solver->set_physical_time(levels_[l].time.get());
  }
}

IterationNorms Multigrid::cycle() {
  NewtonSolver& top = *levels_[0].solver;
  IterationNorms n = top.evaluate_residual();
  n.cfl = top.ser_cfl(n.total);
  return run_cycle(n);
}

IterationNorms Multigrid::cycle_with_cfl(Real cfl) {
  IterationNorms n = levels_[0].solver->evaluate_residual();
  n.cfl = cfl;
  return run_cycle(n);
}

IterationNorms Multigrid::run_cycle(IterationNorms n) {
  if (finest_time_)
    for (std::size_t l = 1; l < levels_.size(); ++l)
      levels_[l].time->set_step(finest_time_->dt(), finest_time_->coefficients());
  // Jacobian freezing: between reassemblies every level keeps its block matrices.
  const bool frozen = ms_.jacobian_interval > 1 && cycles_ % ms_.jacobian_interval != 0;
  for (auto& l : levels_) l.solver->allow_stale_cfl(frozen);
  n.cfl = visit(0, n.cfl, &n, frozen);
  ++cycles_;
  return n;
}

}  // namespace narwhal
