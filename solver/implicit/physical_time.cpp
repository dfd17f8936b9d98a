#include "implicit/physical_time.hpp"

namespace narwhal {

PhysicalTimeTerm::PhysicalTimeTerm(const Grid& g, bool holds_old_levels) : holds_old_levels_(holds_old_levels) {
  if (holds_old_levels) old_ = owned_cell_arrays(g, Vec3(Vec3::Zero()));
}

void PhysicalTimeTerm::set_old_levels(const Grid& g, const std::vector<GhostArray<Real>>& vol_n,
                                      const std::vector<GhostArray<State>>& q_n,
                                      const std::vector<GhostArray<Real>>& vol_nm1,
                                      const std::vector<GhostArray<State>>& q_nm1,
                                      const std::vector<GhostArray<TurbState>>& turb_n,
                                      const std::vector<GhostArray<TurbState>>& turb_nm1) {
  if (!holds_old_levels_) return;
  if (!turb_n.empty() && old_turb_.empty()) old_turb_ = owned_cell_arrays(g, TurbState(TurbState::Zero()));
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    for_each_cell(g.blocks[ib], [&](int i, int j, int k) {
      Vec3 b = c_.c1 * vol_n[ib](i, j, k) * q_n[ib](i, j, k).tail<3>();
      if (c_.c2 != 0.0) b += c_.c2 * vol_nm1[ib](i, j, k) * q_nm1[ib](i, j, k).tail<3>();
      old_[ib](i, j, k) = b;
      if (turb_n.empty()) return;
      TurbState t = c_.c1 * vol_n[ib](i, j, k) * turb_n[ib](i, j, k);
      if (c_.c2 != 0.0) t += c_.c2 * vol_nm1[ib](i, j, k) * turb_nm1[ib](i, j, k);
      old_turb_[ib](i, j, k) = t;
    });
  }
}

void PhysicalTimeTerm::add_to_residual(std::size_t ib, const Block& b, const GhostArray<State>& Q,
                                       GhostArray<State>& R) const {
  const Real inv_dt = 1.0 / dt_;
  for_each_cell(b, [&](int i, int j, int k) {
    Vec3 m = c_.c0 * b.vol(i, j, k) * Q(i, j, k).tail<3>();
    if (holds_old_levels_) m += old_[ib](i, j, k);
    R(i, j, k).tail<3>() += inv_dt * m;
  });
}

}  // namespace narwhal
