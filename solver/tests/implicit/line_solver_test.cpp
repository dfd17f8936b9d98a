// The line solver against a dense solve of the same block-tridiagonal system.
#include <gtest/gtest.h>

#include <random>

#include <Eigen/Dense>

#include "implicit/line_solver.hpp"

namespace narwhal {
namespace {

// A block of ni x nj x nk cells; random diagonally dominant 3x3 point blocks and
// couplings along direction L only (other directions uncoupled): one forward sweep
// must then solve the whole system exactly.
void check_exact_on_lines(int ni, int nj, int nk, int L) {
  constexpr int N = 3;
  using Mat = Eigen::Matrix<Real, N, N>;
  using Vec = Eigen::Matrix<Real, N, 1>;
  Block b("test", ni, nj, nk);
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> u(-1.0, 1.0);
  auto random_mat = [&] {
    Mat m;
    for (int r = 0; r < N; ++r)
      for (int c = 0; c < N; ++c) m(r, c) = u(rng);
    return m;
  };
  GhostArray<Mat> D(ni, nj, nk, 0, Mat::Zero()), lower(ni, nj, nk, 0, Mat::Zero()), upper(ni, nj, nk, 0, Mat::Zero());
  GhostArray<Vec> rhs(ni, nj, nk, 0, Vec::Zero()), x(ni, nj, nk, 1, Vec::Zero());
  for_each_cell(b, [&](int i, int j, int k) {
    D(i, j, k) = random_mat() + 8.0 * Mat::Identity();
    lower(i, j, k) = random_mat();
    upper(i, j, k) = random_mat();
    rhs(i, j, k) = Vec(u(rng), u(rng), u(rng));
  });
  LineFactorization<N> lines;
  lines.factorize(b, L, [&](const Index3& c) { return D(c); }, [&](const Index3& c) { return lower(c); },
                  [&](const Index3& c) { return upper(c); });
  lines.sweep(b, true, [&](const Index3& c) { return rhs(c); }, [&](const Index3& c) { return upper(c); }, x);

  // Dense system: unknowns ordered by cell (memory order).
  const int n = ni * nj * nk;
  auto id = [&](const Index3& c) { return (c[0] + ni * (c[1] + nj * c[2])); };
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(N * n, N * n);
  Eigen::VectorXd f(N * n);
  for_each_cell(b, [&](int i, int j, int k) {
    const Index3 c{i, j, k};
    const int r = id(c);
    A.block<N, N>(N * r, N * r) = D(c);
    f.segment<N>(N * r) = rhs(c);
    if (c[L] > 0) A.block<N, N>(N * r, N * id(add(c, unit(L), -1))) = lower(c);
    if (c[L] < b.n(L) - 1) A.block<N, N>(N * r, N * id(add(c, unit(L)))) = upper(c);
  });
  const Eigen::VectorXd exact = A.partialPivLu().solve(f);
  for_each_cell(b, [&](int i, int j, int k) {
    const Index3 c{i, j, k};
    for (int m = 0; m < N; ++m) EXPECT_NEAR(x(c)[m], exact[N * id(c) + m], 1e-12) << i << " " << j << " " << k;
  });
}

TEST(LineSolver, SolvesLinesInEachDirectionExactly) {
  check_exact_on_lines(7, 3, 2, 0);
  check_exact_on_lines(3, 7, 2, 1);
  check_exact_on_lines(2, 3, 7, 2);
}

TEST(LineSolver, StiffestDirectionIsTheThinOne) {
  Block b("slab", 4, 5, 1);
  // Nodes: unit spacing in i and k, 1e-3 in j.
  b.x.resize(b.ni + 1, b.nj + 1, b.nk + 1, kGhost, Vec3::Zero());
  for (int k = -kGhost; k <= b.nk + kGhost; ++k)
    for (int j = -kGhost; j <= b.nj + kGhost; ++j)
      for (int i = -kGhost; i <= b.ni + kGhost; ++i) b.x(i, j, k) = Vec3(i, 1e-3 * j, k);
  compute_metrics(b);
  EXPECT_EQ(stiffest_direction(b), 1);
}

}  // namespace
}  // namespace narwhal
