#include "parallel/partition.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "core/error.hpp"
#include "mesh/generators.hpp"

namespace narwhal {

Real BlockAssignment::imbalance() const {
  if (cells.empty()) return 0.0;
  const Real total = std::accumulate(cells.begin(), cells.end(), 0.0);
  if (total == 0.0) return 0.0;
  return static_cast<Real>(*std::max_element(cells.begin(), cells.end())) / (total / cells.size()) - 1.0;
}

namespace {

// Interface faces of each block, by neighbour block.
std::vector<std::vector<std::pair<int, std::size_t>>> interface_faces(const Grid& g) {
  std::vector<std::vector<std::pair<int, std::size_t>>> shared(g.blocks.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for (const Patch& p : g.blocks[ib].patches) {
      if (p.type != BcType::Interface || p.interface < 0) continue;
      std::size_t faces = 1;
      for (int t = 0; t < 3; ++t)
        if (t != side_dir(p.side)) faces *= static_cast<std::size_t>(p.hi[t] - p.lo[t]);
      shared[ib].push_back({g.interfaces[p.interface].donor, faces});
    }
  return shared;
}

}  // namespace

namespace {

BlockAssignment empty_assignment(const Grid& g, int ranks) {
  BlockAssignment a;
  a.owner.assign(g.blocks.size(), -1);
  a.cells.assign(static_cast<std::size_t>(ranks), 0);
  return a;
}

void place(const Grid& g, BlockAssignment& a, int ib, int r) {
  a.owner[ib] = r;
  a.cells[r] += g.blocks[ib].cells();
}

// Largest block first onto the least loaded rank (ties: the rank with most of the
// block's interface faces).
BlockAssignment largest_first(const Grid& g, int ranks, const std::vector<std::vector<std::pair<int, std::size_t>>>& shared) {
  BlockAssignment a = empty_assignment(g, ranks);
  std::vector<int> order(g.blocks.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int x, int y) { return g.blocks[x].cells() > g.blocks[y].cells(); });
  for (int ib : order) {
    const std::size_t least = *std::min_element(a.cells.begin(), a.cells.end());
    int best = -1;
    std::size_t best_shared = 0;
    for (int r = 0; r < ranks; ++r) {
      if (a.cells[r] != least) continue;
      std::size_t s = 0;
      for (const auto& [other, faces] : shared[ib])
        if (a.owner[other] == r) s += faces;
      if (best < 0 || s > best_shared) {
        best = r;
        best_shared = s;
      }
    }
    place(g, a, ib, best);
  }
  return a;
}

// Blocks in breadth-first order over the interface graph, cut into consecutive runs of
// about total/ranks cells: neighbours share a rank.
BlockAssignment contiguous(const Grid& g, int ranks, const std::vector<std::vector<std::pair<int, std::size_t>>>& shared) {
  BlockAssignment a = empty_assignment(g, ranks);
  std::vector<int> order;
  std::vector<bool> seen(g.blocks.size(), false);
  for (std::size_t start = 0; start < g.blocks.size(); ++start) {
    if (seen[start]) continue;
    seen[start] = true;
    order.push_back(static_cast<int>(start));
    for (std::size_t q = order.size() - 1; q < order.size(); ++q)
      for (const auto& [other, faces] : shared[order[q]])
        if (!seen[other]) {
          seen[other] = true;
          order.push_back(other);
        }
  }
  const Real target = static_cast<Real>(g.cells()) / ranks;
  std::size_t done = 0;
  for (int ib : order) {
    // The rank whose share [r target, (r+1) target) holds this block's middle cell.
    const Real middle = done + 0.5 * g.blocks[ib].cells();
    place(g, a, ib, std::min(ranks - 1, static_cast<int>(middle / target)));
    done += g.blocks[ib].cells();
  }
  return a;
}

std::size_t cut_faces(const BlockAssignment& a, const std::vector<std::vector<std::pair<int, std::size_t>>>& shared) {
  std::size_t cut = 0;
  for (std::size_t ib = 0; ib < shared.size(); ++ib)
    for (const auto& [other, faces] : shared[ib])
      if (a.owner[ib] != a.owner[other]) cut += faces;
  return cut;
}

}  // namespace

BlockAssignment assign_blocks(const Grid& g, int ranks) {
  if (ranks < 1) fail("assign_blocks: {} ranks", ranks);
  const auto shared = interface_faces(g);
  BlockAssignment a = largest_first(g, ranks, shared), b = contiguous(g, ranks, shared);
  // Cells first (within 1 %), then fewer interface faces between ranks.
  const Real ia = a.imbalance(), ibal = b.imbalance();
  if (ibal < ia - 0.01) return b;
  if (ia < ibal - 0.01) return a;
  return cut_faces(b, shared) < cut_faces(a, shared) ? b : a;
}

namespace {

// Cut positions of n cells into `parts` pieces, on multiples of `stride` (empty when
// some piece would be empty).
std::vector<int> cuts_of(int n, int parts, int stride) {
  std::vector<int> c{0};
  for (int p = 1; p < parts; ++p) {
    const int x = static_cast<int>(std::lround(static_cast<double>(n) * p / parts / stride)) * stride;
    if (x <= c.back() || x >= n) return {};
    c.push_back(x);
  }
  c.push_back(n);
  return c;
}

Grid tensor_split(const Grid& g, const std::vector<Index3>& parts, int stride) {
  Grid out;
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    const Block& b = g.blocks[ib];
    if (parts[ib] == Index3{1, 1, 1}) {
      out.blocks.push_back(b);
      continue;
    }
    std::array<std::vector<int>, 3> c;
    for (int d = 0; d < 3; ++d) c[d] = cuts_of(b.n(d), parts[ib][d], stride);
    for (int pk = 0; pk < parts[ib][2]; ++pk)
      for (int pj = 0; pj < parts[ib][1]; ++pj)
        for (int pi = 0; pi < parts[ib][0]; ++pi)
        {
          Block piece = extract_block(b, fmt::format("{}_p{}_{}_{}", b.name, pi, pj, pk), {c[0][pi], c[1][pj], c[2][pk]},
                                      {c[0][pi + 1], c[1][pj + 1], c[2][pk + 1]});
          piece.parent = b.parent.empty() ? b.name : b.parent;
          piece.parent_offset = add(b.parent_offset, Index3{c[0][pi], c[1][pj], c[2][pk]});
          out.blocks.push_back(std::move(piece));
        }
  }
  return out;
}

}  // namespace

Grid split_for_balance(const Grid& g, int ranks, Real tolerance, int multigrid_levels, int max_blocks,
                       const std::vector<std::array<bool, 3>>& uncut) {
  if (!uncut.empty() && uncut.size() != g.blocks.size())
    fail("split_for_balance: {} uncut masks for {} blocks", uncut.size(), g.blocks.size());
  if (!g.interfaces.empty()) fail("split_for_balance works on grids before connectivity (finalize_grid)");
  const int stride = 1 << std::max(0, multigrid_levels - 1);
  std::vector<Index3> parts(g.blocks.size(), Index3{1, 1, 1});
  std::vector<bool> done(g.blocks.size(), false);
  Grid out = g;
  while (assign_blocks(out, ranks).imbalance() > tolerance && static_cast<int>(out.blocks.size()) < max_blocks) {
    // The original block with the largest pieces gets one more cut along the
    // direction in which its pieces are longest.
    int ib = -1;
    std::size_t piece = 0;
    for (std::size_t b = 0; b < g.blocks.size(); ++b) {
      const std::size_t c = g.blocks[b].cells() / static_cast<std::size_t>(parts[b][0] * parts[b][1] * parts[b][2]);
      if (!done[b] && c > piece) {
        piece = c;
        ib = static_cast<int>(b);
      }
    }
    if (ib < 0) break;
    const Block& b = g.blocks[ib];
    int d = -1;
    for (int t = 0; t < 3; ++t) {
      if (!uncut.empty() && uncut[static_cast<std::size_t>(ib)][static_cast<std::size_t>(t)]) continue;
      if (cuts_of(b.n(t), parts[ib][t] + 1, stride).empty()) continue;
      if (d < 0 || b.n(t) * parts[ib][d] > b.n(d) * parts[ib][t]) d = t;
    }
    if (d < 0) {
      done[ib] = true;  // no further cut keeps every multigrid level
      continue;
    }
    ++parts[ib][d];
    out = tensor_split(g, parts, stride);
  }
  return out;
}

}  // namespace narwhal
