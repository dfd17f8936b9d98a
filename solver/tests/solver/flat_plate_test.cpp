// Laminar flat plate, Re_L = 1e5 (issue bar 5): skin friction within 1% of
// Blasius at every wall face over 0.1 < x/L < 0.9 (RMS within 0.5%), and the
// displacement thickness at x/L = 0.5 within 1%, after a 10-order residual drop.
// The Blasius constants are read from reference_data/, not typed here.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "app/driver.hpp"
#include "io/restart.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

struct Blasius {
  Real cf_coeff;     // Cf sqrt(Re_x) = 2 f''(0)
  Real delta_coeff;  // delta* sqrt(Re_x) / x = lim (eta - f)
  Real eta99;        // f'(eta99) = 0.99
};

Blasius blasius_from_reference() {
  auto t = test::read_csv(test::source_path("reference_data/flat_plate/blasius_laminar_flat_plate.csv"));
  Blasius b;
  b.cf_coeff = 2.0 * t.at("fpp").front();
  b.delta_coeff = t.at("eta").back() - t.at("f").back();
  const auto& eta = t.at("eta");
  const auto& fp = t.at("fp");
  std::size_t k = 1;
  while (fp[k] < 0.99) ++k;
  b.eta99 = eta[k - 1] + (0.99 - fp[k - 1]) * (eta[k] - eta[k - 1]) / (fp[k] - fp[k - 1]);
  return b;
}

TEST(FlatPlate, LaminarSkinFrictionAndDisplacementThicknessMatchBlasius) {
  const std::string case_file = test::source_path("validation/cases/flat_plate_laminar/flat_plate.toml");
  const CaseConfig c = load_case(case_file);
  const std::string out = (test::fresh_temp_dir("narwhal_flat_plate_test")).string();
  std::filesystem::remove_all(out);
  RunOptions opt;
  opt.out_dir = out;
  const RunSummary s = run_case(c, opt);
  ASSERT_EQ(s.status, RunStatus::Converged) << s.message;
  EXPECT_LE(s.residual_drop, 1e-10);
  std::printf("flat plate: %d iterations, %.1f s, residual drop %.2e\n", s.iterations, s.wall_seconds,
              s.residual_drop);

  const Blasius bl = blasius_from_reference();
  const Real Re = c.flow.reynolds;
  auto surf = test::read_csv(out + "/surface_plate.csv");
  Real worst = 0.0, sq = 0.0;
  int n = 0;
  for (std::size_t i = 0; i < surf.at("x").size(); ++i) {
    const Real x = surf.at("x")[i];
    if (x <= 0.1 || x >= 0.9) continue;
    const Real e = surf.at("cf_x")[i] / (bl.cf_coeff / std::sqrt(Re * x)) - 1.0;
    worst = std::max(worst, std::abs(e));
    sq += e * e;
    ++n;
  }
  const Real rms = std::sqrt(sq / n);
  std::printf("flat plate Cf vs Blasius over %d faces in 0.1 < x < 0.9: max %.3f%%, RMS %.3f%%\n", n, 100 * worst,
              100 * rms);
  EXPECT_GT(n, 20);
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(rms, 0.005);

  // Displacement thickness at x = 0.5 from the restart file (the run's state).
  Grid g = build_grid(c);
  FlowField f;
  f.allocate(g, flow_params(c), c.initial);
  read_restart(out + "/restart.h5", g, f, "laminar");
  const Block& b = g.blocks[0];
  // delta* = int_0^ye (1 - u/u_e) dy with y_e = 3 delta99(Blasius) and u_e = u(y_e),
  // interpolated linearly in x between the two columns around x = 0.5.
  auto column = [&](int i) {
    const Real x = b.xc(i, 0, 0).x();
    const Real ye = 3.0 * bl.eta99 * x / std::sqrt(Re * x);
    int je = 0;
    while (b.xc(i, je, 0).y() < ye) ++je;
    const Real ue = f.Q[0](i, je, 0)[1];
    Real d = 0.0;
    for (int j = 0; j < je; ++j) {
      const Real dy = b.x(i, j + 1, 0).y() - b.x(i, j, 0).y();
      d += (1.0 - f.Q[0](i, j, 0)[1] / ue) * dy;
    }
    return std::pair<Real, Real>(x, d);
  };
  int i = 0;
  while (b.xc(i + 1, 0, 0).x() < 0.5) ++i;
  const auto [x0, d0] = column(i);
  const auto [x1, d1] = column(i + 1);
  const Real dstar = d0 + (d1 - d0) * (0.5 - x0) / (x1 - x0);
  const Real dstar_ref = bl.delta_coeff * 0.5 / std::sqrt(Re * 0.5);
  std::printf("flat plate delta* at x = 0.5: %.6e vs Blasius %.6e (%.3f%%)\n", dstar, dstar_ref,
              100 * (dstar / dstar_ref - 1));
  EXPECT_LT(std::abs(dstar / dstar_ref - 1.0), 0.01);
}

}  // namespace
}  // namespace narwhal
