#pragma once
// A zig-zag manoeuvre (the ITTC Z-test; issue 19's horizontal zig-zag with the rudders and
// vertical one with the stern planes, 10/10): from `start` the surface goes to
// first x angle; whenever the attitude it drives (heading for the rudders, pitch for the
// stern planes, both from release) has moved `switch_at` in the direction the present
// deflection drives it, the surface is reversed. The surface turns at `rate` at most, as
// the steering gear does.
//
// Signs are suboff_geometry.hpp's (Gertler & Hagen): a rudder > 0 turns the nose to port
// (heading falls), stern planes > 0 put the nose down (pitch falls); so a deflection of
// sign s drives its attitude towards -s, and the surface reverses once -s x attitude
// reaches switch_at.
#include <vector>

#include "control/vehicle_reading.hpp"
#include "mesh/suboff_geometry.hpp"

namespace narwhal {

struct ZigzagSettings {
  enum class Surface { Rudder, SternPlanes };
  Surface surface = Surface::Rudder;
  Real angle = 0.0;      // the deflection, rad (> 0)
  Real switch_at = 0.0;  // the attitude change that reverses it, rad (> 0)
  Real start = 0.0;      // when the first deflection begins
  Real rate = 0.0;       // the surface's largest rate, rad per unit time (0: at once)
  int first = 1;         // the first deflection's sign
};

class Zigzag {
 public:
  // Throws Error unless angle, switch_at > 0, rate >= 0 and first is +1 or -1.
  explicit Zigzag(ZigzagSettings s);

  // The surfaces' angles for the step that ends at t_next (length dt) and begins with the
  // vehicle at `now`; `present`: their angles now (the other surfaces' are kept).
  suboff::Deflections command(Real t_next, Real dt, const VehicleReading& now, const suboff::Deflections& present);

  int sign() const { return sign_; }  // of the deflection commanded (0 before the start)
  int reversals() const { return reversals_; }

  std::vector<Real> checkpoint() const { return {static_cast<Real>(sign_), static_cast<Real>(reversals_)}; }
  void restore(const std::vector<Real>& values);  // throws Error on a list of another length

 private:
  ZigzagSettings s_;
  int sign_ = 0;
  int reversals_ = 0;
};

}  // namespace narwhal
