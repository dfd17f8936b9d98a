#include "implicit/line_solver.hpp"

namespace narwhal {

int stiffest_direction(const Block& b) {
  int best = -1;
  Real best_sum = -1.0;
  for (int d = 0; d < 3; ++d) {
    if (d == b.invariant_dir || b.n(d) < 2) continue;
    Real sum = 0.0;
    for_each_cell(b, [&](int i, int j, int k) {
      const Index3 c{i, j, k};
      sum += (b.S[d](c).squaredNorm() + b.S[d](add(c, unit(d))).squaredNorm()) / b.vol(c);
    });
    if (sum > best_sum) {
      best_sum = sum;
      best = d;
    }
  }
  if (best >= 0) return best;
  return b.invariant_dir == 0 ? 1 : 0;  // one cell per line: any other direction solves it
}

}  // namespace narwhal
