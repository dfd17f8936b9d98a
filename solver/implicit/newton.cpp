#include "implicit/newton.hpp"

#include <cmath>
#include <limits>

#include <Eigen/LU>

#include "bc/boundary.hpp"
#include "implicit/jacobian.hpp"
#include "mesh/ghost_sweep.hpp"
#include "physics/ac_flux.hpp"
#include "physics/residual.hpp"
#include "parallel/communicator.hpp"
#include "parallel/reduction.hpp"

namespace narwhal {

namespace {

// First-order boundary flux as a function of the first interior state (§5.0):
// the ghost follows Q_1 through the BC, external data held fixed. The geometry of
// the face is gathered once; `operator()` is what the Jacobian differences.
struct BoundaryFaceFlux {
  const Patch& p;
  const FlowParams& fp;
  bool high;
  FaceGeom face, outward;
  Vec3 n, xface, u_wall = Vec3::Zero();
  Real d_wall = 0.0, tl = 0.0;
  State ghost_exact = State::Zero();

  BoundaryFaceFlux(const Block& b, const Patch& patch, const Index3& c, const GhostArray<Real>& nu,
                   const FlowParams& params)
      : p(patch), fp(params), high(side_high(patch.side)) {
    const int d = side_dir(p.side);
    const Index3 f = boundary_face_index(b, p.side, c);
    face = FaceGeom{b.S[d](f), b.kt[d](f)};
    outward = outward_face(b, p.side, c);
    n = outward.S.normalized();
    xface = b.xf[d](f);
    if (p.type == BcType::Wall) {
      d_wall = wall_distance(b, p.side, c);
      u_wall = wall_velocity(b, p, f);
    }
    if (fp.viscous != ViscousForm::Inviscid) tl = thin_layer_coefficient(b, nu, d, f);
    // Dirichlet ghosts do not depend on the interior (see fill_ghosts).
    if (p.type == BcType::Dirichlet) ghost_exact = fp.exact(b.xc(ghost_cell(b, p.side, c, 1)));
  }

  State operator()(const State& q1) const {
    if (p.type == BcType::Wall) return wall_flux(u_wall, q1, face, high, d_wall, 1.0 / fp.reynolds, fp.beta);
    State qb = q1;
    if (is_characteristic_bc(p.type)) qb = boundary_state(p, q1, outward, xface, fp);
    const State qg = p.type == BcType::Dirichlet ? ghost_exact : ghost_value(p, q1, qb, n);
    const State& qL = high ? q1 : qg;
    const State& qR = high ? qg : q1;
    State F = is_characteristic_bc(p.type) ? physical_flux<Real>(qb, face, fp.beta)
                                            : roe_flux<Real>(qL, qR, face, fp.beta);
    F.tail<3>() -= tl * (qR.tail<3>() - qL.tail<3>());
    return F;
  }
};
// Collective over `comm`: "<label>" of the owned cell where value(ib, b, i, j, k) is
// largest on any rank (a NaN value is never the largest).
template <class Value, class Label>
std::string describe_largest_cell_collective(const Grid& g, const Communicator& comm, Value&& value, Label&& label) {
  Real worst = -1.0;
  std::string where;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    for_each_cell(b, [&](int i, int j, int k) {
      const Real r = value(ib, b, i, j, k);
      if (!(r > worst)) return;
      worst = r;
      where = label(b, i, j, k, r);
    });
  }
  return description_of_largest(comm, worst, std::move(where));
}

}  // namespace

NewtonSolver::NewtonSolver(Grid& g, FlowField& f, const FlowParams& fp, NewtonSettings s, const Communicator& comm)
    : g_(g), f_(f), fp_(fp), s_(s), comm_(comm), guard_(s.rise_limit) {
  const std::size_t nb = g.blocks.size();
  R_.resize(nb);
  dQ_.resize(nb);
  Dinv_.resize(nb);
  AL_.resize(nb);
  AR_.resize(nb);
  for (std::size_t ib = 0; ib < nb; ++ib) {
    if (!g.owns(ib)) continue;  // other ranks' blocks: no storage
    const Block& b = g.blocks[ib];
    R_[ib].resize(b.ni, b.nj, b.nk, 0);
    dQ_[ib].resize(b.ni, b.nj, b.nk, kGhost, State::Zero());
    Dinv_[ib].resize(b.ni, b.nj, b.nk, 0);
    for (int d = 0; d < 3; ++d) {
      Index3 n = b.dims();
      n[d] += 1;
      AL_[ib][d].resize(n[0], n[1], n[2], 0, Mat4::Zero());
      AR_[ib][d].resize(n[0], n[1], n[2], 0, Mat4::Zero());
    }
  }
}

IterationNorms NewtonSolver::norms() const {
  // Per-block sums of squares and cell counts, added in block order on every rank.
  constexpr int width = kNumEq + 1;
  std::vector<Real> partial(g_.blocks.size() * width, 0.0);
  for (std::size_t ib = 0; ib < g_.blocks.size(); ++ib) {
    if (!g_.owns(ib)) continue;
    const Block& b = g_.blocks[ib];
    Real* s = &partial[ib * width];
    for_each_cell(b, [&](int i, int j, int k) {
      const State r = R_[ib](i, j, k) / b.vol(i, j, k);
      for (int m = 0; m < kNumEq; ++m) s[m] += r[m] * r[m];
    });
    s[kNumEq] = static_cast<Real>(b.cells());
  }
  const std::vector<Real> total = sum_in_block_order(comm_, g_, std::move(partial), width);
  IterationNorms n;
  for (int m = 0; m < kNumEq; ++m) {
    n.l2[m] = std::sqrt(total[m] / total[kNumEq]);
    n.total += n.l2[m] * n.l2[m];
  }
  n.total = std::sqrt(n.total);
  return n;
}

void NewtonSolver::check_finite() const {
  // States first: a non-finite state is the cause, non-finite residuals of its
  // neighbours the consequence. The turbulence variables and the effective viscosity
  // are states too: a non-finite eddy viscosity shows first in the momentum residuals.
  // Every rank learns the first failure (lowest rank).
  std::string what;
  auto first_non_finite = [&](const Block& b, auto&& value_at, int count, auto&& describe) {
    for_each_cell(b, [&](int i, int j, int k) {
      for (int m = 0; m < count && what.empty(); ++m)
        if (!std::isfinite(value_at(i, j, k, m))) what = describe(m, i, j, k);
    });
  };
  for (int pass = 0; pass < 4 && what.empty(); ++pass)
    for (std::size_t ib = 0; ib < g_.blocks.size() && what.empty(); ++ib) {
      if (!g_.owns(ib)) continue;
      const Block& b = g_.blocks[ib];
      auto where = [&](int i, int j, int k) { return fmt::format("in block '{}' cell ({}, {}, {})", b.name, i, j, k); };
      if (pass == 0)
        first_non_finite(
            b, [&](int i, int j, int k, int m) { return f_.Q[ib](i, j, k)[m]; }, kNumEq,
            [&](int m, int i, int j, int k) { return fmt::format("non-finite {} {}", kEquationNames[m], where(i, j, k)); });
      else if (pass == 1 && ib < f_.turb.size() && !f_.turb[ib].raw().empty())
        first_non_finite(
            b, [&](int i, int j, int k, int m) { return f_.turb[ib](i, j, k)[m]; }, 2,
            [&](int m, int i, int j, int k) {
              return fmt::format("non-finite turbulence variable {} {}", m + 1, where(i, j, k));
            });
      else if (pass == 2 && ib < f_.nu.size() && !f_.nu[ib].raw().empty())
        first_non_finite(
            b, [&](int i, int j, int k, int) { return f_.nu[ib](i, j, k); }, 1,
            [&](int, int i, int j, int k) { return fmt::format("non-finite effective viscosity {}", where(i, j, k)); });
      else if (pass == 3)
        first_non_finite(
            b, [&](int i, int j, int k, int m) { return R_[ib](i, j, k)[m]; }, kNumEq, [&](int m, int i, int j, int k) {
              return fmt::format("non-finite residual of the {} equation {}", kEquationNames[m], where(i, j, k));
            });
    }
  if (g_.owner.empty()) {
    if (!what.empty()) throw DivergenceError(what);
    return;
  }
  const int first = static_cast<int>(comm_.min(what.empty() ? comm_.size() : comm_.rank()));
  if (first == comm_.size()) return;
  comm_.broadcast(what, first);
  throw DivergenceError(what);
}

std::string NewtonSolver::describe_largest_residual(int equation) const {
  int largest_equation = 0;  // of the cell value() looked at last
  return describe_largest_cell_collective(
      g_, comm_,
      [&](std::size_t ib, const Block& b, int i, int j, int k) {
        Real r = -1.0;
        for (int m = 0; m < kNumEq; ++m) {
          if (equation >= 0 && m != equation) continue;
          const Real rm = std::abs(R_[ib](i, j, k)[m]) / b.vol(i, j, k);
          if (rm > r) r = rm, largest_equation = m;
        }
        return r;
      },
      [&](const Block& b, int i, int j, int k, Real r) {
        return fmt::format("block '{}' cell ({}, {}, {}), {} equation: |R|/V = {:.3e}", b.name, i, j, k,
                           kEquationNames[largest_equation], r);
      });
}

IterationNorms NewtonSolver::evaluate_residual() {
  fill_ghosts(g_, f_, fp_);
  compute_residual(g_, f_, fp_, R_);
  if (time_)
    for (std::size_t ib = 0; ib < R_.size(); ++ib)
      if (g_.owns(ib)) time_->add_to_residual(ib, g_.blocks[ib], f_.Q[ib], R_[ib]);
  if (forcing_)
    for (std::size_t ib = 0; ib < R_.size(); ++ib) {
      if (!g_.owns(ib)) continue;
      auto& r = R_[ib].raw();
      const auto& fr = (*forcing_)[ib].raw();
      for (std::size_t n = 0; n < r.size(); ++n) r[n] -= fr[n];
    }
  check_finite();
  return norms();
}

void NewtonSolver::assemble_block(int ib, Real cfl) {
  const Block& b = g_.blocks[ib];
  const auto& Q = f_.Q[ib];
  const auto& nu = f_.nu[ib];
  const Real eps = s_.fd_epsilon;
  // Face Jacobians of the first-order flux (phi = 0) plus the viscous part along the
  // face-normal difference (§4.4; for the full stress with its S S^T term).
  auto interior_face = [&](int d, const Index3& f) {
    const Index3 cL = add(f, unit(d), -1), cR = f;
    const FaceGeom face{b.S[d](f), b.kt[d](f)};
    const State F0 = roe_flux<Real>(Q(cL), Q(cR), face, fp_.beta);
    Mat4 AL = numerical_jacobian([&](const State& q) { return roe_flux<Real>(q, Q(cR), face, fp_.beta); }, Q(cL),
                                 F0, eps);
    Mat4 AR = numerical_jacobian([&](const State& q) { return roe_flux<Real>(Q(cL), q, face, fp_.beta); }, Q(cR),
                                 F0, eps);
    if (fp_.viscous != ViscousForm::Inviscid) {
      const Real cv = thin_layer_coefficient(b, nu, d, f);
      Mat3 V = cv * Mat3::Identity();
      // The full stress also carries nu (du/dn . S) S / V_f, the transpose-gradient
      // part of tau S along the face-normal difference (§4.2). Left out, the normal
      // velocity's implicit coefficient is half its explicit one: at low Reynolds
      // numbers and large CFL the iteration then overshoots and diverges.
      if (fp_.viscous == ViscousForm::Full) {
        const Vec3& S = b.S[d](f);
        V += (cv / S.squaredNorm()) * S * S.transpose();
      }
      AL.bottomRightCorner<3, 3>() += V;
      AR.bottomRightCorner<3, 3>() -= V;
    }
    AL_[ib][d](f) = AL;
    AR_[ib][d](f) = AR;
  };
  for (int d = 0; d < 3; ++d)  // block faces are done per patch below
    for_each_interior_face(b, d, [&](const Index3& f) { interior_face(d, f); });
  // Physical boundary faces: replace by the derivative through the BC (§5.0).
  for (const Patch& p : b.patches) {
    const int d = side_dir(p.side);
    if (d == b.invariant_dir) continue;  // no coupling across an invariant layer's cancelling faces
    const PatchRange r = face_range(p);
    if (p.type == BcType::Interface) {  // the neighbour's cells sit in the ghosts: an ordinary face
      for_each_in(r, [&](Index3 c) { interior_face(d, boundary_face_index(b, p.side, c)); });
      continue;
    }
    for_each_in(r, [&](Index3 c) {
      const Index3 f = boundary_face_index(b, p.side, c);
      const State q1 = Q(interior_cell(b, p.side, c, 1));
      const BoundaryFaceFlux flux(b, p, c, nu, fp_);
      const Mat4 J = numerical_jacobian(flux, q1, flux(q1), eps);
      if (side_high(p.side)) {
        AL_[ib][d](f) = J;
        AR_[ib][d](f).setZero();
      } else {
        AR_[ib][d](f) = J;
        AL_[ib][d](f).setZero();
      }
    });
  }
  // Diagonal blocks with the local pseudo-time term (§6.4, §6.6).
  for (int k = 0; k < b.nk; ++k)
    for (int j = 0; j < b.nj; ++j)
      for (int i = 0; i < b.ni; ++i) {
        const Index3 c{i, j, k};
        Mat4 D = Mat4::Zero();
        Real lambda = 0.0, s2 = 0.0;
        for (int d = 0; d < 3; ++d) {
          if (d == b.invariant_dir) continue;  // the 2-D problem's own spectral radius
          const Index3 up = add(c, unit(d));
          D += AL_[ib][d](up) - AR_[ib][d](c);
          const Vec3 Sbar = 0.5 * (b.S[d](c) + b.S[d](up));
          const Real ktbar = 0.5 * (b.kt[d](c) + b.kt[d](up));
          const Real theta = ktbar + Sbar.dot(Q(c).tail<3>());
          const Real sigma = theta - 0.5 * ktbar;
          lambda += std::abs(sigma) + std::sqrt(sigma * sigma + fp_.beta * Sbar.squaredNorm());
          s2 += Sbar.squaredNorm();
        }
        if (fp_.viscous != ViscousForm::Inviscid) lambda += 2.0 * nu(c) * s2 / b.vol(c);
        if (std::isfinite(cfl)) D.diagonal().array() += lambda / cfl;  // V/dtau = Lambda/CFL
        if (time_) time_->add_to_diagonal(b, c, D);
        for (const auto& source : fp_.sources) source->add_to_diagonal(b, c, Q(c), D);
        Dinv_[ib](c) = D.inverse();
      }
}

void NewtonSolver::sweep_block(int ib, bool forward) {
  const Block& b = g_.blocks[ib];
  auto& dQ = dQ_[ib];
  const auto& R = R_[ib];
  const auto& Dinv = Dinv_[ib];
  const auto& AL = AL_[ib];
  const auto& AR = AR_[ib];
  auto relax = [&](int i, int j, int k) {
    const Index3 c{i, j, k};
    State r = -R(c);
    for (int d = 0; d < 3; ++d) {
      if (d == b.invariant_dir) continue;
      const Index3 e = unit(d);
      const Index3 up = add(c, e), dn = add(c, e, -1);
      r.noalias() -= AR[d](up) * dQ(up);
      r.noalias() += AL[d](c) * dQ(dn);
    }
    dQ(c) = Dinv(c) * r;
  };
  for_each_cell_ordered(b, forward, relax);
}

Real NewtonSolver::ser_cfl(Real norm) {
  if (ref_norm_ <= 0.0) ref_norm_ = norm;
  guard_.observe(norm, last_cfl_, s_.cfl_start);
  Real cfl = std::min({s_.cfl_max, guard_.ceiling(), s_.cfl_start * ref_norm_ / std::max(norm, 1e-300)});
  // After a rejected correction the CFL climbs back at a bounded rate even where SER
  // alone would jump (cfl_growth 0), or each iteration would be rejected once.
  const Real growth = s_.cfl_growth > 0.0 ? s_.cfl_growth : (recovering_ ? kRecoveryGrowth : 0.0);
  if (growth > 0.0 && last_cfl_ > 0.0) cfl = std::min(cfl, growth * last_cfl_);
  if (recovering_ && cfl < growth * last_cfl_) recovering_ = false;
  if (cfl >= std::min(s_.cfl_max, guard_.ceiling())) guard_.arm();
  last_cfl_ = cfl;
  return cfl;
}

IterationNorms NewtonSolver::iterate() {
  IterationNorms n = evaluate_residual();
  return relax_and_update(n, ser_cfl(n.total));
}

void NewtonSolver::sweeps_only(int pairs) {
  for (int it = 0; it < pairs; ++it)
    for (bool forward : {true, false}) {
      for (std::size_t ib = 0; ib < g_.blocks.size(); ++ib)
        if (g_.owns(ib)) sweep_block(static_cast<int>(ib), forward);
      // Block (and rank) coupling is lagged: neighbours' corrections enter through the
      // ghosts after each half sweep, the same on any number of ranks.
      exchange_interfaces(g_, dQ_);
    }
}

IterationNorms NewtonSolver::iterate_with_cfl(Real cfl, bool reuse_jacobian) {
  return relax_and_update(evaluate_residual(), cfl, reuse_jacobian);
}

IterationNorms NewtonSolver::relax_and_update(IterationNorms n, Real cfl, bool reuse_jacobian) {
  // The SGS sweeps converge only for a diagonally dominant enough system; at a large
  // CFL some cells' blocks are not (an SST start on a coarse SUBOFF grid: the nose
  // square's corner cells at CFL 1e3), and more sweeps then amplify the correction
  // instead of refining it. A correction whose linearized residual exceeds the nonlinear
  // one by s_.linear_growth_limit is not applied: the CFL is cut and the system solved again.
  bool reuse = reuse_jacobian && assembled_ && (cfl == assembled_cfl_ || stale_cfl_ok_);
  for (int attempt = 0;; ++attempt) {
    for (std::size_t ib = 0; ib < g_.blocks.size(); ++ib) {
      if (!g_.owns(ib)) continue;
      if (!reuse) assemble_block(static_cast<int>(ib), cfl);
      dQ_[ib].fill(State::Zero());
    }
    assembled_ = true;
    assembled_cfl_ = cfl;
    sweeps_only(s_.sgs_iterations);
    if (!std::isfinite(cfl)) break;  // no pseudo-time term to strengthen the diagonal
    const Real ratio = linear_residual_ratio_collective(n.total);
    if (ratio <= s_.linear_growth_limit) break;
    if (attempt + 1 == kMaxCflCuts)
      throw DivergenceError(fmt::format(
          "the linearized equations' SGS sweeps diverge (linear residual {:.2e} times the nonlinear one) even at "
          "CFL {:.3g}, after {} cuts; largest linear residual at {}",
          ratio, cfl, kMaxCflCuts - 1, describe_largest_linear_residual_collective()));
    cfl *= kCflCut;
    reuse = false;
    ++cfl_cuts_;
    last_cfl_ = cfl;
    recovering_ = true;
  }
  n.cfl = cfl;
  for (std::size_t ib = 0; ib < g_.blocks.size(); ++ib)
    if (g_.owns(ib))
      for_each_cell(g_.blocks[ib], [&](int i, int j, int k) { f_.Q[ib](i, j, k) += s_.relaxation * dQ_[ib](i, j, k); });
  return n;
}

// R + A dQ of a cell's row in §6.4's system, from the stored inverse diagonal block
// (dQ's interface ghosts hold the neighbours' last corrections, as in the sweeps).
State NewtonSolver::linear_residual(int ib, const Index3& c) const {
  const Block& b = g_.blocks[ib];
  const auto& dQ = dQ_[ib];
  State r = R_[ib](c) + Dinv_[ib](c).inverse() * dQ(c);
  for (int d = 0; d < 3; ++d) {
    if (d == b.invariant_dir) continue;
    const Index3 up = add(c, unit(d)), dn = add(c, unit(d), -1);
    r.noalias() += AR_[ib][d](up) * dQ(up);
    r.noalias() -= AL_[ib][d](c) * dQ(dn);
  }
  return r;
}

Real NewtonSolver::linear_residual_ratio_collective(Real nonlinear_total) const {
  std::vector<Real> partial(g_.blocks.size(), 0.0);
  for (std::size_t ib = 0; ib < g_.blocks.size(); ++ib) {
    if (!g_.owns(ib)) continue;
    const Block& b = g_.blocks[ib];
    for_each_cell(b, [&](int i, int j, int k) {
      partial[ib] += (linear_residual(static_cast<int>(ib), {i, j, k}) / b.vol(i, j, k)).squaredNorm();
    });
  }
  const std::vector<Real> total = sum_in_block_order(comm_, g_, std::move(partial), 1);
  Real cells = 0.0;
  for (const Block& b : g_.blocks) cells += static_cast<Real>(b.cells());
  const Real linear_total = std::sqrt(total[0] / cells);
  if (!std::isfinite(linear_total)) return std::numeric_limits<Real>::infinity();
  return nonlinear_total > 0.0 ? linear_total / nonlinear_total : 0.0;
}

std::string NewtonSolver::describe_largest_linear_residual_collective() const {
  return describe_largest_cell_collective(
      g_, comm_,
      [&](std::size_t ib, const Block& b, int i, int j, int k) {
        return linear_residual(static_cast<int>(ib), {i, j, k}).norm() / b.vol(i, j, k);
      },
      [](const Block& b, int i, int j, int k, Real r) {
        return fmt::format("block '{}' cell ({}, {}, {}): |R + A dQ|/V = {:.3e}", b.name, i, j, k, r);
      });
}

}  // namespace narwhal
