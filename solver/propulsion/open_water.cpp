#include "propulsion/open_water.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"
#include "io/table_file.hpp"

namespace narwhal {

MonotoneCubic::MonotoneCubic(std::vector<Real> x, std::vector<Real> y) : x_(std::move(x)), y_(std::move(y)) {
  const std::size_t n = x_.size();
  if (n < 2 || y_.size() != n) fail("monotone cubic: needs two or more points with as many values as abscissae");
  for (std::size_t i = 0; i + 1 < n; ++i)
    if (!(x_[i + 1] > x_[i])) fail("monotone cubic: abscissae must increase (x[{}] = {} after {})", i + 1, x_[i + 1], x_[i]);
  std::vector<Real> h(n - 1), d(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    h[i] = x_[i + 1] - x_[i];
    d[i] = (y_[i + 1] - y_[i]) / h[i];
  }
  // Fritsch-Butland's weighted harmonic mean of the neighbouring slopes, zero at an
  // extremum: the interpolant is monotone wherever the data are.
  m_.assign(n, 0.0);
  m_.front() = d.front();
  m_.back() = d.back();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    if (d[i - 1] * d[i] <= 0.0) continue;
    m_[i] = 3.0 * (h[i - 1] + h[i]) / ((2.0 * h[i] + h[i - 1]) / d[i - 1] + (h[i] + 2.0 * h[i - 1]) / d[i]);
  }
}

Real MonotoneCubic::operator()(Real x) const {
  if (x <= x_.front()) return y_.front() + m_.front() * (x - x_.front());
  if (x >= x_.back()) return y_.back() + m_.back() * (x - x_.back());
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(x_.begin(), x_.end(), x) - x_.begin()) - 1;
  const Real h = x_[i + 1] - x_[i], t = (x - x_[i]) / h;
  const Real h00 = (1 + 2 * t) * (1 - t) * (1 - t), h10 = t * (1 - t) * (1 - t), h01 = t * t * (3 - 2 * t),
             h11 = t * t * (t - 1);
  return h00 * y_[i] + h10 * h * m_[i] + h01 * y_[i + 1] + h11 * h * m_[i + 1];
}

namespace {

std::vector<Real> kq_column(const Table& t) {
  if (t.has("KQ")) return t.column("KQ");
  if (!t.has("10KQ")) fail("{}: an open-water table needs a column 'KQ' or '10KQ'", t.path());
  std::vector<Real> kq = t.column("10KQ");
  for (Real& v : kq) v /= 10.0;
  return kq;
}

}  // namespace

OpenWaterTable::OpenWaterTable(const Table& t)
    : kt_(t.column("J"), t.column("KT")),
      kq_(t.column("J"), kq_column(t)),
      description_(fmt::format("open-water table {} ({} points, J {:g} to {:g})", t.path(), t.rows(),
                               t.column("J").front(), t.column("J").back())) {}

WageningenB::WageningenB(const Table& coefficients, Real pitch_ratio, Real area_ratio, int blades)
    : pitch_ratio_(pitch_ratio), area_ratio_(area_ratio), blades_(blades) {
  if (blades < 2 || blades > 7) fail("Wageningen B-series: {} blades, the series has 2 to 7", blades);
  if (!(area_ratio >= 0.30 && area_ratio <= 1.05))
    fail("Wageningen B-series: blade-area ratio Ae/A0 = {}, the series spans 0.30 to 1.05", area_ratio);
  if (!(pitch_ratio >= 0.5 && pitch_ratio <= 1.4))
    fail("Wageningen B-series: pitch ratio P/D = {}, the series spans 0.5 to 1.4", pitch_ratio);
  const auto& name = coefficients.text("polynomial");
  const auto& c = coefficients.column("C");
  const auto& s = coefficients.column("s_exp_J");
  const auto& t = coefficients.column("t_exp_PD");
  const auto& u = coefficients.column("u_exp_AEAO");
  const auto& v = coefficients.column("v_exp_Z");
  for (std::size_t r = 0; r < coefficients.rows(); ++r) {
    if (name[r] != "KT" && name[r] != "KQ") continue;  // the Reynolds-number corrections
    const Term term{c[r] * std::pow(pitch_ratio, t[r]) * std::pow(area_ratio, u[r]) *
                        std::pow(static_cast<Real>(blades), v[r]),
                    static_cast<int>(s[r])};
    (name[r] == "KT" ? kt_ : kq_).push_back(term);
  }
  if (kt_.empty() || kq_.empty())
    fail("{}: no rows of polynomials 'KT' and 'KQ' in column 'polynomial'", coefficients.path());
}

Real WageningenB::sum(const std::vector<Term>& terms, Real J) {
  Real k = 0.0;
  for (const Term& term : terms) k += term.c * std::pow(J, term.s);
  return k;
}

std::string WageningenB::describe() const {
  return fmt::format("Wageningen B{}-{:.0f}, P/D {:g} (Rn = 2e6)", blades_, 100.0 * area_ratio_, pitch_ratio_);
}

}  // namespace narwhal
