#include "mesh/suboff_geometry.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "core/error.hpp"

namespace narwhal::suboff {

// §2. The cap is written so that it closes exactly at the overall length (the printed
// 3.2 x - 44.733333 leaves -2.8e-6 at the tip).
Real hull_radius(Real x) {
  constexpr Real bow_end = 3.333333, after_start = 10.645833, aft_perpendicular = 13.979167;
  if (x <= 0.0 || x >= kOverallLength) return 0.0;
  if (x <= bow_end) {
    const Real a = 0.3 * x - 1.0, a3 = a * a * a, a4 = a3 * a;
    const Real bracket = 1.126395101 * x * a4 + 0.442874707 * x * x * a3 + 1.0 - a4 * (1.2 * x + 1.0);
    return kMaxRadius * std::pow(std::max(0.0, bracket), 1.0 / 2.1);
  }
  if (x <= after_start) return kMaxRadius;
  if (x <= aft_perpendicular) {
    constexpr Real rh = 0.1175, k0 = 10.0, k1 = 44.6244;
    const Real xi = (aft_perpendicular - x) / 3.333333;
    const Real xi2 = xi * xi, xi3 = xi2 * xi, xi4 = xi3 * xi, xi5 = xi4 * xi, xi6 = xi5 * xi;
    const Real bracket = rh * rh + rh * k0 * xi2 + (20.0 - 20.0 * rh * rh - 4.0 * rh * k0 - k1 / 3.0) * xi3 +
                         (-45.0 + 45.0 * rh * rh + 6.0 * rh * k0 + k1) * xi4 +
                         (36.0 - 36.0 * rh * rh - 4.0 * rh * k0 - k1) * xi5 +
                         (-10.0 + 10.0 * rh * rh + rh * k0 + k1 / 3.0) * xi6;
    return kMaxRadius * std::sqrt(std::max(0.0, bracket));
  }
  const Real u = (x - aft_perpendicular) / (kOverallLength - aft_perpendicular);
  return 0.1175 * kMaxRadius * std::sqrt(std::max(0.0, 1.0 - u * u));
}

Vec3 Appendage::turned(Real x, Real s, Real n, Real angle) const {
  const Real c = std::cos(angle), sn = std::sin(angle);
  const Real dx = x - stock_x;
  const Real x_turned = movable ? stock_x + dx * c - n * sn : x;
  const Real n_turned = movable ? dx * sn + n * c : n;
  return origin + x_turned * Vec3::UnitX() + s * span_direction + n_turned * offset_direction;
}

Vec3 Appendage::surface_point(Real x, Real s, int side) const {
  return deflected(x, s, (side > 0 ? 1.0 : -1.0) * half_thickness(x, s));
}

// ---- §3: the sail ----

Real Sail::section_half_thickness(Real x) {
  constexpr Real fore_end = 3.358507, parallel_end = 3.559028;
  if (x <= kLeadingEdge || x >= kTrailingEdge) return 0.0;
  if (x <= fore_end) {
    const Real d = 3.072000 * (x - kLeadingEdge), dm = d - 1.0, dm3 = dm * dm * dm, dm4 = dm3 * dm;
    const Real a = 2.0 * d * dm4, b = d * d * dm3 / 3.0, c = 1.0 - dm4 * (4.0 * d + 1.0);
    return kMaxHalfThickness * std::sqrt(std::max(0.0, 2.094759 * a + 0.2071781 * b + c));
  }
  if (x <= parallel_end) return kMaxHalfThickness;
  // The afterbody has no square root (the report's equation and its listing agree).
  const Real e = (kTrailingEdge - x) / 0.6822917, em = e - 1.0, em3 = em * em * em, em4 = em3 * em;
  return kMaxHalfThickness * (2.238361 * e * em4 + 3.106529 * e * e * em3 + 1.0 - em4 * (4.0 * e + 1.0));
}

// The cap's crest: its cross-section is a half-ellipse of semi-axes Z1 (across) and Z1/2 (up).
Real Sail::tip(Real x) const { return kUniformTop + 0.5 * section_half_thickness(x); }

Real Sail::half_thickness(Real x, Real s) const {
  const Real z1 = section_half_thickness(x);
  if (s <= kUniformTop) return z1;
  const Real up = 2.0 * (s - kUniformTop);
  return std::sqrt(std::max(0.0, z1 * z1 - up * up));
}

// ---- §4: the fins ----

Fin::Fin(std::string name, const Shape& shape) : Appendage(std::move(name)), shape_(shape) {
  if (!(chord(shape.tip_span) > 0.0)) fail("fin '{}': the chord vanishes before the tip", this->name());
}

Real Fin::section(Real xi) {
  if (xi <= 0.0 || xi >= 1.0) return 0.0;
  return 0.29690 * std::sqrt(xi) - 0.12600 * xi - 0.35160 * xi * xi + 0.28520 * xi * xi * xi -
         0.10450 * xi * xi * xi * xi;
}

Real Fin::half_thickness(Real x, Real s) const {
  if (s >= shape_.tip_span) return 0.0;
  const Real c = chord(s);
  return c * (shape_.thickness_ratio / 0.20) * section(chord_fraction(x, s));
}

Real Fin::root(Real x) const {
  return shape_.on_sail ? Sail::section_half_thickness(x) : hull_radius(x);
}

namespace {

// 25 % of the mean geometric chord from its leading edge (a balanced all-moving surface).
Real quarter_mean_chord(const Fin::Shape& f, Real root_span) {
  const Real mean_chord = f.chord_at_zero + f.chord_slope * 0.5 * (root_span + f.tip_span);
  return f.trailing_edge_x - 0.75 * mean_chord;
}

}  // namespace

std::unique_ptr<Fin> make_stern_appendage(SternAppendage which, Real deflection) {
  static constexpr const char* names[] = {"upper_rudder", "lower_rudder", "starboard_stern_plane",
                                          "port_stern_plane"};
  auto fin = std::make_unique<Fin>(names[static_cast<int>(which)], Fin::Shape{});
  // Roddy (1990) Table 1: span 0.438 ft from the root chord 0.704 ft to the tip.
  fin->stock_x = quarter_mean_chord(fin->shape(), kMaxRadius - 0.438);
  fin->movable = true;
  fin->deflection = deflection;
  switch (which) {
    case SternAppendage::UpperRudder: fin->span_direction = Vec3::UnitY(); fin->offset_direction = Vec3::UnitZ(); break;
    case SternAppendage::LowerRudder: fin->span_direction = -Vec3::UnitY(); fin->offset_direction = Vec3::UnitZ(); break;
    case SternAppendage::StarboardPlane: fin->span_direction = -Vec3::UnitZ(); fin->offset_direction = -Vec3::UnitY(); break;
    case SternAppendage::PortPlane: fin->span_direction = Vec3::UnitZ(); fin->offset_direction = -Vec3::UnitY(); break;
  }
  return fin;
}

std::unique_ptr<Fin> make_sail_plane(bool starboard, Real deflection) {
  using D = SailPlaneDesign;
  Fin::Shape shape;
  shape.trailing_edge_x = D::kTrailingEdge;
  shape.chord_at_zero = D::kRootChord;
  shape.chord_slope = (D::kTipChord - D::kRootChord) / D::kTipSpan;
  shape.tip_span = D::kTipSpan;
  shape.thickness_ratio = D::kThicknessRatio;
  shape.on_sail = true;
  auto fin = std::make_unique<Fin>(starboard ? "starboard_sail_plane" : "port_sail_plane", shape);
  fin->origin = Vec3(0.0, D::kHeight, 0.0);
  fin->span_direction = starboard ? Vec3(-Vec3::UnitZ()) : Vec3(Vec3::UnitZ());
  fin->offset_direction = -Vec3::UnitY();
  fin->movable = true;
  fin->stock_x = quarter_mean_chord(shape, Sail::kMaxHalfThickness);
  fin->deflection = deflection;
  return fin;
}

const std::vector<std::string>& configuration_names() {
  static const std::vector<std::string> names{"bare", "sail", "stern4", "sail_stern4", "full"};
  return names;
}

Configuration make_configuration(const std::string& name, const Deflections& d) {
  const auto& names = configuration_names();
  if (std::find(names.begin(), names.end(), name) == names.end())
    fail("SUBOFF configuration '{}': expected one of {}", name, fmt::join(names, ", "));
  Configuration c{name, {}};
  const bool sail = name == "sail" || name == "sail_stern4" || name == "full";
  const bool stern = name == "stern4" || name == "sail_stern4" || name == "full";
  if (sail) c.appendages.push_back(std::make_unique<Sail>());
  if (stern) {
    c.appendages.push_back(make_stern_appendage(SternAppendage::UpperRudder, d.rudder));
    c.appendages.push_back(make_stern_appendage(SternAppendage::LowerRudder, d.rudder));
    c.appendages.push_back(make_stern_appendage(SternAppendage::StarboardPlane, d.stern_planes));
    c.appendages.push_back(make_stern_appendage(SternAppendage::PortPlane, d.stern_planes));
  }
  if (name == "full") {
    c.appendages.push_back(make_sail_plane(true, d.sail_planes));
    c.appendages.push_back(make_sail_plane(false, d.sail_planes));
  }
  return c;
}

}  // namespace narwhal::suboff
