#pragma once
// A stack of O-grid levels and the blocks cut from it: what an appendage's box
// (mesh/appendage_box.hpp) and the sail planes' tube are made of. Each level holds an O
// about a section (ring[t][s], t = 0 on the section) and, beyond a tip, the section's
// interior (the cap's ring inwards and its core); blocks take a range of ring positions
// (or core columns) over a range of levels.
#include <array>
#include <string>
#include <vector>

#include "mesh/block.hpp"

namespace narwhal {

struct Level {
  std::vector<std::vector<Vec3>> ring;      // [t][s], outwards from the section
  std::vector<std::vector<Vec3>> cap_ring;  // [t][s], inwards from the section
  std::vector<std::vector<Vec3>> core;      // [a][b]
  std::array<int, 5> split{};               // the O's parts along the ring (ogrid::OGrid::split)
};

// The core's edges as the cap ring's innermost nodes (the same chart points, mapped alike),
// bit for bit.
void tie_core_to_cap_ring(Level& lv);

enum class RingOf { O, Cap };

// The O's six blocks along its ring: the front halved (fm: from the lower junction to the
// leading edge, fp: on to the upper junction), the upper side (up), the back halved (bp,
// bm) and the lower side (lo); `half_front` is also the cap core's half width.
struct RingPart {
  const char* name;
  int s0, cells;
};
std::array<RingPart, 6> ring_parts(const std::array<int, 5>& split);

// A block of an O-type ring (the O's outwards, the cap's inwards) between ring positions
// [s0, s0 + cells] and levels [k0, k1]; i runs along the ring (reversed if that keeps the
// block right-handed), j across it. Fails naming the block when both orientations fold.
Block ring_block(const std::vector<Level>& levels, RingOf ring, const std::string& name, int s0, int cells, int k0,
                 int k1);

// The cap's core, its half on one side of the section's mean line, b in [b0, b0 + cells].
Block core_block(const std::vector<Level>& levels, const std::string& name, int b0, int cells, int k0, int k1);

// A patch over the whole of a block's side (0..5: imin, imax, jmin, jmax, kmin, kmax).
void add_whole_side_patch(Block& b, int side, const std::string& label);

}  // namespace narwhal
