#include "app/force_steadiness.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace narwhal {

void ForceSteadiness::observe(const std::map<std::string, ForceCoefficients>& forces) {
  if (!enabled()) return;
  // Once the window is full, the oldest sample's storage takes the newest: no
  // allocation per iteration.
  std::vector<Real> sample;
  if (static_cast<int>(samples_.size()) >= window_) {
    sample = std::move(samples_.front());
    samples_.pop_front();
  }
  sample.clear();
  for (const auto& [name, fc] : forces)
    for (int d = 0; d < 3; ++d) sample.push_back(fc.force[d]);
  samples_.push_back(std::move(sample));
}

Real ForceSteadiness::span() const {
  if (samples_.empty() || static_cast<int>(samples_.size()) < window_) return std::numeric_limits<Real>::infinity();
  const std::vector<Real>& last = samples_.back();
  Real scale = 0.0;
  for (std::size_t g = 0; g + 2 < last.size(); g += 3)
    scale = std::max(scale, std::sqrt(last[g] * last[g] + last[g + 1] * last[g + 1] + last[g + 2] * last[g + 2]));
  Real worst = 0.0;
  for (std::size_t m = 0; m < last.size(); ++m) {
    Real lo = last[m], hi = last[m];
    for (const auto& s : samples_) {
      lo = std::min(lo, s[m]);
      hi = std::max(hi, s[m]);
    }
    worst = std::max(worst, hi - lo);
  }
  if (worst == 0.0) return 0.0;
  return scale > 0.0 ? worst / scale : std::numeric_limits<Real>::infinity();
}

std::vector<Real> ForceSteadiness::state() const {
  std::vector<Real> flat;
  for (const auto& s : samples_) flat.insert(flat.end(), s.begin(), s.end());
  return flat;
}

void ForceSteadiness::restore(const std::vector<Real>& flat, int components_per_sample) {
  samples_.clear();
  if (flat.empty() || components_per_sample <= 0) return;
  if (flat.size() % static_cast<std::size_t>(components_per_sample) != 0)
    fail("force window of {} values does not hold whole samples of {}", flat.size(), components_per_sample);
  for (std::size_t at = 0; at < flat.size(); at += static_cast<std::size_t>(components_per_sample))
    samples_.emplace_back(flat.begin() + static_cast<std::ptrdiff_t>(at),
                          flat.begin() + static_cast<std::ptrdiff_t>(at + components_per_sample));
  while (static_cast<int>(samples_.size()) > window_) samples_.pop_front();
}

}  // namespace narwhal
