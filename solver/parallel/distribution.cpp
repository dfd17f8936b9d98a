#include "parallel/distribution.hpp"

#include <map>

#include "core/error.hpp"
#include "parallel/communicator.hpp"
#include "parallel/partition.hpp"

namespace narwhal {

void distribute(Grid& g, int ranks, int rank) {
  g.halo.reset();
  if (ranks <= 1) {
    g.owner.clear();
    g.rank = 0;
    return;
  }
  g.owner = assign_blocks(g, ranks).owner;
  g.rank = rank;
}

void gather_to_root(const Communicator& comm, const Grid& g, FlowField& f) {
  if (g.owner.empty()) return;
  const bool turb = !f.turb.empty();
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const int from = g.owner[ib];
    if (from == 0) continue;
    // Whole arrays, ghosts included: one message per array and block.
    auto move = [&](auto& array, int tag) {
      auto& raw = array.raw();
      const std::size_t bytes = raw.size() * sizeof(raw[0]);
      if (comm.rank() == from) comm.send(static_cast<const void*>(raw.data()), bytes, 0, tag);
      if (comm.is_root()) comm.receive(static_cast<void*>(raw.data()), bytes, from, tag);
    };
    if (comm.rank() != from && !comm.is_root()) continue;
    move(f.Q[ib], 1);
    if (!f.nu.empty()) move(f.nu[ib], 2);
    if (turb) move(f.turb[ib], 3);
  }
}

void copy_between_layouts(const Grid& pieces, FlowField& f_pieces, const Grid& whole, FlowField& f_whole, bool to_whole) {
  std::map<std::string, int> index;
  for (std::size_t ib = 0; ib < whole.blocks.size(); ++ib) index[whole.blocks[ib].name] = static_cast<int>(ib);
  FlowField& src = to_whole ? f_pieces : f_whole;
  FlowField& dst = to_whole ? f_whole : f_pieces;
  const Grid& dst_grid = to_whole ? whole : pieces;
  if (!src.turb.empty() && dst.turb.size() != dst_grid.blocks.size()) dst.allocate_turbulence(dst_grid);
  for (std::size_t ip = 0; ip < pieces.blocks.size(); ++ip) {
    const Block& p = pieces.blocks[ip];
    const std::string& name = p.parent.empty() ? p.name : p.parent;
    const auto it = index.find(name);
    if (it == index.end()) fail("block '{}' has no block '{}' to come from", p.name, name);
    const int iw = it->second;
    const Index3 o = p.parent_offset;
    for_each_cell(p, [&](int i, int j, int k) {
      const Index3 cp{i, j, k}, cw{i + o[0], j + o[1], k + o[2]};
      const Index3& s = to_whole ? cp : cw;
      const Index3& d = to_whole ? cw : cp;
      const std::size_t sb = to_whole ? ip : static_cast<std::size_t>(iw);
      const std::size_t db = to_whole ? static_cast<std::size_t>(iw) : ip;
      dst.Q[db](d) = src.Q[sb](s);
      if (!src.nu.empty()) dst.nu[db](d) = src.nu[sb](s);
      if (!src.turb.empty()) dst.turb[db](d) = src.turb[sb](s);
    });
  }
}

}  // namespace narwhal
