#include "turbulence/baldwin_lomax.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bc/boundary.hpp"
#include "mesh/ghost_sweep.hpp"
#include "physics/residual.hpp"
#include "turbulence/flow_gradients.hpp"

namespace narwhal {

namespace {
constexpr Real kappa = 0.40, aplus = 26.0, ccp = 1.6, ckleb = 0.3, cwk = 0.25, kclauser = 0.0168;

}  // namespace

FunctionPeak refined_peak(const Real y[3], const Real F[3]) {
  const Real d01 = (F[1] - F[0]) / (y[1] - y[0]), d12 = (F[2] - F[1]) / (y[2] - y[1]);
  const Real a = (d12 - d01) / (y[2] - y[0]);  // F = F1 + (y - y1) (d01 + a (y - y0))
  if (!(a < 0.0)) return {y[1], F[1]};          // no interior maximum: keep the cell's
  const Real yp = std::clamp(0.5 * (y[0] + y[1]) - 0.5 * d01 / a, y[0], y[2]);
  return {yp, std::max(F[1], F[1] + (yp - y[1]) * (d01 + a * (yp - y[0])))};
}

void BaldwinLomax::update_viscosity(const Grid& g, FlowField& f, const FlowParams& fp) {
  const Real nu = 1.0 / fp.reynolds;
  const Real w = *settings_.relaxation;
  nut_.resize(g.blocks.size());
  ywall_.resize(g.blocks.size());
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    // The search runs along grid lines inside the block; the balancer keeps lines
    // normal to walls uncut when this model runs (parallel/partition.hpp).
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    const auto& Q = f.Q[ib];
    auto& nut = nut_[ib];
    auto& ywall = ywall_[ib];
    if (nut.ni() != b.ni || nut.nj() != b.nj || nut.nk() != b.nk) {
      nut.resize(b.ni, b.nj, b.nk, 0, 0.0);
      ywall.resize(b.ni, b.nj, b.nk, 0, 0.0);
    }
    nut.fill(0.0);
    ywall.fill(std::numeric_limits<Real>::infinity());
    for (const Patch& p : b.patches) {
      if (p.type != BcType::Wall) continue;
      const int d = side_dir(p.side);
      for_each_in(face_range(p), [&](Index3 c) {
        Vec3 n;
        const Real d1 = wall_distance(b, p.side, c, &n);
        const Index3 fw = boundary_face_index(b, p.side, c);
        const Vec3 xw = b.xf[d](fw), uw = wall_velocity(b, p, fw);
        const Index3 c1 = interior_cell(b, p.side, c, 1);
        const Vec3 ut1 = Q(c1).tail<3>() - uw - n.dot(Q(c1).tail<3>() - uw) * n;
        const Real utau = std::sqrt(nu * ut1.norm() / d1);
        // The line: cells at depth 1 .. n(d) from this wall.
        const int len = b.n(d);
        y_.resize(static_cast<std::size_t>(len));
        omega_.resize(static_cast<std::size_t>(len));
        f_.resize(static_cast<std::size_t>(len));
        auto& y = y_;
        auto& om = omega_;
        auto& F = f_;
        Real fmax = 0.0, ymax = 0.0, fpeak = 0.0, udif = 0.0;
        int mpeak = -1;
        bool past_peak = false;
        for (int m = 0; m < len; ++m) {
          const Index3 cm = interior_cell(b, p.side, c, m + 1);
          y[m] = n.dot(b.xc(cm) - xw);
          om[m] = vorticity_magnitude(velocity_gradient(b, Q, cm));
          udif = std::max(udif, (Q(cm).tail<3>() - uw).norm());
          const Real damp = 1.0 - std::exp(-fp.reynolds * utau * y[m] / aplus);
          F[m] = y[m] * om[m] * damp;
          if (!past_peak) {
            if (F[m] > fpeak) {
              fpeak = F[m];
              fmax = F[m];
              ymax = y[m];
              mpeak = m;
            } else if (settings_.degani_schiff && F[m] < 0.9 * fpeak) {
              past_peak = true;  // Degani-Schiff: the first peak
            }
          }
        }
        // §8.2's F_max is the maximum of F(y), not of its cell values: the cells'
        // maximum jumps by a cell as the peak moves, nu_t jumps with it, and the
        // discrete equations then had several solutions (which one a run found
        // depended on its path: turbulence/DESIGN.md).
        if (mpeak > 0 && mpeak + 1 < len) {
          const FunctionPeak peak = refined_peak(&y[mpeak - 1], &F[mpeak - 1]);
          ymax = peak.y;
          fmax = peak.f;
        }
        const Real fwake = fmax > 0.0 ? std::min(ymax * fmax, cwk * ymax * udif * udif / fmax) : 0.0;
        bool outer = false;
        for (int m = 0; m < len; ++m) {
          const Index3 cm = interior_cell(b, p.side, c, m + 1);
          if (y[m] >= ywall(cm)) continue;  // a nearer wall owns this cell
          const Real l = kappa * y[m] * (1.0 - std::exp(-fp.reynolds * utau * y[m] / aplus));
          const Real inner = l * l * om[m];
          const Real kl = ymax > 0.0 ? ckleb * y[m] / ymax : 0.0;
          const Real outerv = kclauser * ccp * fwake / (1.0 + 5.5 * std::pow(kl, 6));
          outer = outer || inner >= outerv;
          nut(cm) = outer ? outerv : inner;
          ywall(cm) = y[m];
        }
      });
    }
    for_each_cell(b, [&](int i, int j, int k) {
      const Real target = nu + std::clamp(nut(i, j, k), 0.0, 1.0e6 * nu);
      f.nu[ib](i, j, k) += w * (target - f.nu[ib](i, j, k));
    });
  }
}

TurbulenceNorms BaldwinLomax::advance(Grid& g, FlowField& f, const FlowParams& fp, Real) {
  fill_ghosts(g, f, fp);
  update_viscosity(g, f, fp);
  return {};
}

}  // namespace narwhal
