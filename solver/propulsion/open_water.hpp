#pragma once
// A propeller's open-water curves K_T(J) and K_Q(J) (NUMERICS §9.1): from a table of
// measured points, or from the Wageningen B-series regression for a stated pitch ratio,
// blade-area ratio and blade count.
#include <memory>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace narwhal {

class Table;

class OpenWaterCurve {
 public:
  virtual ~OpenWaterCurve() = default;
  virtual Real kt(Real J) const = 0;
  virtual Real kq(Real J) const = 0;
  // Where the curve comes from, for the run's report.
  virtual std::string describe() const = 0;
};

// Monotone piecewise-cubic interpolation (Fritsch-Carlson tangents: no overshoot between
// measured points, which a plain spline gives near a curve's steep end), extended
// linearly beyond the table with its end tangents. x strictly increasing.
class MonotoneCubic {
 public:
  MonotoneCubic(std::vector<Real> x, std::vector<Real> y);
  Real operator()(Real x) const;

 private:
  std::vector<Real> x_, y_, m_;
};

// A table's K_T and K_Q against J. The K_Q column is "KQ", or "10KQ" (tabulated ten
// times over, as open-water data often are).
class OpenWaterTable final : public OpenWaterCurve {
 public:
  explicit OpenWaterTable(const Table& t);
  Real kt(Real J) const override { return kt_(J); }
  Real kq(Real J) const override { return kq_(J); }
  std::string describe() const override { return description_; }

 private:
  MonotoneCubic kt_, kq_;
  std::string description_;
};

// The Wageningen B-series polynomials at Rn = 2e6 (Oosterveld & van Oossanen 1975):
// K = sum_i C_i J^s (P/D)^t (Ae/A0)^u Z^v, from the coefficient table's rows of
// polynomials "KT" and "KQ" (columns polynomial, C, s_exp_J, t_exp_PD, u_exp_AEAO,
// v_exp_Z). The Reynolds-number corrections are not applied: K_T and K_Q are the
// series' at Rn = 2e6.
class WageningenB final : public OpenWaterCurve {
 public:
  // An Error names the parameter outside the series' range (2 <= Z <= 7,
  // 0.30 <= Ae/A0 <= 1.05, 0.5 <= P/D <= 1.4).
  WageningenB(const Table& coefficients, Real pitch_ratio, Real area_ratio, int blades);
  Real kt(Real J) const override { return sum(kt_, J); }
  Real kq(Real J) const override { return sum(kq_, J); }
  std::string describe() const override;

 private:
  struct Term {
    Real c;  // the coefficient times (P/D)^t (Ae/A0)^u Z^v
    int s;   // the power of J
  };
  static Real sum(const std::vector<Term>& terms, Real J);
  std::vector<Term> kt_, kq_;
  Real pitch_ratio_, area_ratio_;
  int blades_;
};

}  // namespace narwhal
