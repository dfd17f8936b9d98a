#include "physics/invariant_direction.hpp"

#include <cmath>
#include <optional>

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

// Every patch of `side` an interface of block ib with its own opposite side, by a
// translation (no rotation of vectors).
bool side_is_self_periodic(const Grid& g, int ib, int side) {
  const Block& b = g.blocks[static_cast<std::size_t>(ib)];
  bool any = false;
  for (const Patch& p : b.patches) {
    if (p.side != side) continue;
    if (p.type != BcType::Interface || p.interface < 0) return false;
    const Interface& itf = g.interfaces[static_cast<std::size_t>(p.interface)];
    if (itf.donor != ib || itf.donor_side != (side ^ 1) || !itf.R.isIdentity(0.0)) return false;
    any = true;
  }
  return any;
}

// The faces across the layer equal (and still), and for symmetry planes flat and
// parallel to `normal`.
bool faces_across_match(const Block& b, int d, const Vec3& normal, bool must_be_parallel) {
  const Index3 e = unit(d);
  bool ok = true;
  for_each_cell(b, [&](int i, int j, int k) {
    const Index3 lo{i, j, k}, hi = add(lo, e);
    const Vec3& s0 = b.S[d](lo);
    const Vec3& s1 = b.S[d](hi);
    ok = ok && (!must_be_parallel || parallel(s0, normal)) && (s1 - s0).norm() <= kPlanarTol * s0.norm() &&
         b.kt[d](lo) == 0.0 && b.kt[d](hi) == 0.0;
  });
  return ok;
}

// Every other face lies across the plane (no flux component along the normal).
bool other_faces_in_plane(const Block& b, int d, const Vec3& normal) {
  for (int t : {(d + 1) % 3, (d + 2) % 3}) {
    Index3 n = b.dims();
    n[t] += 1;
    for (int k = 0; k < n[2]; ++k)
      for (int j = 0; j < n[1]; ++j)
        for (int i = 0; i < n[0]; ++i) {
          const Vec3& s = b.S[t](i, j, k);
          if (std::abs(s.dot(normal)) > kPlanarTol * s.norm()) return false;
        }
  }
  return true;
}

}  // namespace

Slab slab_direction(const Grid& g, int ib) {
  const Block& b = g.blocks[static_cast<std::size_t>(ib)];
  for (int d = 0; d < 3; ++d) {
    if (b.n(d) != 1) continue;
    const Vec3 normal = b.S[d](0, 0, 0).normalized();
    if (side_is_symmetry(b, 2 * d) && side_is_symmetry(b, 2 * d + 1) && faces_across_match(b, d, normal, true) &&
        other_faces_in_plane(b, d, normal))
      return {SlabKind::SymmetryPlanes, d, normal};
    if (side_is_self_periodic(g, ib, 2 * d) && side_is_self_periodic(g, ib, 2 * d + 1) &&
        faces_across_match(b, d, normal, false))
      return {SlabKind::SelfPeriodic, d, normal};
  }
  return {};
}

std::string mark_invariant_directions(Grid& g, const FlowField& f, const FlowParams& fp) {
  for (Block& b : g.blocks) b.invariant_dir = -1;
  if (g.blocks.empty()) return "";
  std::vector<Slab> slab(g.blocks.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    slab[ib] = slab_direction(g, static_cast<int>(ib));
    if (slab[ib].kind == SlabKind::None)
      return ib == 0 ? "" : fmt::format("not invariant: block '{}' is not a one-cell slab", g.blocks[ib].name);
    if (slab[ib].kind != slab[0].kind)
      return fmt::format("not invariant: block '{}' is another kind of slab", g.blocks[ib].name);
    // The periodic normal's sign is a matter of the block's handedness.
    if (!parallel(slab[ib].normal, slab[0].normal))
      return fmt::format("not invariant: block '{}' has another normal", g.blocks[ib].name);
  }
  const Vec3 normal = slab[0].normal;
  if (slab[0].kind == SlabKind::SymmetryPlanes) {
    // A velocity along the normal would make the mirror ghosts differ from the cells.
    auto across = [&](const Vec3& u) { return std::abs(u.dot(normal)) > kPlanarTol * std::max<Real>(1.0, u.norm()); };
    for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
      const Block& b = g.blocks[ib];
      for (const Patch& p : b.patches)
        if (across(p.velocity)) return fmt::format("not planar: patch '{}' has a velocity across the plane", p.label);
      bool flow_across = false;
      for_each_cell(b, [&](int i, int j, int k) {
        flow_across = flow_across || across(f.Q[ib](i, j, k).tail<3>());
        for (const auto& source : fp.sources) {
          const std::optional<Vec3> m = source->momentum_at(b.xc(i, j, k));
          flow_across = flow_across || !m || across(*m);  // a state-dependent source might push across
        }
      });
      if (flow_across) return fmt::format("not planar: flow across the plane in block '{}'", b.name);
    }
  }
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) g.blocks[ib].invariant_dir = slab[ib].dir;
  const std::string n = fmt::format("({:.3g}, {:.3g}, {:.3g})", normal[0] + 0.0, normal[1] + 0.0, normal[2] + 0.0);
  if (slab[0].kind == SlabKind::SymmetryPlanes)
    return fmt::format("planar grid (one-cell slabs between parallel symmetry planes, normal {}): "
                       "the symmetry-plane faces are skipped, their fluxes cancel",
                       n);
  return fmt::format("invariant along {} (one-cell layers periodic onto themselves): "
                     "the periodic faces are skipped, their fluxes cancel",
                     n);
}

}  // namespace narwhal
