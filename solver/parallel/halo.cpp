#include "parallel/halo.hpp"

#include <map>

#ifdef NARWHAL_HAVE_MPI
#include <mpi.h>
#endif

#include "core/error.hpp"

namespace narwhal {

std::size_t ExchangePlan::sent_cells() const {
  std::size_t n = 0;
  for (const HaloPeer& p : peers)
    if (p.rank != rank) n += p.send.size();
  return n;
}

std::size_t ExchangePlan::messages() const {
  std::size_t n = 0;
  for (const HaloPeer& p : peers) n += p.rank != rank && !p.send.empty();
  return n;
}

ExchangePlan build_exchange_plan(const Grid& g, const std::vector<int>& owner, int rank, GhostSelection sel) {
  if (!owner.empty() && owner.size() != g.blocks.size())
    fail("exchange plan: {} owners for {} blocks", owner.size(), g.blocks.size());
  auto owner_of = [&](int ib) { return owner.empty() ? rank : owner[static_cast<std::size_t>(ib)]; };
  ExchangePlan plan;
  plan.rank = rank;
  std::map<int, HaloPeer> peers;
  // Receives: ghosts of my blocks, from whoever owns the donor. Sends: donor cells of
  // mine that other ranks' (or my) ghosts need, in the receiver's order: the loop
  // over receiving blocks is the same on both ends.
  for (int ib = 0; ib < static_cast<int>(g.blocks.size()); ++ib) {
    for_each_interface_ghost(
        g, ib,
        [&](int itf, const Index3& gc, int donor, const Index3& dc) {
          if (owner_of(ib) == rank) {
            HaloPeer& p = peers[owner_of(donor)];
            p.rank = owner_of(donor);
            p.receive.push_back({ib, gc, itf});
          }
          if (owner_of(donor) == rank) {
            HaloPeer& p = peers[owner_of(ib)];
            p.rank = owner_of(ib);
            p.send.push_back({donor, dc, itf});
          }
        },
        sel);
  }
  for (auto& [r, p] : peers) plan.peers.push_back(std::move(p));
  return plan;
}

const HaloPlans& halo_plans(const Grid& g) {
  const HaloPlans* h = g.halo.get();
  if (h && h->blocks == g.blocks.size() && h->interfaces == g.interfaces.size() && h->owner == g.owner &&
      h->rank == g.rank)
    return *h;
  auto plans = std::make_shared<HaloPlans>();
  for (int d = 0; d < 3; ++d)
    for (int m = 1; m <= kGhost; ++m)
      plans->sweep[static_cast<std::size_t>(d * kGhost + m - 1)] =
          build_exchange_plan(g, g.owner, g.rank, GhostSelection{d, m, true});
  plans->faces = build_exchange_plan(g, g.owner, g.rank, GhostSelection{-1, 1, false});
  plans->blocks = g.blocks.size();
  plans->interfaces = g.interfaces.size();
  plans->owner = g.owner;
  plans->rank = g.rank;
  g.halo = plans;
  return *plans;
}

void transfer(const ExchangePlan& plan) {
  auto& out = plan.out;
  auto& in = plan.in;
#ifdef NARWHAL_HAVE_MPI
  std::vector<MPI_Request> requests;
  constexpr int tag = 4711;
  for (std::size_t k = 0; k < plan.peers.size(); ++k) {
    const HaloPeer& p = plan.peers[k];
    if (p.rank == plan.rank) continue;
    if (!in[k].empty())
      MPI_Irecv(in[k].data(), static_cast<int>(in[k].size()), MPI_DOUBLE, p.rank, tag, MPI_COMM_WORLD,
                &requests.emplace_back());
    if (!out[k].empty())
      MPI_Isend(out[k].data(), static_cast<int>(out[k].size()), MPI_DOUBLE, p.rank, tag, MPI_COMM_WORLD,
                &requests.emplace_back());
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
}

void exchange_halo(const Grid& g, const ExchangePlan& plan, std::vector<GhostArray<State>>& Q) {
  exchange(g, plan, Q, RotateVelocity{});
}

}  // namespace narwhal
