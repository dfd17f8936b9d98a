#pragma once
// The DARPA SUBOFF model (DTRC models 5470/5471) as equations: the hull, the fairwater
// (sail), the four stern appendages, and a pair of sail planes of our own (SUBOFF has
// none). Groves, Huang & Chang (1989), DTRC/SHD-1298-01, transcribed in
// reference_data/suboff/suboff_geometry.md (§ numbers below are that file's).
//
// Model feet. The SUBOFF frame: x aft of the nose, y up, z to port (right-handed); the
// hull axis is the x axis. Grids put the nose towards -x with z down (motion/grid_axes.hpp):
// grid (x, y, z) = SUBOFF (x, z, -y), see to_grid_axes.
//
// An appendage is described in its own plane: the span coordinate s is the distance
// from the hull axis along the appendage (for the sail planes: from the sail's centre
// plane), and the offset n is normal to that plane. Its surface is n = +-t(x, s) over the
// planform bounded by the leading edge x_le(s), the trailing edge x_te(s), the root (the
// hull or the sail) and the tip s_tip(x), where t falls to zero: a grid can then close
// the tip on a block boundary (mesh/DESIGN.md).
#include <memory>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace narwhal::suboff {

inline constexpr Real kOverallLength = 14.291667;  // §1, L_OA
inline constexpr Real kMaxRadius = 5.0 / 6.0;       // §1
// Roddy (1990), Table 1: the captive-model data's length (L_BP) and moment centre
// (reference_data/suboff/suboff_roddy1990_model_parameters.csv).
inline constexpr Real kRoddyLength = 13.9792;
inline constexpr Real kRoddyMomentCentre = 6.6042;  // aft of the nose

// §2: the hull radius at x (zero outside [0, L_OA]).
Real hull_radius(Real x);

// SUBOFF frame -> grid axes (x aft, y port, z down), and back.
inline Vec3 to_grid_axes(const Vec3& p) { return {p[0], p[2], -p[1]}; }
inline Vec3 from_grid_axes(const Vec3& g) { return {g[0], -g[2], g[1]}; }

class Appendage {
 public:
  virtual ~Appendage() = default;
  const std::string& name() const { return name_; }

  virtual Real leading_edge(Real s) const = 0;
  virtual Real trailing_edge(Real s) const = 0;
  // The planform's outer edge at x: where the half-thickness reaches zero.
  virtual Real tip(Real x) const = 0;
  // The half-thickness t(x, s) >= 0, zero off the planform.
  virtual Real half_thickness(Real x, Real s) const = 0;
  // Where the root meets what the appendage stands on, as a span coordinate at x
  // (the hull: s = R(x); the sail planes: the sail's side).
  virtual Real root(Real x) const = 0;

  // Mounting: the span and offset directions and the origin of s = 0, in the SUBOFF
  // frame. A positive deflection moves the trailing edge towards +offset.
  Vec3 origin = Vec3::Zero();
  Vec3 span_direction = Vec3::UnitY();
  Vec3 offset_direction = Vec3::UnitZ();
  // The stock: the axis (parallel to span_direction, at x = stock_x in the plane) a
  // control surface turns about; deflection in radians. The sail does not turn.
  bool movable = false;
  Real stock_x = 0.0;
  Real deflection = 0.0;
  bool is_deflected() const { return movable && deflection != 0.0; }

  // The surface point at (x, s) on the side `side` (+1: towards +offset, -1: away),
  // the deflection applied, in the SUBOFF frame.
  Vec3 surface_point(Real x, Real s, int side) const;
  // The same point of the plane (offset n) turned about the stock.
  Vec3 deflected(Real x, Real s, Real n) const { return turned(x, s, n, deflection); }
  // The point (x, s, n) of the plane turned about the stock by `angle` (radians, the
  // deflection's sign; a fixed appendage does not turn): a grid deformed about a
  // deflected surface turns its nodes by fractions of the deflection.
  Vec3 turned(Real x, Real s, Real n, Real angle) const;
  // A point's coordinates in the undeflected plane: {x, s, n}.
  Vec3 plane_coordinates(const Vec3& p) const {
    const Vec3 d = p - origin;
    return {p[0], d.dot(span_direction), d.dot(offset_direction)};
  }

 protected:
  explicit Appendage(std::string name) : name_(std::move(name)) {}

 private:
  std::string name_;
};

// §3: the fairwater on top dead centre, closed by its elliptic cap.
class Sail final : public Appendage {
 public:
  Sail() : Appendage("sail") {}
  static constexpr Real kLeadingEdge = 3.032986, kTrailingEdge = 4.241319;
  static constexpr Real kUniformTop = 1.507813, kMaxHalfThickness = 0.109375;
  // Z1(x): the half-thickness of the uniform section.
  static Real section_half_thickness(Real x);
  Real leading_edge(Real) const override { return kLeadingEdge; }
  Real trailing_edge(Real) const override { return kTrailingEdge; }
  Real tip(Real x) const override;
  Real half_thickness(Real x, Real s) const override;
  Real root(Real x) const override { return hull_radius(x); }
};

// A fin of the stern appendages' family (§4): the DTRC section z/c (a NACA-0020-type
// thickness, scaled by thickness_ratio / 0.2), a chord linear in span with a straight
// trailing edge at x = trailing_edge_x, ending flat at s = tip_span (Appendix C).
class Fin : public Appendage {
 public:
  struct Shape {
    Real trailing_edge_x = 13.146284;  // §4 baseline position
    Real chord_at_zero = 0.88859;      // c(s) = chord_at_zero + chord_slope s
    Real chord_slope = -0.466308;
    Real tip_span = kMaxRadius;
    Real thickness_ratio = 0.20;
    bool on_sail = false;              // the root on the sail's side (sail planes), else on the hull
  };
  Fin(std::string name, const Shape& shape);
  const Shape& shape() const { return shape_; }

  Real chord(Real s) const { return shape_.chord_at_zero + shape_.chord_slope * s; }
  // §4: z/c at the chord fraction xi = (x - x_te)/c + 1 (0 at the leading edge).
  static Real section(Real xi);
  Real chord_fraction(Real x, Real s) const { return (x - shape_.trailing_edge_x) / chord(s) + 1.0; }
  Real leading_edge(Real s) const override { return shape_.trailing_edge_x - chord(s); }
  Real trailing_edge(Real) const override { return shape_.trailing_edge_x; }
  Real tip(Real) const override { return shape_.tip_span; }
  Real half_thickness(Real x, Real s) const override;
  Real root(Real x) const override;

 private:
  Shape shape_;
};

// The four stern appendages at the baseline position, and the representative sail
// planes (their definition and its reasons: mesh/DESIGN.md). Sign conventions of the
// deflections (Gertler & Hagen): a positive rudder angle moves the trailing edges to
// port, a positive stern- or sail-plane angle moves them down.
enum class SternAppendage { UpperRudder, LowerRudder, StarboardPlane, PortPlane };
std::unique_ptr<Fin> make_stern_appendage(SternAppendage which, Real deflection = 0.0);
std::unique_ptr<Fin> make_sail_plane(bool starboard, Real deflection = 0.0);
// The sail planes' definition (in the SUBOFF frame, feet).
struct SailPlaneDesign {
  static constexpr Real kHeight = 1.20;           // span axis at y = 1.20 ft (55 % of the sail's uniform span)
  static constexpr Real kTrailingEdge = 3.62;     // straight trailing edge, x aft of the nose
  static constexpr Real kRootChord = 0.40;        // at the sail's centre plane
  static constexpr Real kTipChord = 0.28;
  static constexpr Real kTipSpan = 0.42;          // from the sail's centre plane (0.31 ft outside the sail)
  static constexpr Real kThicknessRatio = 0.15;
};

// Configurations by name (the issue's): bare, sail, stern4, sail_stern4 (AFF-8), full.
struct Configuration {
  std::string name;
  std::vector<std::unique_ptr<Appendage>> appendages;
};
struct Deflections {
  Real rudder = 0.0, stern_planes = 0.0, sail_planes = 0.0;  // radians
  bool operator==(const Deflections&) const = default;
};
Configuration make_configuration(const std::string& name, const Deflections& deflections = {});
// The valid names, for messages.
const std::vector<std::string>& configuration_names();

}  // namespace narwhal::suboff
