#include "mesh/level_stack.hpp"

#include "core/error.hpp"

namespace narwhal {
namespace {

// The signed volume of a block's middle cell (its handedness).
Real middle_cell_volume(const Block& b) {
  const int i = b.ni / 2, j = b.nj / 2, k = b.nk / 2;
  Vec3 e[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  for (int a = 0; a <= 1; ++a)
    for (int c = 0; c <= 1; ++c) {
      e[0] += b.x(i + 1, j + a, k + c) - b.x(i, j + a, k + c);
      e[1] += b.x(i + a, j + 1, k + c) - b.x(i + a, j, k + c);
      e[2] += b.x(i + a, j + c, k + 1) - b.x(i + a, j + c, k);
    }
  return e[0].dot(e[1].cross(e[2]));
}

}  // namespace

// The core's edges as the cap ring's innermost nodes (the same chart points, mapped alike),
// bit for bit.
void tie_core_to_cap_ring(Level& lv) {
  const auto& edge = lv.cap_ring.back();
  const int around = lv.split[4];
  const int na = static_cast<int>(lv.core.size()) - 1, nb = static_cast<int>(lv.core.front().size()) - 1;
  for (int q = 0; q <= na; ++q) {
    lv.core[static_cast<std::size_t>(q)].front() = edge[static_cast<std::size_t>(around - q)];
    lv.core[static_cast<std::size_t>(q)].back() = edge[static_cast<std::size_t>(lv.split[1] + q)];
  }
  for (int q = 0; q <= nb; ++q) {
    lv.core.front()[static_cast<std::size_t>(q)] = edge[static_cast<std::size_t>(q)];
    lv.core.back()[static_cast<std::size_t>(q)] = edge[static_cast<std::size_t>(lv.split[3] - q)];
  }
}

std::array<RingPart, 6> ring_parts(const std::array<int, 5>& split) {
  const int half_front = (split[1] - split[0]) / 2, half_back = (split[3] - split[2]) / 2;
  return {{{"fm", split[0], half_front},
           {"fp", split[0] + half_front, half_front},
           {"up", split[1], split[2] - split[1]},
           {"bp", split[2], half_back},
           {"bm", split[2] + half_back, half_back},
           {"lo", split[3], split[4] - split[3]}}};
}

void add_whole_side_patch(Block& b, int side, const std::string& label) {
  Patch p;
  p.side = side;
  p.lo = {0, 0, 0};
  p.hi = b.dims();
  p.label = label;
  b.patches.push_back(p);
}

Block ring_block(const std::vector<Level>& levels, RingOf which, const std::string& name, int s0, int cells, int k0,
                 int k1) {
  auto ring = [which](const Level& l) -> const std::vector<std::vector<Vec3>>& {
    return which == RingOf::O ? l.ring : l.cap_ring;
  };
  const int n = static_cast<int>(ring(levels[static_cast<std::size_t>(k0)]).size()) - 1;
  for (const bool reversed : {false, true}) {
    Block b(name, cells, n, k1 - k0);
    for (int k = k0; k <= k1; ++k) {
      const auto& r = ring(levels[static_cast<std::size_t>(k)]);
      for (int t = 0; t <= n; ++t)
        for (int i = 0; i <= cells; ++i) {
          const int s = s0 + (reversed ? cells - i : i);
          b.x(i, t, k - k0) = r[static_cast<std::size_t>(t)][static_cast<std::size_t>(s)];
        }
    }
    if (middle_cell_volume(b) > 0.0) return b;
  }
  fail("appendage box: block '{}' is folded", name);
}

Block core_block(const std::vector<Level>& levels, const std::string& name, int b0, int cells, int k0, int k1) {
  const int na = static_cast<int>(levels[static_cast<std::size_t>(k0)].core.size()) - 1;
  for (const bool reversed : {false, true}) {
    Block b(name, na, cells, k1 - k0);
    for (int k = k0; k <= k1; ++k)
      for (int bb = 0; bb <= cells; ++bb)
        for (int a = 0; a <= na; ++a) {
          const int q = b0 + (reversed ? cells - bb : bb);
          b.x(a, bb, k - k0) =
              levels[static_cast<std::size_t>(k)].core[static_cast<std::size_t>(a)][static_cast<std::size_t>(q)];
        }
    if (middle_cell_volume(b) > 0.0) return b;
  }
  fail("appendage box: block '{}' is folded", name);
}

}  // namespace narwhal
