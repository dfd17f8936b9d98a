#include "turbulence/transport_model.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "bc/boundary.hpp"
#include "mesh/ghost_sweep.hpp"
#include "parallel/communicator.hpp"
#include "parallel/halo.hpp"
#include "parallel/reduction.hpp"
#include "physics/residual.hpp"
#include "turbulence/flow_gradients.hpp"

namespace narwhal {

namespace {

Real positive(Real x) { return x > 0.0 ? x : 0.0; }
Real negative(Real x) { return x < 0.0 ? x : 0.0; }

// Volume flux U_f = F_1/beta + k_t through face f of direction d (along +S), from
// the flux the mean flow itself uses there (§8.6).
Real interior_volume_flux(const Block& b, const GhostArray<State>& Q, int d, const Index3& f, const FlowParams& fp) {
  return inviscid_face_flux(b, Q, d, f, fp)[0] / fp.beta + b.kt[d](f);
}


}  // namespace

TransportModel::TransportModel(const TurbulenceSettings& s, const Grid& g, const Communicator& comm) :
    settings_(with_model_defaults(s)), comm_(comm), wall_(compute_wall_distance(g)) {
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    Work w;
    aux_.emplace_back();
    grad_u_.emplace_back();
    if (!g.owns(ib)) {  // other ranks' blocks: no storage
      work_.push_back(std::move(w));
      continue;
    }
    aux_.back().resize(b.ni, b.nj, b.nk, 1, TurbState::Zero());
    for (int d = 0; d < 3; ++d) {
      Index3 n = b.dims();
      n[d] += 1;
      w.U[d].resize(n[0], n[1], n[2], 0, 0.0);
      w.aL[d].resize(n[0], n[1], n[2], 0, TurbState::Zero());
      w.aR[d].resize(n[0], n[1], n[2], 0, TurbState::Zero());
    }
    w.R.resize(b.ni, b.nj, b.nk, 0, TurbState::Zero());
    w.D.resize(b.ni, b.nj, b.nk, 0, TurbState::Zero());
    w.M.resize(b.ni, b.nj, b.nk, 0, Eigen::Matrix2d::Identity());
    w.line_dir = stiffest_direction(b);  // geometry only: fixed for the run
    w.dphi.resize(b.ni, b.nj, b.nk, 1, TurbState::Zero());
    w.lam.resize(b.ni, b.nj, b.nk, 0, 0.0);
    w.flow.resize(b.ni, b.nj, b.nk, 0, CellFlow{});
    work_.push_back(std::move(w));
  }
}

void TransportModel::initialize(const Grid& g, FlowField& f, const FlowParams& fp, bool keep) {
  if (keep && f.turb.size() == g.blocks.size()) return;
  f.allocate_turbulence(g);
  const TurbState inf = freestream(1.0 / fp.reynolds);
  for (auto& t : f.turb) t.fill(inf);
}

void TransportModel::fill_scalar_ghosts(Grid& g, FlowField& f, const FlowParams& fp) const {
  const Real nu = 1.0 / fp.reynolds;
  const TurbState inf = freestream(nu);
  auto physical = [&](int ib, const Patch& p, int m) {
    const Block& b = g.blocks[ib];
    auto& T = f.turb[ib];
    const PatchRange r = extended_cell_range(b, p);
    for_each_in(r, [&](Index3 c) {
      const Index3 gc = ghost_cell(b, p.side, c, m);
      const TurbState& tm = T(interior_cell(b, p.side, c, m));
      switch (p.type) {
        case BcType::Wall: T(gc) = 2.0 * wall_value(nu, wall_distance(b, p.side, c), T(interior_cell(b, p.side, c, 1))) - tm; break;
        case BcType::Symmetry: T(gc) = tm; break;
        case BcType::Outflow: T(gc) = tm; break;  // zero gradient
        // Far field, inflow, Dirichlet: the free stream. A ghost that switched with the
        // sign of u.n would make the diffusion flux discontinuous where the flow is
        // tangent to the boundary (and the iteration cycle); the convective flux
        // U+ phi_1 + U- phi_g upwinds continuously anyway.
        default: T(gc) = inf; break;
      }
    });
  };
  owned_ghost_sweep(g, physical, [&](const ExchangePlan& plan) { exchange(g, plan, f.turb, Unrotated{}); });
}

namespace {
// First ghost layer of a per-cell work array: the donor's value across interfaces
// (tensors rotated by `rotate`), the adjacent interior cell at physical boundaries.
template <class T, class Rotate>
void fill_first_ghost_layer(const Grid& g, std::vector<GhostArray<T>>& A, Rotate rotate, bool extrapolate_at_walls = false) {
  if (!g.interfaces.empty()) exchange(g, halo_plans(g).faces, A, rotate);
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    auto& Ab = A[ib];
    for (const Patch& p : b.patches) {
      if (p.type == BcType::Interface) continue;
      for_each_in(face_range(p), [&](Index3 c) {
        const Index3 gc = ghost_cell(b, p.side, c, 1);
        if (extrapolate_at_walls && p.type == BcType::Wall && b.dims()[side_dir(p.side)] > 1)
          Ab(gc) = 2.0 * Ab(interior_cell(b, p.side, c, 1)) - Ab(interior_cell(b, p.side, c, 2));
        else
          Ab(gc) = Ab(interior_cell(b, p.side, c, 1));
      });
    }
  }
}
}  // namespace

CellFlow TransportModel::cell_flow(const Block& b, int ib, const FlowField& f, const FlowParams& fp, const Index3& c,
                                   bool for_sources) const {
  // Green-Gauss over the faces with face values averaged from the two cells (§8.1).
  CellFlow cf;
  cf.grad_u = velocity_gradient(b, f.Q[ib], c);
  cf.grad_phi.setZero();
  const Real inv_v = 1.0 / b.vol(c);
  if (for_sources) {
    const auto& T = f.turb[ib];
    auto root = [&](const Index3& x) { return std::copysign(std::sqrt(std::abs(T(x)[0])), T(x)[0]); };
    for (int d = 0; d < 3; ++d) {
      if (d == b.invariant_dir) continue;
      const Index3 e = unit(d);
      const Index3 up = add(c, e), dn = add(c, e, -1);
      cf.grad_phi += b.S[d](up) * (0.5 * (T(c) + T(up))).transpose() - b.S[d](c) * (0.5 * (T(c) + T(dn))).transpose();
      if (needs_root_gradient())
        cf.grad_sqrt_phi0 += b.S[d](up) * (0.5 * (root(c) + root(up))) - b.S[d](c) * (0.5 * (root(c) + root(dn)));
    }
    cf.grad_phi *= inv_v;
    cf.grad_sqrt_phi0 *= inv_v;
  }
  cf.d = wall_.d[ib](c);
  cf.nu = 1.0 / fp.reynolds;
  if (!u_tau_.empty()) {
    const int face = wall_.face[ib](c);
    cf.u_tau = face >= 0 ? u_tau_[static_cast<std::size_t>(face)] : 0.0;
  }
  const auto& GU = grad_u_[ib];
  if (for_sources && GU.ni() == b.ni && needs_velocity_hessian()) {
    Real h2 = 0.0;
    for (int l = 0; l < 3; ++l) {
      Mat3 H = Mat3::Zero();  // d/dx_l of grad u
      for (int d = 0; d < 3; ++d) {
        if (d == b.invariant_dir) continue;
        const Index3 e = unit(d);
        const Index3 up = add(c, e), dn = add(c, e, -1);
        H += 0.5 * (GU(c) + GU(up)) * b.S[d](up)[l] - 0.5 * (GU(c) + GU(dn)) * b.S[d](c)[l];
      }
      h2 += (H * inv_v).squaredNorm();
    }
    cf.hessian_u2 = h2;
  }
  return cf;
}

// One model iteration per pass, as named phases: the frozen mean flow's data, then
// per pass the cells' data, the linearized equations, their line relaxation and the
// update; the effective viscosity last.
TurbulenceNorms TransportModel::advance(Grid& g, FlowField& f, const FlowParams& fp, Real cfl) {
  const Real cfl_t = std::min(cfl, settings_.cfl_max);
  fill_ghosts(g, f, fp);  // mean-flow ghosts: volume fluxes and velocity gradients
  if (needs_friction_velocity()) gather_friction_velocity(g, f, fp);
  compute_volume_fluxes(g, f, fp);
  if (needs_velocity_hessian()) compute_velocity_gradients(g, f);
  TurbulenceNorms norms;
  for (int it = 0; it < *settings_.iterations; ++it) {
    fill_scalar_ghosts(g, f, fp);
    compute_cell_data(g, f, fp);
    norms = assemble(g, f, fp, cfl_t);
    relax(g);
    apply_update(g, f);
  }
  update_viscosity(g, f, fp);
  return norms;
}

// Volume fluxes of every face, once per call: the mean flow is frozen here.
void TransportModel::compute_volume_fluxes(const Grid& g, const FlowField& f, const FlowParams& fp) {
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    Work& w = work_[ib];
    for (int d = 0; d < 3; ++d) {
      if (d == b.invariant_dir) continue;
      for_each_interior_face(b, d, [&](const Index3& fi) { w.U[d](fi) = interior_volume_flux(b, f.Q[ib], d, fi, fp); });
    }
    for (const Patch& p : b.patches) {
      const int d = side_dir(p.side);
      if (d == b.invariant_dir) continue;
      for_each_in(face_range(p), [&](Index3 c) {
        const Index3 fi = boundary_face_index(b, p.side, c);
        w.U[d](fi) = boundary_face_flux(b, p, f.Q[ib], f.nu[ib], c, fp)[0] / fp.beta + b.kt[d](fi);
      });
    }
  }
}

// Cell velocity gradients with their first ghost layer (Launder-Sharma's Hessian).
void TransportModel::compute_velocity_gradients(const Grid& g, const FlowField& f) {
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    auto& GU = grad_u_[ib];
    if (GU.ni() != b.ni) GU.resize(b.ni, b.nj, b.nk, 1, Mat3::Zero());
    for_each_cell(b, [&](int i, int j, int k) { GU(i, j, k) = velocity_gradient(b, f.Q[ib], {i, j, k}); });
  }
  fill_first_ghost_layer(g, grad_u_, RotateTensor{},
                         // Linear extrapolation into the wall ghost: a copy of the wall
                         // cell's gradient would halve d2u/dy2 there (E of §8.3 lives at the wall).
                         true);
}

// What the sources see of every cell, and the auxiliary values with their first
// ghost layer (donor values across interfaces).
void TransportModel::compute_cell_data(const Grid& g, const FlowField& f, const FlowParams& fp) {
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
      CellFlow& cf = work_[ib].flow(i, j, k);
      cf = cell_flow(g.blocks[ib], static_cast<int>(ib), f, fp, {i, j, k}, true);
      aux_[ib](i, j, k) = cell_aux(f.turb[ib](i, j, k), cf);
    });
  }
  fill_first_ghost_layer(g, aux_, Unrotated{});
}

// The residual and its Newton linearization on every owned block; returns the
// residual norms (collective: a sum over all ranks in block order).
TurbulenceNorms TransportModel::assemble(const Grid& g, const FlowField& f, const FlowParams& fp, Real cfl_t) {
  std::vector<Real> partial(3 * g.blocks.size(), 0.0);  // per block: sums of squares, cells
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    Work& w = work_[ib];
    w.R.fill(TurbState::Zero());
    w.D.fill(TurbState::Zero());
    if (coupled()) {  // the wall-BC couplings: k-epsilon only
      if (w.Dx.ni() != b.ni) w.Dx.resize(b.ni, b.nj, b.nk, 0, TurbState::Zero());
      w.Dx.fill(TurbState::Zero());
    }
    w.lam.fill(0.0);
    assemble_interior_faces(b, static_cast<int>(ib), f, fp);
    assemble_boundary_faces(b, static_cast<int>(ib), f, fp);
    assemble_sources(b, static_cast<int>(ib), f, fp, cfl_t, &partial[3 * ib]);
    partial[3 * ib + 2] = static_cast<Real>(b.cells());
  }
  const std::vector<Real> total = sum_in_block_order(comm_, g, std::move(partial), 3);
  TurbulenceNorms norms;
  for (int m = 0; m < num_variables(); ++m) norms.l2[m] = std::sqrt(total[static_cast<std::size_t>(m)] / total[2]);
  return norms;
}

// Thin-layer diffusion coefficients Gamma |S|^2 / V_f of face fi for its left and right cells.
TransportModel::FaceDiffusivity TransportModel::face_coefficients(const Block& b, int ib, const FlowField& f,
                                                                  const FlowParams& fp, int d, const Index3& cL,
                                                                  const Index3& cR, const Index3& fi) const {
  const auto& T = f.turb[static_cast<std::size_t>(ib)];
  const auto& A = aux_[static_cast<std::size_t>(ib)];
  FaceDiffusivity fd = face_diffusivity(T(cL), T(cR), 1.0 / fp.reynolds, A(cL), A(cR));
  const Real geo = b.S[d](fi).squaredNorm() / (0.5 * (b.vol(cL) + b.vol(cR)));
  fd.left *= geo;
  fd.right *= geo;
  return fd;
}

// Upwind convection and thin-layer diffusion through interior faces: residual,
// diagonal, the two off-diagonal couplings, and the spectral radius of the
// pseudo-time term.
void TransportModel::assemble_interior_faces(const Block& b, int ib, const FlowField& f, const FlowParams& fp) {
  Work& w = work_[static_cast<std::size_t>(ib)];
  const auto& T = f.turb[static_cast<std::size_t>(ib)];
  for (int d = 0; d < 3; ++d) {
    if (d == b.invariant_dir) continue;
    for_each_interior_face(b, d, [&](const Index3& fi) {
      const Index3 cL = add(fi, unit(d), -1), cR = fi;
      const Real U = w.U[d](fi);
      const FaceDiffusivity c = face_coefficients(b, ib, f, fp, d, cL, cR, fi);
      const TurbState conv = positive(U) * T(cL) + negative(U) * T(cR);
      const TurbState jump = T(cR) - T(cL);
      w.R(cL) += conv - c.left.cwiseProduct(jump);
      w.R(cR) -= conv - c.right.cwiseProduct(jump);
      w.D(cL) += TurbState::Constant(positive(U)) + c.left;
      w.D(cR) += c.right - TurbState::Constant(negative(U));
      w.aR[d](fi) = TurbState::Constant(negative(U)) - c.left;    // dR_L / dphi_R
      w.aL[d](fi) = -(TurbState::Constant(positive(U)) + c.right);  // dR_R / dphi_L
      w.lam(cL) += 0.5 * std::abs(U) + c.left.maxCoeff();
      w.lam(cR) += 0.5 * std::abs(U) + c.right.maxCoeff();
    });
  }
}

// Boundary faces: the ghost follows the BC, d(ghost)/d(phi_1) = dg.
void TransportModel::assemble_boundary_faces(const Block& b, int ib, const FlowField& f, const FlowParams& fp) {
  Work& w = work_[static_cast<std::size_t>(ib)];
  const auto& T = f.turb[static_cast<std::size_t>(ib)];
  const Real nu = 1.0 / fp.reynolds;
  for (const Patch& p : b.patches) {
    const int d = side_dir(p.side);
    if (d == b.invariant_dir) continue;
    const Real s = side_high(p.side) ? 1.0 : -1.0;
    for_each_in(face_range(p), [&](Index3 cc) {
      const Index3 fi = boundary_face_index(b, p.side, cc);
      const Index3 c1 = interior_cell(b, p.side, cc, 1), gc = ghost_cell(b, p.side, cc, 1);
      const Real Uout = s * w.U[d](fi);
      Real dg = 1.0;
      switch (p.type) {
        case BcType::Wall: dg = -1.0; break;
        case BcType::Interface: dg = 0.0; break;  // lagged, like the mean flow's block coupling
        case BcType::Symmetry: dg = 1.0; break;
        case BcType::Outflow: dg = 1.0; break;
        default: dg = 0.0; break;  // far field, inflow, Dirichlet: the ghost holds the free stream
      }
      const TurbState c = face_coefficients(b, ib, f, fp, d, c1, gc, fi).left;  // cell 1 is "left" here
      w.R(c1) += positive(Uout) * T(c1) + negative(Uout) * T(gc) - c.cwiseProduct(T(gc) - T(c1));
      w.D(c1) += TurbState::Constant(positive(Uout) + negative(Uout) * dg) + c * (1.0 - dg);
      if (coupled() && p.type == BcType::Wall) {
        // A wall value that depends on the wall cell's other variable (Myong-Kasagi's
        // eps_w = 2 nu k_1/d_1^2) couples them through the ghost 2 phi_w - phi_1:
        // d(R_m)/d(phi_n) = -2 c_m d(phi_w,m)/d(phi_n). Left explicit, the k-eps wall
        // coupling (~nu/d_1^3) made the 137 TMR level diverge (measured).
        const Real d1 = wall_distance(b, p.side, cc);
        const TurbState pw = wall_value(nu, d1, T(c1));
        for (int n = 0; n < 2; ++n) {
          TurbState shifted = T(c1);
          const Real h = 1e-6 * std::abs(T(c1)[n]) + 1e-30;
          shifted[n] += h;
          const TurbState dpw = (wall_value(nu, d1, shifted) - pw) / h;
          w.Dx(c1)[1 - n] += -2.0 * c[1 - n] * dpw[1 - n];  // row 1-n, column n
        }
      }
      w.lam(c1) += 0.5 * std::abs(Uout) + c.maxCoeff();
    });
  }
}

// The sustaining term of TurbulenceSettings::sustain_freestream: minus the point
// source of the free-stream values in a uniform flow (no gradients) at this cell's
// wall distance and viscosity. A constant per cell: the Jacobians below do not see it.
TurbState TransportModel::sustaining_source(const TurbState& inf, const CellFlow& c) const {
  CellFlow still;
  still.grad_u = Mat3::Zero();
  still.grad_phi.setZero();
  still.d = c.d;
  still.nu = c.nu;
  still.u_tau = c.u_tau;
  return -source(inf, still).value;
}

// Point sources and the pseudo-time term; the point blocks M. Adds the squared
// residuals per variable to sums[0..1].
void TransportModel::assemble_sources(const Block& b, int ib, const FlowField& f, const FlowParams& fp, Real cfl_t,
                                      Real* sums) {
  Work& w = work_[static_cast<std::size_t>(ib)];
  const auto& T = f.turb[static_cast<std::size_t>(ib)];
  const int nv = num_variables();
  const TurbState inf = freestream(1.0 / fp.reynolds);
  for_each_cell(b, [&](int i, int j, int k) {
    const Index3 c{i, j, k};
    const CellFlow& cfw = w.flow(c);
    const PointSource src = source(T(c), cfw);
    // The implicit coefficient is the larger of the model's destruction
    // linearization and -dS/dphi by a one-sided difference of the whole point
    // source: near walls SA's fw and ft2 vary fast with nu~, and a diagonal that
    // missed it let the iteration cycle with period 2 (coarse TMR plate).
    TurbState implicit = src.implicit;
    Eigen::Matrix2d J = Eigen::Matrix2d::Zero();  // dS/dphi, numerically
    for (int m = 0; m < nv; ++m) {
      TurbState shifted = T(c);
      const Real h = 1e-6 * std::abs(T(c)[m]) + 1e-9 * std::abs(inf[m]) + 1e-300;
      shifted[m] += h;
      J.col(m) = (source(shifted, cfw).value - src.value) / h;
      implicit[m] = std::max(implicit[m], -J(m, m));
    }
    // The sustaining term is a constant of the cell: added after the Jacobian, which
    // is the difference of the model's own source.
    const TurbState value = settings_.sustain_freestream ? TurbState(src.value + sustaining_source(inf, cfw)) : src.value;
    const Real V = b.vol(c);
    w.R(c) -= V * value;
    w.D(c) += V * implicit + TurbState::Constant(w.lam(c) / cfl_t);
    if (time_) time_->add_to_turbulence(static_cast<std::size_t>(ib), c, V, T(c), w.R(c), w.D(c));
    for (int m = 0; m < nv; ++m) {
      if (!(w.D(c)[m] > 0.0)) w.D(c)[m] = w.lam(c) > 0.0 ? w.lam(c) : 1.0;  // keep the relaxation defined
      sums[m] += (w.R(c)[m] / V) * (w.R(c)[m] / V);
    }
    if (nv < 2) {
      w.R(c)[1] = 0.0;
      w.D(c)[1] = 1.0;
    }
    Eigen::Matrix2d M = w.D(c).asDiagonal();
    if (coupled()) {
      // 2x2 point-implicit source (k-epsilon): the diagonal as above, the
      // off-diagonal couplings dS_k/deps, dS_eps/dk kept. The diagonal-only form
      // leaves k's growth through nu_t ~ k^2/eps explicit and let k and eps
      // chase each other (bursts of k ~ 1 near the plate's leading edge, measured);
      // the point system of k-epsilon is stable (trace < 0, det > 0) only together.
      M(0, 1) = -V * J(0, 1) + w.Dx(c)[0];
      M(1, 0) = -V * J(1, 0) + w.Dx(c)[1];
    }
    w.M(c) = M;
  });
}

// The linearized equations, relaxed by symmetric Gauss-Seidel: sgs_iterations
// forward-backward pairs of line sweeps (implicit/line_solver.hpp; lines in each
// block's stiffest direction) or point sweeps. Rows:
//   M(c) dphi(c) + sum_d [aR[d](c + e_d) .* dphi(c + e_d) + aL[d](c) .* dphi(c - e_d)] = -R(c).
// Block interfaces lag, as in the mean flow: their coefficients are zero here and dphi's
// ghosts stay zero, so each block's system is independent of the others. All of a
// block's sweeps are therefore made before the next block's (the same answer bit for bit
// as sweeping every block in turn): the block's coefficients stay in cache through its
// sweeps instead of streaming the whole grid from memory for every sweep.
void TransportModel::relax(const Grid& g) {
  const bool lines = settings_.smoother == "lines";
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    Work& w = work_[ib];
    w.dphi.fill(TurbState::Zero());
    if (lines) {
      const int L = w.line_dir;
      const Index3 eL = unit(L);
      w.lines.factorize(
          b, L, [&](const Index3& c) { return w.M(c); },
          [&](const Index3& c) -> Eigen::Matrix2d { return w.aL[L](c).asDiagonal(); },
          [&](const Index3& c) -> Eigen::Matrix2d { return w.aR[L](add(c, eL)).asDiagonal(); });
    } else if (coupled()) {
      invert_point_blocks(b, w);
    }
    for (int sweep = 0; sweep < 2 * settings_.sgs_iterations; ++sweep) {
      const bool forward = sweep % 2 == 0;
      if (lines)
        sweep_lines(b, w, forward);
      else
        sweep_points(b, w, forward);
    }
  }
}

void TransportModel::sweep_lines(const Block& b, Work& w, bool forward) const {
  const int L = w.line_dir;
  const Index3 eL = unit(L);
  auto rhs = [&](const Index3& c) {  // -R and the other lines' latest corrections
    TurbState r = -w.R(c);
    for (int d = 0; d < 3; ++d) {
      if (d == L || d == b.invariant_dir) continue;
      const Index3 up = add(c, unit(d)), dn = add(c, unit(d), -1);
      r -= w.aR[d](up).cwiseProduct(w.dphi(up)) + w.aL[d](c).cwiseProduct(w.dphi(dn));
    }
    return r;
  };
  w.lines.sweep(b, forward, rhs, [&](const Index3& c) -> Eigen::Matrix2d { return w.aR[L](add(c, eL)).asDiagonal(); },
                w.dphi);
}

// The point smoother's 2x2 blocks inverted once per assembly, not once per sweep.
void TransportModel::invert_point_blocks(const Block& b, Work& w) const {
  if (w.M_inv.ni() != b.ni) w.M_inv.resize(b.ni, b.nj, b.nk, 0, Eigen::Matrix2d::Identity());
  for_each_cell(b, [&](int i, int j, int k) { w.M_inv(i, j, k) = w.M(i, j, k).inverse(); });
}

void TransportModel::sweep_points(const Block& b, Work& w, bool forward) const {
  const bool coupled_blocks = coupled();
  auto relax_cell = [&](int i, int j, int k) {
    const Index3 c{i, j, k};
    TurbState r = -w.R(c);
    for (int d = 0; d < 3; ++d) {
      if (d == b.invariant_dir) continue;
      const Index3 e = unit(d);
      const Index3 up = add(c, e), dn = add(c, e, -1);
      r -= w.aR[d](up).cwiseProduct(w.dphi(up)) + w.aL[d](c).cwiseProduct(w.dphi(dn));
    }
    w.dphi(c) = coupled_blocks ? TurbState(w.M_inv(c) * r) : TurbState(r.cwiseQuotient(w.D(c)));
  };
  for_each_cell_ordered(b, forward, relax_cell);
}

void TransportModel::apply_update(const Grid& g, FlowField& f) {
  const int nv = num_variables();
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
      TurbState& phi = f.turb[ib](i, j, k);
      phi += *settings_.relaxation * limit_update(phi, work_[ib].dphi(i, j, k));
      if (nv < 2) phi[1] = 0.0;
    });
  }
}

void TransportModel::gather_friction_velocity(const Grid& g, const FlowField& f, const FlowParams& fp) {
  // Same face order as compute_wall_distance. tau_w = nu |u_t1| / d1 from the wall
  // cell's tangential velocity (the wall at rest in the grid frame's sense of §5.1
  // is not needed here: y+ only switches damping functions).
  const Real nu = 1.0 / fp.reynolds;
  u_tau_.clear();
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    for (const Patch& p : b.patches) {
      if (p.type != BcType::Wall) continue;
      for_each_in(face_range(p), [&](Index3 c) {
        if (!g.owns(ib)) {  // another rank's face: its value arrives in the sum below
          u_tau_.push_back(0.0);
          return;
        }
        Vec3 n;
        const Real d1 = wall_distance(b, p.side, c, &n);
        const Vec3 u1 = f.Q[ib](interior_cell(b, p.side, c, 1)).tail<3>();
        const Vec3 ut = u1 - u1.dot(n) * n;
        u_tau_.push_back(std::sqrt(nu * ut.norm() / std::max(d1, 1e-300)));
      });
    }
  }
  // Every wall face has one owner: the sum is an exact gather (a cell's nearest wall
  // face may be on another rank).
  if (!g.owner.empty()) comm_.sum(u_tau_);
}

void TransportModel::update_viscosity(const Grid& g, FlowField& f, const FlowParams& fp) {
  const Real nu = 1.0 / fp.reynolds;
  if (needs_friction_velocity() && u_tau_.size() != wall_.faces.size()) gather_friction_velocity(g, f, fp);
  const Real cap = 1.0e6 * nu;  // §8.6: nut_hat <= 1e6
  const bool nonlinear = has_nonlinear_stress();
  if (nonlinear && f.tau_nl.size() != g.blocks.size()) {
    f.tau_nl.resize(g.blocks.size());
    for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
      if (!g.owns(ib)) continue;  // other ranks' blocks: no storage
      const Block& b = g.blocks[ib];
      f.tau_nl[ib].resize(b.ni, b.nj, b.nk, kGhost);
      f.tau_nl[ib].fill(Mat3::Zero());
    }
  }
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    for_each_cell(b, [&](int i, int j, int k) {
      const CellFlow cf = cell_flow(b, static_cast<int>(ib), f, fp, {i, j, k}, false);
      const Real nu_t = std::clamp(nut(f.turb[ib](i, j, k), cf), 0.0, cap);
      f.nu[ib](i, j, k) = nu + nu_t;
      if (nonlinear) f.tau_nl[ib](i, j, k) = cell_nonlinear_stress(f.turb[ib](i, j, k), cf, nu_t);
    });
  }
  if (nonlinear) fill_tensor_ghosts(g, f.tau_nl);
}

std::string TransportModel::describe_largest_residual(const Grid& g, int m, const Communicator& comm) const {
  Real worst = -1.0;
  std::string where;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib) || work_[ib].R.ni() != g.blocks[ib].ni) continue;
    const Block& b = g.blocks[ib];
    for_each_cell(b, [&](int i, int j, int k) {
      const Real r = std::abs(work_[ib].R(i, j, k)[m]) / b.vol(i, j, k);
      if (r <= worst) return;
      worst = r;
      where = fmt::format("block '{}' cell ({}, {}, {}), {} equation: |R|/V = {:.3e}", b.name, i, j, k,
                          variable_name(m), r);
    });
  }
  return description_of_largest(comm, worst, std::move(where));
}

Real TransportModel::eddy_viscosity(const FlowField& f, const FlowParams& fp, int ib, const Index3& c) const {
  return f.nu[ib](c) - 1.0 / fp.reynolds;
}

}  // namespace narwhal
