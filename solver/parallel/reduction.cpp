#include "parallel/reduction.hpp"

#include "core/error.hpp"
#include "parallel/communicator.hpp"

namespace narwhal {

std::vector<Real> sum_in_block_order(const Communicator& comm, const Grid& g, std::vector<Real> partials, int width) {
  const std::size_t w = static_cast<std::size_t>(width);
  if (partials.size() != g.blocks.size() * w)
    fail("sum_in_block_order: {} partials for {} blocks of width {}", partials.size(), g.blocks.size(), width);
  if (!g.owner.empty()) comm.sum(partials);
  std::vector<Real> total(w, 0.0);
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib)
    for (std::size_t m = 0; m < w; ++m) total[m] += partials[ib * w + m];
  return total;
}

std::string description_of_largest(const Communicator& comm, Real local_largest, std::string local_description) {
  if (comm.size() == 1) return local_description;
  const Real global = comm.max(local_largest);
  const int teller = static_cast<int>(comm.min(local_largest == global ? comm.rank() : comm.size()));
  comm.broadcast(local_description, teller);
  return local_description;
}

}  // namespace narwhal
