#include "multigrid/coarsen.hpp"

#include "core/error.hpp"

namespace narwhal {

Index3 coarsening_factors(const Block& b) {
  Index3 c;
  for (int d = 0; d < 3; ++d) c[d] = b.n(d) > 1 ? 2 : 1;
  return c;
}

std::string why_not_coarsenable(const Grid& g, int min_cells) {
  for (const Block& b : g.blocks) {
    const Index3 c = coarsening_factors(b);
    if (c == Index3{1, 1, 1}) return fmt::format("block '{}' has a single cell in every direction", b.name);
    for (int d = 0; d < 3; ++d)
      if (c[d] == 2 && b.n(d) % 2 != 0)
        return fmt::format("block '{}' has {} cells in direction {} (odd)", b.name, b.n(d), "ijk"[d]);
    for (int d = 0; d < 3; ++d)
      if (c[d] == 2 && b.n(d) / 2 < min_cells)
        return fmt::format("block '{}' would keep {} cell(s) in direction {} (fewer than {})", b.name, b.n(d) / 2,
                           "ijk"[d], min_cells);
    for (const Patch& p : b.patches)
      for (int d = 0; d < 3; ++d)
        if (d != side_dir(p.side) && c[d] == 2 && (p.lo[d] % 2 != 0 || p.hi[d] % 2 != 0))
          return fmt::format("block '{}' patch '{}' starts or ends at an odd index in direction {}", b.name,
                             p.label, "ijk"[d]);
  }
  for (const Interface& itf : g.interfaces) {
    const Index3 ca = coarsening_factors(g.blocks[itf.block]);
    const Index3 cb = coarsening_factors(g.blocks[itf.donor]);
    for (int m = 0; m < 3; ++m)
      for (int n = 0; n < 3; ++n)
        if (itf.T(n, m) != 0 && m != side_dir(itf.side) && ca[m] != cb[n])
          return fmt::format("interface '{}'-'{}' joins directions coarsened differently", g.blocks[itf.block].name,
                             g.blocks[itf.donor].name);
  }
  return "";
}

Grid coarsen(const Grid& g) {
  const std::string why = why_not_coarsenable(g);
  if (!why.empty()) fail("cannot coarsen the grid: {}", why);
  Grid h;
  h.owner = g.owner;  // a coarse block lives where its fine block does
  h.rank = g.rank;
  for (const Block& b : g.blocks) {
    const Index3 c = coarsening_factors(b);
    Block cb(b.name, b.ni / c[0], b.nj / c[1], b.nk / c[2]);
    cb.invariant_dir = b.invariant_dir;  // a slab stays a slab: the one-cell direction is not coarsened
    cb.parent = b.parent;
    for (int d = 0; d < 3; ++d) cb.parent_offset[d] = b.parent_offset[d] / c[d];
    for (int k = 0; k <= cb.nk; ++k)
      for (int j = 0; j <= cb.nj; ++j)
        for (int i = 0; i <= cb.ni; ++i) cb.x(i, j, k) = b.x(c[0] * i, c[1] * j, c[2] * k);
    for (Patch p : b.patches) {
      for (int d = 0; d < 3; ++d) {
        p.lo[d] /= c[d];
        p.hi[d] /= c[d];
      }
      cb.patches.push_back(p);
    }
    h.blocks.push_back(std::move(cb));
  }
  for (Interface itf : g.interfaces) {
    const Index3 ca = coarsening_factors(g.blocks[itf.block]);
    const Index3 cd = coarsening_factors(g.blocks[itf.donor]);
    for (int d = 0; d < 3; ++d) {
      itf.a0[d] /= ca[d];
      itf.b0[d] /= cd[d];
    }
    h.interfaces.push_back(itf);
  }
  prepare_geometry(h);
  return h;
}

CoarseLevels coarse_levels(const Grid& fine, int levels, int min_cells) {
  CoarseLevels out;
  for (int built = 1; built < levels; ++built) {
    const Grid& last = out.grids.empty() ? fine : out.grids.back();
    out.stop = why_not_coarsenable(last);
    out.impossible = !out.stop.empty();
    if (!out.impossible) out.stop = why_not_coarsenable(last, min_cells);
    if (!out.stop.empty()) break;
    out.grids.push_back(coarsen(last));
  }
  return out;
}

}  // namespace narwhal
