#pragma once
// Volume sources of the mean-flow equations, as a list (NUMERICS §2.5: R_c = sum_f s_cf
// (F_f - F_v,f) - V_c S_c): a manufactured solution's forcing (§12.2), a driving force,
// constant or adjusted to a flow rate, and later a propulsor's body force (§9.4). Each
// adds its part of the residual and, when it depends on the state, its part of the
// Newton matrix's diagonal block (§6.4), so that residual and matrix see the same list.
// Every multigrid level evaluates the same sources on its own cells.
//
// Usage:
//   fp.sources.push_back(position_source("body force", [g](const Vec3&) { return g; }));
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "fields/ghost_array.hpp"
#include "mesh/block.hpp"

namespace narwhal {

class VolumeSource {
 public:
  virtual ~VolumeSource() = default;
  virtual std::string name() const = 0;
  // R_c -= V_c S_c over the cells of block b.
  virtual void add_to_residual(const Block& b, const GhostArray<State>& Q, GhostArray<State>& R) const = 0;
  // D_c -= V_c dS_c/dQ_c at cell c of state q; nothing for a source that does not depend
  // on the state (the default).
  virtual void add_to_diagonal(const Block&, const Index3&, const State&, Mat4&) const {}
  // The momentum per unit volume at x when the source is a function of position alone
  // (a planar grid is only planar if no source pushes across its plane); nullopt otherwise.
  virtual std::optional<Vec3> momentum_at(const Vec3&) const { return std::nullopt; }
  // A dual-time run sets the time the sources are taken at, t^{n+1}, before each step's
  // iterations; steady sources ignore it.
  virtual void at_time(Real) {}
};

// Shared by the multigrid levels' copies of FlowParams: each source is set in time once.
using VolumeSources = std::vector<std::shared_ptr<VolumeSource>>;

// A momentum source per unit volume that depends on position alone.
class PositionSource final : public VolumeSource {
 public:
  PositionSource(std::string name, std::function<Vec3(const Vec3&)> momentum)
      : name_(std::move(name)), momentum_(std::move(momentum)) {}
  std::string name() const override { return name_; }
  void add_to_residual(const Block& b, const GhostArray<State>&, GhostArray<State>& R) const override {
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i) R(i, j, k).tail<3>() -= b.vol(i, j, k) * momentum_(b.xc(i, j, k));
  }
  std::optional<Vec3> momentum_at(const Vec3& x) const override { return momentum_(x); }

 private:
  std::string name_;
  std::function<Vec3(const Vec3&)> momentum_;
};

inline std::shared_ptr<VolumeSource> position_source(std::string name, std::function<Vec3(const Vec3&)> f) {
  return std::make_shared<PositionSource>(std::move(name), std::move(f));
}

}  // namespace narwhal
