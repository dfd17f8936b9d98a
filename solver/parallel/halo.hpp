#pragma once
// Halo exchange over blocks distributed on ranks (issue #6): precomputed plans per
// grid level say which ghost cells of the blocks a rank owns come from which donor
// cells, on this rank or another. On-rank and off-rank interfaces take the same path:
// values are gathered into per-peer buffers in the plan's order, sent (MPI
// non-blocking, or copied when the peer is this rank), and scattered into the ghosts,
// vectors and tensors rotated by the interface's R (rotational periodicity). The
// serial solver is the one-rank case of the same code.
//
// Ghost fills (owned_ghost_sweep) keep the serial sweep's structure
// (mesh/ghost_sweep.hpp): directions i, j, k, depth 1 before depth 2, tangential
// ranges extended into the ghosts of earlier directions so edges and corners come
// along, two rounds when there are interfaces. Each (direction, depth) step first
// exchanges every interface ghost of that step from a snapshot of the donors, then
// applies the physical BCs of the owned blocks. Nothing in a step depends on which
// rank owns what, so the ghosts are the same bit for bit on any number of ranks.
#include <array>
#include <cstring>
#include <memory>
#include <vector>

#include "fields/ghost_array.hpp"
#include "mesh/block.hpp"
#include "mesh/ghost_sweep.hpp"

namespace narwhal {

struct HaloCell {
  int block = -1;      // block index in the grid
  Index3 cell;         // ghost cell (receive) or donor cell (send)
  int interface = -1;  // the interface (receive side: rotation of vectors)
};

struct HaloPeer {
  int rank = -1;
  std::vector<HaloCell> send, receive;  // same length and order on both ends
};

struct ExchangePlan {
  int rank = 0;
  std::vector<HaloPeer> peers;  // one per rank this rank talks to (itself included)
  // Message buffers per peer, reused by every exchange through this plan.
  mutable std::vector<std::vector<double>> out, in;
  std::size_t sent_cells() const;  // off-rank only
  std::size_t messages() const;    // off-rank sends
};

// Which interface ghosts a plan covers.
struct GhostSelection {
  int dir = -1;          // patches of this direction only (-1: all)
  int depth = -1;        // ghost layer 1 or 2 (-1: both)
  bool extended = true;  // tangential ranges extended as in the ghost sweep; false: face range
};

// Calls visit(interface, ghost cell, donor block, donor cell) for every selected
// interface ghost of block ib, in the serial sweep's order (the plan's order).
template <class F>
void for_each_interface_ghost(const Grid& g, int ib, F&& visit, GhostSelection sel = {}) {
  const Block& b = g.blocks[ib];
  for (int d = 0; d < 3; ++d) {
    if (sel.dir >= 0 && d != sel.dir) continue;
    for (int m = 1; m <= kGhost; ++m) {
      if ((sel.depth >= 0 && m != sel.depth) || (!sel.extended && m > 1 && sel.depth < 0)) continue;
      for (const Patch& p : b.patches) {
        if (side_dir(p.side) != d || p.type != BcType::Interface) continue;
        const Interface& itf = g.interfaces[p.interface];
        for_each_in(sel.extended ? extended_cell_range(b, p) : face_range(p), [&](Index3 c) {
          const Index3 gc = ghost_cell(b, p.side, c, m);
          visit(p.interface, gc, itf.donor, itf.map_cell(gc));
        });
      }
    }
  }
}

// The plan of `rank` for the selected ghosts of a grid whose blocks are owned as
// `owner` says (empty: all on `rank`).
ExchangePlan build_exchange_plan(const Grid& g, const std::vector<int>& owner, int rank, GhostSelection sel = {});

// The plans of a grid's layout: one per (direction, depth) step of the ghost sweep,
// and one for the first layer of face ghosts (SGS corrections, work arrays).
struct HaloPlans {
  std::array<ExchangePlan, 3 * kGhost> sweep;  // [d * kGhost + m - 1]
  ExchangePlan faces;
  // The layout they were built for (rebuilt when it changes).
  std::size_t blocks = 0, interfaces = 0;
  std::vector<int> owner;
  int rank = 0;
};
const HaloPlans& halo_plans(const Grid& g);

// Moves the plan's buffers: out[k] to peer k, in[k] from peer k (doubles).
void transfer(const ExchangePlan& plan);

// Fills the plan's ghosts of the owned blocks of A (arrays of blocks not owned may be
// empty). rotate(R, value) maps a donor value into the receiver's frame. Collective:
// every rank calls it with its own plan.
template <class T, class Rotate>
void exchange(const Grid& g, const ExchangePlan& plan, std::vector<GhostArray<T>>& A, Rotate&& rotate) {
  static_assert(sizeof(T) % sizeof(double) == 0, "halo values are made of doubles");
  constexpr std::size_t w = sizeof(T) / sizeof(double);
  auto& out = plan.out;
  auto& in = plan.in;
  out.resize(plan.peers.size());
  in.resize(plan.peers.size());
  for (std::size_t k = 0; k < plan.peers.size(); ++k) {
    const HaloPeer& p = plan.peers[k];
    out[k].resize(w * p.send.size());
    in[k].resize(w * p.receive.size());
    double* o = out[k].data();
    for (const HaloCell& c : p.send) {
      std::memcpy(o, static_cast<const void*>(&A[c.block](c.cell)), sizeof(T));
      o += w;
    }
  }
  transfer(plan);
  for (std::size_t k = 0; k < plan.peers.size(); ++k) {
    const double* i = in[k].data();
    for (const HaloCell& c : plan.peers[k].receive) {
      T v;
      std::memcpy(static_cast<void*>(&v), i, sizeof(T));
      i += w;
      A[c.block](c.cell) = rotate(g.interfaces[c.interface].R, v);
    }
  }
}

// Rotations for exchange(): scalars stay, velocities in a State turn, tensors R T R^T.
struct Unrotated {
  template <class T>
  T operator()(const Mat3&, const T& v) const { return v; }
};
struct RotateVelocity {
  State operator()(const Mat3& R, State q) const {
    q.tail<3>() = R * q.tail<3>();
    return q;
  }
};
struct RotateTensor {
  Mat3 operator()(const Mat3& R, const Mat3& T) const { return R * T * R.transpose(); }
};

// State fields with the velocity rotated (the serial test's entry point).
void exchange_halo(const Grid& g, const ExchangePlan& plan, std::vector<GhostArray<State>>& Q);

// The ghost sweep over owned blocks: exchange(plan) for every interface step,
// fill(block, patch, depth) for the physical patches (see the header comment).
template <class Fill, class Exchange>
void owned_ghost_sweep(const Grid& g, Fill&& fill, Exchange&& exchange_step) {
  const bool interfaces = !g.interfaces.empty();
  const HaloPlans* plans = interfaces ? &halo_plans(g) : nullptr;
  for (int round = 0; round < (interfaces ? 2 : 1); ++round)
    for (int d = 0; d < 3; ++d)
      for (int m = 1; m <= kGhost; ++m) {
        if (plans) exchange_step(plans->sweep[static_cast<std::size_t>(d * kGhost + m - 1)]);
        for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
          if (!g.owns(ib)) continue;
          for (const Patch& p : g.blocks[ib].patches)
            if (side_dir(p.side) == d && p.type != BcType::Interface) fill(static_cast<int>(ib), p, m);
        }
      }
}

}  // namespace narwhal
