#include "parallel/halo.hpp"

#include <map>

#ifdef NARWHAL_HAVE_MPI
#include <mpi.h>
#endif

#include "core/error.hpp"
#include "mesh/ghost_sweep.hpp"

namespace narwhal {

std::size_t ExchangePlan::sent_cells() const {
  std::size_t n = 0;
  for (const HaloPeer& p : peers)
    if (p.rank != rank) n += p.send.size();
  return n;
}


ExchangePlan build_exchange_plan(const Grid& g, const std::vector<int>& owner, int rank) {
  if (owner.size() != g.blocks.size()) fail("exchange plan: {} owners for {} blocks", owner.size(), g.blocks.size());
  ExchangePlan plan;
  plan.rank = rank;
  std::map<int, HaloPeer> peers;
  // Receives: ghosts of my blocks, from whoever owns the donor. Sends: donor cells of
  // mine that other ranks' (or my) ghosts need, in the receiver's order: the loop
  // over receiving blocks is the same on both ends.
  for (int ib = 0; ib < static_cast<int>(g.blocks.size()); ++ib) {
    for_each_interface_ghost(g, ib, [&](int itf, const Index3& gc, int donor, const Index3& dc) {
      if (owner[ib] == rank) {
        HaloPeer& p = peers[owner[donor]];
        p.rank = owner[donor];
        p.receive.push_back({ib, gc, itf});
      }
      if (owner[donor] == rank) {
        HaloPeer& p = peers[owner[ib]];
        p.rank = owner[ib];
        p.send.push_back({donor, dc, itf});
      }
    });
  }
  for (auto& [r, p] : peers) plan.peers.push_back(std::move(p));
  return plan;
}

void exchange_halo(const Grid& g, const ExchangePlan& plan, std::vector<GhostArray<State>>& Q) {
  std::vector<std::vector<State>> out(plan.peers.size()), in(plan.peers.size());
  for (std::size_t k = 0; k < plan.peers.size(); ++k) {
    const HaloPeer& p = plan.peers[k];
    out[k].reserve(p.send.size());
    for (const HaloCell& c : p.send) out[k].push_back(Q[c.block](c.cell));
    in[k].resize(p.receive.size());
  }
#ifdef NARWHAL_HAVE_MPI
  std::vector<MPI_Request> requests;
  constexpr int tag = 4711;
  for (std::size_t k = 0; k < plan.peers.size(); ++k) {
    const HaloPeer& p = plan.peers[k];
    if (p.rank == plan.rank) continue;
    const int n = static_cast<int>(4 * p.receive.size());
    if (n > 0) MPI_Irecv(in[k].data()->data(), n, MPI_DOUBLE, p.rank, tag, MPI_COMM_WORLD, &requests.emplace_back());
    const int s = static_cast<int>(4 * p.send.size());
    if (s > 0) MPI_Isend(out[k].data()->data(), s, MPI_DOUBLE, p.rank, tag, MPI_COMM_WORLD, &requests.emplace_back());
  }
#endif
  for (std::size_t k = 0; k < plan.peers.size(); ++k)
    if (plan.peers[k].rank == plan.rank) in[k] = out[k];  // on-rank: the message is a copy
#ifdef NARWHAL_HAVE_MPI
  if (!requests.empty()) MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
#else
  for (const HaloPeer& p : plan.peers)
    if (p.rank != plan.rank) fail("halo exchange with rank {} in a build without MPI", p.rank);
#endif
  for (std::size_t k = 0; k < plan.peers.size(); ++k) {
    const HaloPeer& p = plan.peers[k];
    for (std::size_t i = 0; i < p.receive.size(); ++i) {
      const HaloCell& c = p.receive[i];
      State q = in[k][i];
      q.tail<3>() = g.interfaces[c.interface].R * q.tail<3>();
      Q[c.block](c.cell) = q;
    }
  }
}

}  // namespace narwhal
