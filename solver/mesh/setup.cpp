#include "mesh/setup.hpp"

#include "core/error.hpp"
#include "mesh/connectivity.hpp"

namespace narwhal {

int assign_bc(Grid& g, const std::string& label, const PatchBc& bc) {
  int n = 0;
  for (auto& b : g.blocks)
    for (auto& p : b.patches)
      if (p.label == label) {
        p.type = bc.type;
        p.velocity = bc.velocity;
        p.pressure = bc.pressure;
        p.body_surface = bc.body_surface || bc.type == BcType::Wall;  // every no-slip wall is the body's
        ++n;
      }
  return n;
}

void finalize_grid(Grid& g) {
  g.halo.reset();
  connect_free_faces(g);
  check_patch_cover(g);
  for (const auto& b : g.blocks)
    for (const auto& p : b.patches)
      if (p.type == BcType::Interface && p.interface < 0)
        fail("block '{}' side {}: patch '{}' has no boundary condition (no [bc.{}] given)", b.name,
             side_name(p.side), p.label, p.label);
  prepare_geometry(g);
  for (const auto& b : g.blocks)
    for (int k = 0; k < b.nk; ++k)
      for (int j = 0; j < b.nj; ++j)
        for (int i = 0; i < b.ni; ++i)
          if (!(b.vol(i, j, k) > 0.0))
            fail("block '{}' cell ({}, {}, {}) has non-positive volume {:.3e}: the grid is folded or left-handed",
                 b.name, i, j, k, b.vol(i, j, k));
}

}  // namespace narwhal
