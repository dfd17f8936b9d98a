#pragma once
// The physical-time term of dual time stepping (NUMERICS §2.5, §6.1): per cell
//   R*_c = I_a (c0 V_c^{n+1} Q_c + c1 V_c^n Q_c^n + c2 V_c^{n-1} Q_c^{n-1}) / dt_n + R_c(Q),
// I_a = diag(0, 1, 1, 1) (continuity carries no time derivative), with the BDF
// coefficients of §2.4. It is one contribution to the residual and one to the Newton
// matrix's diagonal blocks, c0 V_c / dt_n I_a (§6.2, §6.4). The old levels' part
//   B_c = I_a (c1 V^n Q^n + c2 V^{n-1} Q^{n-1})
// is constant during a step; on a coarse multigrid level it cancels in the FAS forcing
// (§7.3), so only the finest level holds it and the coarse levels' terms have none.
// The transport turbulence models' variables phi (§8.6) take the same term, all of
// them with a time derivative: (c0 V phi + c1 V^n phi^n + c2 V^{n-1} phi^{n-1}) / dt in
// the residual and c0 V / dt on the diagonal; they are solved on the finest level only.
#include <vector>

#include "core/types.hpp"
#include "fields/ghost_array.hpp"
#include "mesh/block.hpp"
#include "physics/flow.hpp"  // TurbState

namespace narwhal {

// §2.4: BDF coefficients for a step dt_n after a step dt_{n-1}.
struct BdfCoefficients {
  Real c0 = 1.0, c1 = -1.0, c2 = 0.0;
  static BdfCoefficients bdf1() { return {1.0, -1.0, 0.0}; }
  // omega = dt_n / dt_{n-1}; at omega = 1: 3/2, -2, 1/2.
  static BdfCoefficients bdf2(Real omega) {
    return {(1.0 + 2.0 * omega) / (1.0 + omega), -(1.0 + omega), omega * omega / (1.0 + omega)};
  }
};

class PhysicalTimeTerm {
 public:
  // For the blocks of `g` this rank owns; `holds_old_levels`: the finest level.
  PhysicalTimeTerm(const Grid& g, bool holds_old_levels);

  // The step's size and coefficients (the old levels' part is set apart, set_old_levels).
  void set_step(Real dt, const BdfCoefficients& c) {
    dt_ = dt;
    c_ = c;
  }
  // B_c from the old levels' volumes and states (c2's level ignored when c2 = 0); the
  // turbulence variables' part too when `turb_n` is not empty.
  void set_old_levels(const Grid& g, const std::vector<GhostArray<Real>>& vol_n, const std::vector<GhostArray<State>>& q_n,
                      const std::vector<GhostArray<Real>>& vol_nm1, const std::vector<GhostArray<State>>& q_nm1,
                      const std::vector<GhostArray<TurbState>>& turb_n = {},
                      const std::vector<GhostArray<TurbState>>& turb_nm1 = {});

  // R_c += I_a (c0 V_c Q_c + B_c) / dt for the cells of block ib (V_c: the block's current volume).
  void add_to_residual(std::size_t ib, const Block& b, const GhostArray<State>& Q, GhostArray<State>& R) const;
  // The diagonal block's share: c0 V_c / dt on the three momentum rows.
  void add_to_diagonal(const Block& b, const Index3& c, Mat4& D) const {
    const Real a = c_.c0 * b.vol(c) / dt_;
    D(1, 1) += a;
    D(2, 2) += a;
    D(3, 3) += a;
  }

  // The turbulence variables' share in cell c of block ib (volume V, values phi): residual
  // and diagonal (finest level, after set_old_levels with the turbulence levels).
  void add_to_turbulence(std::size_t ib, const Index3& c, Real V, const TurbState& phi, TurbState& R,
                         TurbState& D) const {
    R += (c_.c0 * V * phi + old_turb_[ib](c)) / dt_;
    D += TurbState::Constant(c_.c0 * V / dt_);
  }
  bool has_turbulence() const { return !old_turb_.empty(); }

  Real dt() const { return dt_; }
  const BdfCoefficients& coefficients() const { return c_; }

 private:
  Real dt_ = 1.0;
  BdfCoefficients c_;
  bool holds_old_levels_;
  std::vector<GhostArray<Vec3>> old_;  // B_c's momentum part per owned block (finest level only)
  std::vector<GhostArray<TurbState>> old_turb_;  // the turbulence variables' (transport models)
};

}  // namespace narwhal
