// The communicator on however many ranks the test runs with (CTest: 1 and, in MPI
// builds, 2 under mpirun): reductions and broadcasts give the same on every rank.
#include <gtest/gtest.h>

#include <cstdlib>

#include "parallel/communicator.hpp"

namespace narwhal {
namespace {

TEST(Communicator, ReductionsOverRanks) {
  const Communicator c = Communicator::world();
  const int n = c.size();
  // Under mpirun the communicator must see every rank (not a one-rank stand-in).
  if (const char* launched = std::getenv("OMPI_COMM_WORLD_SIZE")) {
    EXPECT_EQ(n, std::atoi(launched));
  }
  EXPECT_GE(c.rank(), 0);
  EXPECT_LT(c.rank(), n);
  EXPECT_EQ(c.sum(static_cast<Real>(c.rank())), n * (n - 1) / 2.0);
  EXPECT_EQ(c.sum(static_cast<long long>(c.rank() + 1)), static_cast<long long>(n) * (n + 1) / 2);
  EXPECT_EQ(c.max(static_cast<Real>(c.rank())), n - 1.0);
  EXPECT_EQ(c.min(static_cast<Real>(c.rank())), 0.0);
  std::vector<Real> v{1.0, static_cast<Real>(c.rank())};
  c.sum(v);
  EXPECT_EQ(v[0], static_cast<Real>(n));
  EXPECT_EQ(v[1], n * (n - 1) / 2.0);
}

TEST(Communicator, BroadcastFromRoot) {
  const Communicator c = Communicator::world();
  std::vector<Real> v;
  if (c.is_root()) v = {3.0, -1.5, 2e-300};
  c.broadcast(v);
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[2], 2e-300);
  c.barrier();
}

}  // namespace
}  // namespace narwhal

int main(int argc, char** argv) {
  narwhal::ParallelSession session(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  // Only the root prints (every rank runs and checks everything).
  if (!narwhal::Communicator::world().is_root()) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
}
