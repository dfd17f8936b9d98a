#include "physics/planar.hpp"

#include <cmath>

#include <fmt/format.h>

namespace narwhal {

namespace {

constexpr Real kPlanarTol = 1e-12;  // relative; geometry built from exactly planar nodes is exact

bool parallel(const Vec3& a, const Vec3& n) { return (a - a.dot(n) * n).norm() <= kPlanarTol * a.norm(); }

bool side_is_symmetry(const Block& b, int side) {
  bool any = false;
  for (const Patch& p : b.patches) {
    if (p.side != side) continue;
    if (p.type != BcType::Symmetry) return false;
    any = true;
  }
  return any;
}

}  // namespace

int planar_slab_direction(const Block& b, Vec3& normal) {
  for (int d = 0; d < 3; ++d) {
    if (b.n(d) != 1 || !side_is_symmetry(b, 2 * d) || !side_is_symmetry(b, 2 * d + 1)) continue;
    const Index3 e = unit(d);
    normal = b.S[d](0, 0, 0).normalized();
    bool ok = true;
    // Both planes flat, parallel and still; the faces across the slab equal.
    for_each_cell(b, [&](int i, int j, int k) {
      const Index3 lo{i, j, k}, hi = add(lo, e);
      const Vec3& s0 = b.S[d](lo);
      const Vec3& s1 = b.S[d](hi);
      ok = ok && parallel(s0, normal) && (s1 - s0).norm() <= kPlanarTol * s0.norm() && b.kt[d](lo) == 0.0 &&
           b.kt[d](hi) == 0.0;
    });
    // Every other face lies across the plane (no flux component along the normal).
    for (int t : {(d + 1) % 3, (d + 2) % 3}) {
      Index3 n = b.dims();
      n[t] += 1;
      for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
          for (int i = 0; i < n[0]; ++i) {
            const Vec3& s = b.S[t](i, j, k);
            ok = ok && std::abs(s.dot(normal)) <= kPlanarTol * s.norm();
          }
    }
    if (ok) return d;
  }
  return -1;
}

std::string mark_planar_blocks(Grid& g, const FlowField& f, const FlowParams& fp) {
  for (Block& b : g.blocks) b.planar_dir = -1;
  if (g.blocks.empty()) return "";
  std::vector<int> dir(g.blocks.size());
  Vec3 normal = Vec3::Zero();
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    Vec3 n;
    dir[ib] = planar_slab_direction(g.blocks[ib], n);
    if (dir[ib] < 0) return ib == 0 ? "" : fmt::format("not planar: block '{}' is not a symmetry slab", g.blocks[ib].name);
    if (ib == 0) normal = n;
    if (!parallel(n, normal))
      return fmt::format("not planar: block '{}' has another plane normal", g.blocks[ib].name);
  }
  auto across = [&](const Vec3& u) { return std::abs(u.dot(normal)) > kPlanarTol * std::max<Real>(1.0, u.norm()); };
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    for (const Patch& p : b.patches)
      if (across(p.velocity)) return fmt::format("not planar: patch '{}' has a velocity across the plane", p.label);
    bool flow_across = false;
    for_each_cell(b, [&](int i, int j, int k) {
      flow_across = flow_across || across(f.Q[ib](i, j, k).tail<3>()) ||
                    (fp.momentum_source && across(fp.momentum_source(b.xc(i, j, k))));
    });
    if (flow_across) return fmt::format("not planar: flow across the plane in block '{}'", b.name);
  }
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) g.blocks[ib].planar_dir = dir[ib];
  return fmt::format("planar grid (one-cell slabs between parallel symmetry planes, normal ({:.3g}, {:.3g}, {:.3g})): "
                     "the symmetry-plane faces are skipped, their fluxes cancel",
                     normal[0] + 0.0, normal[1] + 0.0, normal[2] + 0.0);  // no "-0"
}

}  // namespace narwhal
