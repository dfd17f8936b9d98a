#include "config/case_config.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "config/reader.hpp"
#include "core/error.hpp"
#include "io/cgns_reader.hpp"
#include "mesh/connectivity.hpp"
#include "mesh/grid_quality.hpp"
#include "mesh/plot3d.hpp"
#include "motion/grid_axes.hpp"
#include "multigrid/coarsen.hpp"
#include "parallel/partition.hpp"

namespace narwhal {
namespace {

// Cell counts per direction of generated grids (mesh/block.hpp has the why).
const Range kCellCount = Range::between(1, kMaxCellsPerDirection);
// Sweeps and smoothing passes: beyond these a run would sit for hours on one step.
const Range kSweepCount = Range::between(1, 1000);
const Range kSmoothCount = Range::between(1, 100);
// The splitter cuts at most this many pieces (parallel/partition.hpp).
constexpr int kMaxSplitRanks = 4096;


// A slip wall is the symmetry condition (§5.4) on a body surface: the same ghosts,
// with surface output and forces (pressure only).
PatchBc parse_bc_type(const ConfigReader& r, const std::string& key) {
  const std::string t = r.string(key, "a boundary type");
  static const std::pair<const char*, BcType> types[] = {
      {"wall", BcType::Wall},         {"slip_wall", BcType::Symmetry}, {"farfield", BcType::Farfield},
      {"inflow", BcType::Inflow},     {"outflow", BcType::Outflow},    {"symmetry", BcType::Symmetry},
      {"dirichlet", BcType::Dirichlet}};
  for (const auto& [name, type] : types)
    if (t == name) {
      PatchBc bc;
      bc.type = type;
      bc.body_surface = t == "slip_wall";  // walls are body surfaces anyway (assign_bc)
      return bc;
    }
  r.error(key, "unknown boundary type '" + t +
                   "'; valid types: wall, slip_wall, farfield, inflow, outflow, symmetry, dirichlet (and [[periodic]] "
                   "pairs)");
}

// The unit free stream from flow.angle_of_attack and flow.drift_angle (degrees), for
// a body whose nose points to -x of the grid (motion/grid_axes.hpp).
Vec3 free_stream_direction(const ConfigReader& r) {
  const Real a = kRadiansPerDegree *
                 r.number_or("flow.angle_of_attack", 0.0, "the angle of attack in degrees", Range::between(-90, 90));
  const Real b =
      kRadiansPerDegree * r.number_or("flow.drift_angle", 0.0, "the drift angle in degrees", Range::between(-90, 90));
  return free_stream_in_grid_axes(a, b);
}

// The wall spacing for a target y+ of the first cell centre (half the spacing), from the
// flat-plate friction at the Reynolds number of `length`: the estimate the quality report
// uses for its y+.
Real spacing_for_y_plus(const ConfigReader& r, const std::string& key, Real length) {
  const Real y_plus = r.number(key, "the target y+ of the wall cells' centres", Range::between(0.01, 300));
  const Real re = r.number("flow.reynolds", "Re = U L / nu", Range::positive());
  const Real friction_velocity = std::sqrt(0.5 * flat_plate_friction_estimate(re * length));
  return 2.0 * y_plus / (re * friction_velocity);
}

// [grid] of type appended_suboff (mesh/appended_suboff.hpp). Cell counts are per stretch;
// the first spacings follow y+ targets (hull: the hull's Reynolds number; appendages: their
// own, on the stern appendages' mean chord) unless given as lengths.
void read_appended_suboff_grid(const ConfigReader& r, AppendedSuboffSpec& a) {
  const std::vector<std::string> meshed = appended_suboff_configurations();
  const std::string expected = fmt::format("one of {}", fmt::join(meshed, ", "));
  a.configuration = r.string_or("grid.configuration", a.configuration, "the appendages: " + expected);
  if (std::find(meshed.begin(), meshed.end(), a.configuration) == meshed.end())
    r.error("grid.configuration", "expected " + expected + ", got '" + a.configuration + "'");
  a.length = r.number_or("grid.length", a.length, "the overall length", Range::positive());
  struct Count {
    const char* key;
    int* value;
    const char* what;
  };
  const Count counts[] = {{"cells_bow", &a.cells_bow, "cells from the nose square to the sail's leading edge"},
                          {"cells_sail", &a.cells_sail, "cells along the sail's chord"},
                          {"cells_middle", &a.cells_middle, "cells from the sail to the stern appendages"},
                          {"cells_fin", &a.cells_fin, "cells along the stern appendages' chord"},
                          {"cells_stern", &a.cells_stern, "cells from the stern appendages to the tail square"},
                          {"cells_around", &a.cells_around, "cells per 90-degree sector (even)"},
                          {"cells_span", &a.cells_span, "cells from the hull to the appendages' tip level"},
                          {"cells_outer", &a.cells_outer, "cells from the tip level to the far field"},
                          {"box_half_width", &a.box_half_width, "sector cells either side of an appendage's plane in its box"},
                          {"cells_margin", &a.cells_margin, "cells of an appendage's box ahead of and behind its chord"},
                          {"cells_section", &a.cells_section, "cells from an appendage's section to its box"}};
  for (const Count& c : counts)
    *c.value = r.integer_or(std::string("grid.") + c.key, *c.value, c.what, Range::between(2, kMaxCellsPerDirection));
  if (a.cells_around % 2 != 0)
    r.error("grid.cells_around", fmt::format("expected an even count, got {}", a.cells_around));
  a.far_field = r.number_or("grid.far_field", a.far_field, "the far-field distance in overall lengths", Range::at_least(1.0));
  // Each wall spacing is a length or a y+ target, on the Reynolds number of its wall: the
  // hull's overall length, or the stern appendages' mean chord for the appendages' sides
  // and their tip faces (the tip level is a wall as their sides are).
  const Real fin_chord = 0.6 / suboff::kOverallLength * a.length;
  struct WallSpacing {
    const char* key;
    Real* value;
    const char* what;
    Real reynolds_length;
    Real largest;  // in overall lengths
  };
  const WallSpacing wall_spacings[] = {
      {"first_spacing", &a.first_spacing, "the first spacing off the hull", a.length, 0.01},
      {"fin_spacing", &a.fin_spacing, "the first spacing off the appendages", fin_chord, 0.01},
      {"tip_spacing", &a.tip_spacing, "the spacing along the wall lines at the tip level", fin_chord, 0.05}};
  for (const WallSpacing& w : wall_spacings) {
    const std::string key = std::string("grid.") + w.key, key_yplus = key + "_yplus";
    if (r.has(key_yplus) && r.has(key))
      r.error(key_yplus, fmt::format("give either {} or {}, not both", key, key_yplus));
    *w.value = r.has(key_yplus) ? spacing_for_y_plus(r, key_yplus, w.reynolds_length)
                                : r.number_or(key, *w.value, w.what, Range::between(0.0, w.largest * a.length));
  }
  struct Length {
    const char* key;
    Real* value;
    const char* what;
    Real largest;  // in overall lengths
  };
  const Length lengths[] = {
      {"leading_edge_spacing", &a.leading_edge_spacing, "the stations' spacing at the appendages' leading edges", 0.01},
      {"trailing_edge_spacing", &a.trailing_edge_spacing, "the stations' spacing at the appendages' trailing edges",
       0.01},
      {"pole_spacing", &a.pole_spacing, "the meridional spacing at nose and tail", 0.01},
      {"section_layer", &a.section_layer, "how far the appendages' O-grid lines leave along the section's normal", 0.05},
      {"section_edge_spacing", &a.section_edge_spacing, "the spacing along the appendages' sections at their edges",
       0.01},
      {"cap_growth", &a.cap_growth, "the height over which the cap blocks widen above the appendages' tips", a.far_field}};
  for (const Length& l : lengths)
    *l.value = r.number_or(std::string("grid.") + l.key, *l.value, l.what, Range::between(0.0, l.largest * a.length));
  // Control surfaces, in degrees with Gertler & Hagen's signs (suboff_geometry.hpp): a
  // positive rudder angle moves the trailing edges to port, a positive stern-plane angle down.
  // Each is refused by name where the configuration has no such surface.
  const suboff::Configuration geometry = suboff::make_configuration(a.configuration);
  auto has = [&](const std::string& appendage) {
    return std::any_of(geometry.appendages.begin(), geometry.appendages.end(),
                       [&](const auto& p) { return p->name() == appendage; });
  };
  struct Deflection {
    const char* key;
    Real* value;
    const char* appendage;
    const char* what;
  };
  const Deflection deflections[] = {
      {"rudder_deflection", &a.deflections.rudder, "upper_rudder", "the rudders' angle in degrees (positive: trailing edges to port)"},
      {"stern_plane_deflection", &a.deflections.stern_planes, "starboard_stern_plane",
       "the stern planes' angle in degrees (positive: trailing edges down)"},
      {"sail_plane_deflection", &a.deflections.sail_planes, "starboard_sail_plane",
       "the sail planes' angle in degrees (positive: trailing edges down)"}};
  for (const Deflection& d : deflections) {
    const std::string key = std::string("grid.") + d.key;
    const Real degrees = r.number_or(key, 0.0, d.what, Range::between(-30.0, 30.0));
    if (degrees != 0.0 && !has(d.appendage))
      r.error(key, fmt::format("configuration '{}' has no {}", a.configuration, d.appendage));
    *d.value = degrees * kRadiansPerDegree;
  }
  // Last: the counts and spacings above (y+ targets included) are the scale-1 member's.
  const Real scale = r.number_or("grid.scale", 1.0,
                                 "the member of the grid family: cell counts times it, wall, edge and pole spacings over it",
                                 Range::between(0.1, 2.0));
  if (scale != 1.0) a = scaled(a, scale);
}

// grid.type = "flat_plate": a plate with a run-up, stretched from its leading edge and wall.
void read_flat_plate_grid(const ConfigReader& r, FlatPlateSpec& p) {
  p.x_runup = r.number_or("grid.runup", p.x_runup, "the run-up length ahead of the plate", Range::positive());
  p.length = r.number_or("grid.length", p.length, "the plate length", Range::positive());
  p.height = r.number_or("grid.height", p.height, "the domain height", Range::positive());
  p.width = r.number_or("grid.width", p.width, "the span of the single cell in z", Range::positive());
  p.n_runup = r.integer_or("grid.cells_runup", p.n_runup, "cells along the run-up", kCellCount);
  p.n_plate = r.integer_or("grid.cells_plate", p.n_plate, "cells along the plate", kCellCount);
  p.n_normal = r.integer_or("grid.cells_normal", p.n_normal, "cells normal to the plate", kCellCount);
  p.dx_le = r.number_or("grid.dx_leading_edge", p.dx_le, "the streamwise spacing at the leading edge", Range::positive());
  p.dx_te = r.number_or("grid.dx_trailing_edge", p.dx_te, "the streamwise spacing at the trailing edge (0: free)", Range::at_least(0));
  p.dy_wall = r.number_or("grid.dy_wall", p.dy_wall, "the first wall-normal spacing", Range::positive());
  // Geometric stretching from a first spacing needs room for that many cells of it.
  auto fits = [&](const char* key, Real ds, Real length, int cells, const char* where) {
    if (ds * cells > length * (1 + 1e-12))
      r.error(key, fmt::format("{} cells starting at {} do not fit in {} ({}): the spacing must be at most {}", cells,
                               ds, where, length, length / cells));
  };
  fits("grid.dx_leading_edge", p.dx_le, p.x_runup, p.n_runup, "the run-up");
  if (p.dx_te > 0.0) {
    if (p.n_plate < 2) r.error("grid.cells_plate", "a trailing-edge spacing needs at least 2 plate cells");
    fits("grid.dx_leading_edge", p.dx_le, 0.5 * p.length, p.n_plate / 2, "the front half of the plate");
    fits("grid.dx_trailing_edge", p.dx_te, 0.5 * p.length, p.n_plate - p.n_plate / 2, "the rear half of the plate");
  } else {
    fits("grid.dx_leading_edge", p.dx_le, p.length, p.n_plate, "the plate");
  }
  fits("grid.dy_wall", p.dy_wall, p.height, p.n_normal, "the height");
}

// grid.type = "box": per direction [start, end, cells], clustered from a first spacing.
void read_box_grid(const ConfigReader& r, GridConfig& g) {
  const char* names[3] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d) {
    const std::string key = std::string("grid.") + names[d];
    const Vec3 spec = r.vec3(key, "[start, end, cells]");
    if (!(spec[2] >= 1 && spec[2] <= kMaxCellsPerDirection && spec[2] == std::floor(spec[2])))
      r.error(key, fmt::format("the cell count (third entry) must be a whole number between 1 and {}, got {}",
                               kMaxCellsPerDirection, spec[2]));
    const int n = static_cast<int>(spec[2]);
    if (!(spec[1] > spec[0])) r.error(key, fmt::format("the end ({}) must lie beyond the start ({})", spec[1], spec[0]));
    const std::string ck = std::string("grid.cluster_") + names[d];
    const std::string cluster =
        r.string_or(ck, "start", "where the first spacing applies: \"start\", \"both\" ends or the \"middle\"");
    if (cluster != "start" && cluster != "both" && cluster != "middle")
      r.error(ck, "expected \"start\", \"both\" or \"middle\", got '" + cluster + "'");
    const bool halves = cluster == "both" || cluster == "middle";
    if (halves && n % 2 != 0) r.error(key, "clustering at both ends or in the middle needs an even cell count");
    // The first cell cannot be longer than the stretch it starts (half of it when both ends are clustered).
    const Real span = (spec[1] - spec[0]) / (halves ? 2 : 1);
    const std::string sk = std::string("grid.first_spacing_") + names[d];
    const Real ds = r.number_or(sk, 0.0, "the first spacing from the start (0: uniform)", Range::between(0.0, span));
    if (ds <= 0.0)
      g.box_nodes[d] = uniform_nodes(spec[0], spec[1], n);
    else if (cluster == "both")
      g.box_nodes[d] = geometric_nodes_both_ends(spec[0], spec[1], n, ds);
    else if (cluster == "middle")
      g.box_nodes[d] = geometric_nodes_from_middle(spec[0], spec[1], n, ds);
    else
      g.box_nodes[d] = geometric_nodes(spec[0], spec[1], n, ds);
  }
}

// grid.type = "body_of_revolution": an O-grid around a sphere, spheroid or SUBOFF hull.
void read_body_of_revolution_grid(const ConfigReader& r, BodyGridSpec& b) {
  const std::string body = r.string("grid.body", "the body: sphere, spheroid or suboff");
  const Real length = r.number_or("grid.length", 1.0, "the body length (sphere: its diameter)", Range::positive());
  if (body == "sphere") {
    b.profile = sphere_profile(length);
  } else if (body == "spheroid") {
    b.profile = spheroid_profile(length, r.number("grid.ratio", "the spheroid's length-to-diameter ratio",
                                                  Range::at_least(1.0)));
  } else if (body == "suboff") {
    b.profile = suboff_profile(length);
  } else {
    r.error("grid.body", "expected \"sphere\", \"spheroid\" or \"suboff\", got '" + body + "'");
  }
  b.cells_along = r.integer_or("grid.cells_along", b.cells_along, "cells along a meridian between the pole squares",
                               kCellCount);
  if (b.cells_along % 2 != 0 || b.cells_along < 2)
    r.error("grid.cells_along", fmt::format("expected an even count >= 2, got {}", b.cells_along));
  b.cells_around = r.integer_or("grid.cells_around", b.cells_around, "cells per 90-degree sector of azimuth",
                                kCellCount);
  b.cells_normal = r.integer_or("grid.cells_normal", b.cells_normal, "cells from the body to the far field",
                                kCellCount);
  b.far_field = r.number_or("grid.far_field", b.far_field, "the far-field distance in body lengths",
                            Range::at_least(1.0));
  if (r.has("grid.first_spacing_yplus")) {
    if (r.has("grid.first_spacing"))
      r.error("grid.first_spacing_yplus", "give either grid.first_spacing or grid.first_spacing_yplus, not both");
    b.first_spacing = spacing_for_y_plus(r, "grid.first_spacing_yplus", length);
  } else {
    b.first_spacing = r.number_or("grid.first_spacing", b.first_spacing, "the first wall-normal spacing",
                                  Range{0.0, b.far_field * length / b.cells_normal, true, false});
  }
  b.pole_spacing = r.number_or("grid.pole_spacing", 0.0,
                               "the meridional spacing at nose and tail (0: a quarter of the mean)",
                               Range::between(0.0, length / b.cells_along));
}

// grid.type = "perturbed_box": the unit box with sinusoidally moved nodes (metric tests).
void read_perturbed_box_grid(const ConfigReader& r, GridConfig& g) {
  g.perturbed_cells = r.integer("grid.cells", "cells per direction of the unit box", Range::between(1, 512));
  // Beyond about a quarter of the box the perturbed cells fold over.
  g.perturbed_amplitude = r.number_or("grid.amplitude", g.perturbed_amplitude, "the sinusoidal perturbation amplitude",
                                      Range::between(-0.2, 0.2));
}

// grid.type = "plot3d" or "cgns": a grid file, and its patches by block, side and range.
void read_grid_file(const ConfigReader& r, GridConfig& g) {
  g.grid_file = r.file_path("grid.file", fmt::format("the {} grid file (relative to the case file)",
                                                      g.type == "cgns" ? "CGNS" : "Plot3D"));
  const std::size_t n = r.array_size("grid.patch");
  for (std::size_t i = 0; i < n; ++i) {
    const std::string pre = fmt::format("grid.patch[{}].", i);
    FilePatch p;
    p.key = fmt::format("grid.patch[{}]", i);
    p.block = r.integer(pre + "block", "the 1-based block number", Range::at_least(1)) - 1;
    const std::string side = r.string(pre + "side", "one of imin, imax, jmin, jmax, kmin, kmax");
    p.side = parse_side(side);
    if (p.side < 0) r.error(pre + "side", "expected one of imin, imax, jmin, jmax, kmin, kmax, got '" + side + "'");
    p.label = r.string(pre + "label", "the patch label used by [bc.<label>]");
    // Optional cell ranges in the two tangential directions (0-based, half-open); default: whole face.
    const int d = side_dir(p.side);
    for (int t = 0; t < 3; ++t) {
      p.lo[t] = 0;
      p.hi[t] = -1;  // resolved against the block size later
    }
    for (int q = 0; q < 2; ++q) {
      const int t = (d + 1 + q) % 3;
      const std::string key = pre + "range_" + "ijk"[t];
      if (r.has(key)) {
        const auto [lo, hi] = r.index_range(key, "a 0-based, half-open cell range [first, last + 1]",
                                            kMaxCellsPerDirection);
        p.lo[t] = lo;
        p.hi[t] = hi;
        p.range_key[t] = key;
      }
    }
    g.file_patches.push_back(p);
  }
}

void read_grid(const ConfigReader& r, GridConfig& g) {
  g.type = r.string("grid.type",
                    "one of flat_plate, box, perturbed_box, body_of_revolution, appended_suboff, plot3d, cgns");
  if (g.type == "flat_plate")
    read_flat_plate_grid(r, g.plate);
  else if (g.type == "box")
    read_box_grid(r, g);
  else if (g.type == "body_of_revolution")
    read_body_of_revolution_grid(r, g.body);
  else if (g.type == "appended_suboff")
    read_appended_suboff_grid(r, g.appended);
  else if (g.type == "perturbed_box")
    read_perturbed_box_grid(r, g);
  else if (g.type == "plot3d" || g.type == "cgns")
    read_grid_file(r, g);
  else
    r.error("grid.type", "unknown grid type '" + g.type +
                             "'; valid: flat_plate, box, perturbed_box, body_of_revolution, appended_suboff, plot3d, cgns");
  if (r.has("grid.split")) {
    const Vec3 s = r.vec3("grid.split", "[parts_i, parts_j, parts_k]", Range::between(1, 64));
    for (int d = 0; d < 3; ++d) {
      if (s[d] != std::floor(s[d])) r.error("grid.split", fmt::format("expected whole numbers, entry {} is {}", d + 1, s[d]));
      g.split[d] = static_cast<int>(s[d]);
    }
  }
  g.split_rotate = r.boolean_or("grid.split_rotate", false, "whether split blocks get rotated index orientations");
  g.coarsen = r.integer_or("grid.coarsen", 0, "how many times every other grid line is removed (nested families)",
                           Range::between(0, 16));
}

// [time] (TimeConfig). Read after [turbulence] and [flow]: what dual time does not carry
// yet is refused here, naming the key.
void read_time(const ConfigReader& r, CaseConfig& c) {
  auto& t = c.time;
  if (!r.has("time")) return;
  const std::string scheme = r.string("time.scheme", "the physical-time scheme: bdf1 or bdf2");
  if (scheme == "bdf1")
    t.scheme = TimeConfig::Scheme::Bdf1;
  else if (scheme == "bdf2")
    t.scheme = TimeConfig::Scheme::Bdf2;
  else
    r.error("time.scheme", "expected \"bdf1\" or \"bdf2\", got '" + scheme + "'");
  t.step = r.number("time.step", "the physical time step in units of L / U", Range::positive());
  t.steps = r.integer("time.steps", "the number of physical time steps", Range::between(1, 1e9));
  t.pseudo_cfl = r.number_or("time.pseudo_cfl", t.pseudo_cfl,
                             "the CFL number of the pseudo-time term inside a step (omit: none)", Range::positive());
  t.subiteration_drop = r.number_or("time.subiteration_drop", t.subiteration_drop,
                                    "the residual drop that ends a step's sub-iterations", Range::open(0, 1));
  t.min_subiterations = r.integer_or("time.min_subiterations", t.min_subiterations,
                                     "the fewest sub-iterations per step", Range::between(1, 1e6));
  t.max_subiterations = r.integer_or("time.max_subiterations", t.max_subiterations,
                                     "the most sub-iterations per step", Range::between(t.min_subiterations, 1e6));
  t.force_change = r.number_or("time.force_change", t.force_change,
                               "the wall forces' change between sub-iterations, relative to their largest "
                               "component, that also ends a step (0: the residual drop alone)",
                               Range::between(0.0, 1.0));
  if (c.bulk_velocity > 0.0)
    r.error("time.scheme", "a flow-rate-controlled body force (flow.bulk_velocity) is for steady runs");
}

// Whether the case's appended configuration has this appendage.
bool has_appendage(const CaseConfig& c, const std::string& appendage) {
  const suboff::Configuration geometry = suboff::make_configuration(c.grid.appended.configuration);
  return std::any_of(geometry.appendages.begin(), geometry.appendages.end(),
                     [&](const auto& a) { return a->name() == appendage; });
}

// [controls.<surface>] (control/control_schedule.hpp): times and angles in degrees,
// piecewise linear. After read_motion: a case that turns its control surfaces without
// moving otherwise gets a stationary prescribed motion, the grid deforming in place.
void read_controls(const ConfigReader& r, CaseConfig& c) {
  struct Surface {
    const char* key;
    std::optional<AngleTable> ControlScheduleSpec::*table;
    const char* appendage;
  };
  const Surface surfaces[] = {{"rudder", &ControlScheduleSpec::rudder, "upper_rudder"},
                              {"stern_planes", &ControlScheduleSpec::stern_planes, "starboard_stern_plane"},
                              {"sail_planes", &ControlScheduleSpec::sail_planes, "starboard_sail_plane"}};
  ControlScheduleSpec spec;
  bool any = false;
  for (const Surface& s : surfaces) {
    const std::string pre = std::string("controls.") + s.key + ".";
    if (!r.has(std::string("controls.") + s.key)) continue;
    any = true;
    if (c.grid.type != "appended_suboff")
      r.error(std::string("controls.") + s.key, "control surfaces turn only on an appended SUBOFF grid "
                                                "(grid.type = \"appended_suboff\")");
    if (!has_appendage(c, s.appendage))
      r.error(std::string("controls.") + s.key,
              fmt::format("configuration '{}' has no {}", c.grid.appended.configuration, s.appendage));
    const std::vector<Real> times = r.number_list(pre + "times", "the schedule's times (increasing)");
    const std::vector<Real> angles =
        r.number_list(pre + "angles", "the angles in degrees at those times", Range::between(-30.0, 30.0));
    if (angles.size() != times.size())
      r.error(pre + "angles", fmt::format("expected one angle per time ({}), got {}", times.size(), angles.size()));
    AngleTable table;
    for (std::size_t i = 0; i < times.size(); ++i) {
      if (i > 0 && !(times[i] > times[i - 1]))
        r.error(pre + "times", fmt::format("the times must increase: entry {} ({}) follows {}", i + 1, times[i],
                                           times[i - 1]));
      table.emplace_back(times[i], angles[i] * kRadiansPerDegree);
    }
    spec.*s.table = table;
  }
  if (!any) return;
  if (!c.time.unsteady()) r.error("controls", "turning control surfaces needs physical time: add a [time] table");
  if (!c.grid_moves()) c.motion = PrescribedMotionSpec{};  // the grid deforms in place
  c.controls = spec;
}

// [autopilot] (control/autopilot.hpp): commands in degrees and body lengths, each loop's
// gains in [autopilot.<loop>], one limit and rate for every surface. After read_controls.
void read_autopilot(const ConfigReader& r, CaseConfig& c) {
  if (!r.has("autopilot")) return;
  if (c.grid.type != "appended_suboff")
    r.error("autopilot", "the autopilots drive an appended SUBOFF's control surfaces (grid.type = \"appended_suboff\")");
  if (!c.time.unsteady()) r.error("autopilot", "the autopilots act in physical time: add a [time] table");
  AutopilotSettings a;
  auto angle = [&](const std::string& key, const std::string& what) -> std::optional<Real> {
    if (!r.has(key)) return std::nullopt;
    return r.number(key, what, Range::between(-180.0, 180.0)) * kRadiansPerDegree;
  };
  a.heading = angle("autopilot.heading", "the heading to hold, degrees from the release's (> 0: to starboard)");
  a.pitch = angle("autopilot.pitch", "the pitch to hold, degrees (> 0: nose up)");
  if (r.has("autopilot.depth_change"))
    a.depth_change = r.number("autopilot.depth_change", "how much deeper to go, body lengths (> 0: down)");
  if (a.depth_change && a.pitch)
    r.error("autopilot.pitch", "a depth change sets the pitch command itself: give one of depth_change and pitch");
  const Real limit = r.number_or("autopilot.surface_limit", 25.0, "every surface's largest angle, degrees",
                                 Range::between(0.0, 30.0)) * kRadiansPerDegree;
  const Real rate = r.number_or("autopilot.surface_rate", 1.0e3, "every surface's largest rate, degrees per unit time",
                                Range::positive()) * kRadiansPerDegree;
  const Real steepest = r.number_or("autopilot.max_pitch", 15.0, "the depth loop's steepest pitch command, degrees",
                                    Range::between(0.0, 45.0)) * kRadiansPerDegree;
  auto loop = [&](const std::string& name, Real largest, Real fastest) {
    const std::string pre = "autopilot." + name + ".";
    PidSettings p;
    p.kp = r.number(pre + "kp", "the proportional gain (>= 0)", Range::at_least(0.0));
    p.ki = r.number_or(pre + "ki", 0.0, "the integral gain (>= 0)", Range::at_least(0.0));
    p.kd = r.number_or(pre + "kd", 0.0, "the derivative gain (>= 0)", Range::at_least(0.0));
    p.min_output = -largest;
    p.max_output = largest;
    p.max_rate = fastest;
    return p;
  };
  struct Need {
    bool active;
    const char* key;
    const char* appendage;
    const char* surface;
  };
  const Need needs[] = {{a.heading.has_value(), "autopilot.heading", "upper_rudder", "rudder"},
                        {a.pitch || a.depth_change, a.pitch ? "autopilot.pitch" : "autopilot.depth_change",
                         "starboard_stern_plane", "stern_planes"},
                        {r.has("autopilot.sail_plane_loop"), "autopilot.sail_plane_loop", "starboard_sail_plane",
                         "sail_planes"}};
  for (const Need& n : needs) {
    if (!n.active) continue;
    if (!has_appendage(c, n.appendage))
      r.error(n.key, fmt::format("configuration '{}' has no {}", c.grid.appended.configuration, n.appendage));
    if (r.has(std::string("controls.") + n.surface))
      r.error(n.key, fmt::format("the {} are scheduled by [controls.{}]: one of the two drives them", n.surface,
                                 n.surface));
  }
  if (a.heading) a.heading_loop = loop("heading_loop", limit, rate);
  if (a.pitch || a.depth_change) a.pitch_loop = loop("pitch_loop", limit, rate);
  if (a.depth_change) {
    const Real unlimited = std::numeric_limits<Real>::infinity();
    a.depth_loop = loop("depth_loop", steepest, unlimited);
    if (r.has("autopilot.sail_plane_loop")) a.sail_plane_loop = loop("sail_plane_loop", limit, rate);
  } else if (r.has("autopilot.sail_plane_loop")) {
    r.error("autopilot.sail_plane_loop", "the sail planes hold depth: give autopilot.depth_change");
  }
  if (!a.heading && !a.pitch && !a.depth_change)
    r.error("autopilot", "no command: give heading, pitch or depth_change");
  if (c.free_body && c.free_body->mass.weight > 0.0 && (c.free_body->mass.down - Vec3::UnitZ()).norm() > 1e-12)
    r.error("motion.gravity", "the autopilots take depth along the grid's +z (z_B down, NUMERICS §0.1): gravity must "
                              "point along +z");
  if (!c.grid_moves()) c.motion = PrescribedMotionSpec{};  // the grid deforms in place
  c.autopilot = a;
}

// [zigzag] (control/zigzag.hpp): a zig-zag manoeuvre of the rudders or the stern planes,
// angles in degrees. After read_autopilot: one controller drives each surface.
void read_zigzag(const ConfigReader& r, CaseConfig& c) {
  if (!r.has("zigzag")) return;
  if (c.grid.type != "appended_suboff")
    r.error("zigzag", "a zig-zag turns an appended SUBOFF's control surfaces (grid.type = \"appended_suboff\")");
  if (!c.time.unsteady()) r.error("zigzag", "a zig-zag happens in physical time: add a [time] table");
  ZigzagSettings z;
  const std::string surface = r.string("zigzag.surface", "the surface: rudder (heading) or stern_planes (pitch)");
  if (surface != "rudder" && surface != "stern_planes")
    r.error("zigzag.surface", "expected \"rudder\" or \"stern_planes\", got '" + surface + "'");
  z.surface = surface == "rudder" ? ZigzagSettings::Surface::Rudder : ZigzagSettings::Surface::SternPlanes;
  if (!has_appendage(c, surface == "rudder" ? "upper_rudder" : "starboard_stern_plane"))
    r.error("zigzag.surface", fmt::format("configuration '{}' has no {}", c.grid.appended.configuration, surface));
  if (r.has("controls." + surface))
    r.error("zigzag.surface", fmt::format("the {0} are scheduled by [controls.{0}]: one of the two drives them", surface));
  const bool piloted = c.autopilot && (surface == "rudder" ? c.autopilot->heading.has_value()
                                                           : (c.autopilot->pitch || c.autopilot->depth_change));
  if (piloted) r.error("zigzag.surface", fmt::format("the {} are driven by [autopilot]: one of the two drives them", surface));
  z.angle = r.number("zigzag.angle", "the deflection, degrees", Range{0.0, 30.0, false, true}) * kRadiansPerDegree;
  z.switch_at = r.number_or("zigzag.switch_at", z.angle / kRadiansPerDegree,
                            "the heading or pitch change that reverses the surface, degrees (the deflection's)",
                            Range{0.0, 90.0, false, true}) * kRadiansPerDegree;
  z.start = r.number_or("zigzag.start", 0.0, "when the first deflection begins", Range::at_least(0.0));
  z.rate = r.number_or("zigzag.rate", 0.0, "the surface's largest rate, degrees per unit time (0: at once)",
                       Range::at_least(0.0)) * kRadiansPerDegree;
  const Real first = r.number_or("zigzag.first", 1.0, "the first deflection's sign, 1 or -1");
  if (first != 1.0 && first != -1.0) r.error("zigzag.first", fmt::format("expected 1 or -1, got {}", first));
  z.first = static_cast<int>(first);
  if (!c.grid_moves()) c.motion = PrescribedMotionSpec{};  // the grid deforms in place
  c.zigzag = z;
}

// The fluid's density and the run's reference length and speed, that turn a free
// body's SI properties into the flow's units (all 1: nondimensional).
struct Scales {
  Real rho = 1.0, length = 1.0, speed = 1.0;
};

// [[motion.ballast]] (motion/ballast.hpp): the water each tank blows out (or takes in),
// whose weight the body loses at the tank, as a step or a ramp. `g`: gravity's magnitude
// in flow units.
void read_ballast(const ConfigReader& r, const Scales& u, Real g, std::vector<BallastChange>& out) {
  const std::size_t n = r.array_size("motion.ballast");
  const bool si = u.rho != 1.0 || u.length != 1.0 || u.speed != 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string pre = fmt::format("motion.ballast[{}].", i);
    BallastChange b;
    const Real water = r.number(pre + "mass", std::string("the mass of water the tank blows out (> 0) or takes in (< 0)") +
                                                  (si ? " in kg" : "")) / (u.rho * std::pow(u.length, 3));
    if (g == 0.0) r.error(pre + "mass", "a change of ballast needs gravity: give motion.gravity");
    b.weight = water * g;
    b.tank = r.vec3(pre + "tank", std::string("the tank's centre relative to O, body axes") + (si ? " in m" : "")) /
             u.length;
    const Real time = u.length / u.speed;
    b.start = r.number_or(pre + "start", 0.0, std::string("when the change begins") + (si ? " in s" : ""),
                          Range::at_least(0.0)) / time;
    b.duration = r.number_or(pre + "duration", 0.0,
                             std::string("the ramp's duration (0: a step)") + (si ? " in s" : ""),
                             Range::at_least(0.0)) / time;
    out.push_back(b);
  }
}

// [motion] type = "free": mass properties, initial state, held degrees of freedom and
// the coupling's settings (motion/coupled_body.hpp). A case in SI units gives the
// fluid's density and the run's reference length and speed, and is converted to the
// flow's units (mass / (rho L^3), inertia / (rho L^5), lengths / L, g L / U^2).
void read_free_body(const ConfigReader& r, CaseConfig& c) {
  FreeBodySpec f;
  const std::string units = r.string_or("motion.units", "nondimensional", "the units of the body's properties");
  Real rho = 1.0, length = 1.0, speed = 1.0;
  if (units == "SI") {
    rho = r.number("motion.fluid_density", "the fluid's density in kg/m^3", Range::positive());
    length = r.number("motion.reference_length", "the run's reference length L in m", Range::positive());
    speed = r.number("motion.reference_speed", "the run's reference speed U in m/s", Range::positive());
  } else if (units != "nondimensional") {
    r.error("motion.units", "expected \"nondimensional\" or \"SI\", got '" + units + "'");
  }
  const std::string unit_mass = units == "SI" ? " in kg" : "", unit_length = units == "SI" ? " in m" : "";
  MassProperties& m = f.mass;
  m.mass = r.number("motion.mass", "the body's mass" + unit_mass, Range::positive()) / (rho * std::pow(length, 3));
  const Real volume = r.number("motion.displaced_volume", "the volume of fluid the body displaces" +
                                   std::string(units == "SI" ? " in m^3" : ""), Range::at_least(0.0)) / std::pow(length, 3);
  const Vec3 moments = r.vec3("motion.inertia", "the moments of inertia about O, body axes (I_x, I_y, I_z)" +
                                  std::string(units == "SI" ? " in kg m^2" : ""), Range::positive());
  const Vec3 products = r.vec3_or("motion.products_of_inertia", Vec3::Zero(), "the products of inertia (I_xy, I_xz, I_yz)");
  const Real inertia_scale = rho * std::pow(length, 5);
  m.inertia_o << moments[0], -products[0], -products[1], -products[0], moments[1], -products[2], -products[1],
      -products[2], moments[2];
  m.inertia_o /= inertia_scale;
  m.r_g = r.vec3_or("motion.centre_of_gravity", Vec3::Zero(), "the centre of gravity relative to O, body axes" + unit_length) / length;
  m.r_b = r.vec3_or("motion.centre_of_buoyancy", Vec3::Zero(), "the centre of buoyancy relative to O, body axes" + unit_length) / length;
  const Vec3 gravity = r.vec3_or("motion.gravity", Vec3::Zero(), "the acceleration of gravity, grid axes" +
                                     std::string(units == "SI" ? " in m/s^2" : "")) * (length / (speed * speed));
  const Real g = gravity.norm();
  if (g > 0.0) m.down = gravity / g;
  m.weight = m.mass * g;
  m.buoyancy = volume * g;  // fluid density 1
  const std::vector<std::string> names{"surge", "sway", "heave", "roll", "pitch", "yaw"};
  const std::vector<std::string> free = r.strings_or("motion.free", names, "the free degrees of freedom (body axes)");
  f.options.free.fill(false);
  for (const std::string& n : free) {
    const auto it = std::find(names.begin(), names.end(), n);
    if (it == names.end())
      r.error("motion.free", "expected some of surge, sway, heave, roll, pitch, yaw; got '" + n + "'");
    f.options.free[it - names.begin()] = true;
  }
  if (r.has("motion.added_mass_estimate")) {
    const std::vector<Real> a = r.numbers("motion.added_mass_estimate",
                                          "the added-mass estimate's diagonal (surge ... yaw, body axes, flow units)", 6,
                                          Range::at_least(0.0));
    for (int d = 0; d < 6; ++d) f.options.added_mass_estimate(d, d) = a[d];
  }
  f.coupling.relaxation = r.number_or("motion.relaxation", f.coupling.relaxation,
                                      "the under-relaxation of the body's state per correction", Range::between(0.01, 1.0));
  f.coupling.tolerance = r.number_or("motion.coupling_tolerance", f.coupling.tolerance,
                                     "the velocity change below which a step's motion has converged", Range::positive());
  f.origin = r.vec3_or("motion.origin", f.origin, "the body origin O in grid coordinates" + unit_length) / length;
  f.velocity = r.vec3_or("motion.velocity", f.velocity, "the initial velocity of O, grid axes") / speed;
  f.angular_velocity = r.vec3_or("motion.angular_velocity", f.angular_velocity,
                                 "the initial angular velocity, grid axes (rad per unit time)") * (length / speed);
  read_ballast(r, units == "SI" ? Scales{rho, length, speed} : Scales{}, g, f.ballast);
  for (const std::string& n : r.strings_or("motion.trim", {}, "the degrees of freedom trimmed at release (heave, pitch)")) {
    if (n == "heave") f.trim.heave = true;
    else if (n == "pitch") f.trim.pitch = true;
    else r.error("motion.trim", "expected some of heave, pitch (trimmed by weights); got '" + n + "'");
  }
  if (f.trim.any() && g == 0.0) r.error("motion.trim", "trimming by weights needs gravity: give motion.gravity");
  try {
    RigidBodyEquations check(f.mass, f.options);  // names an unphysical property
  } catch (const Error& e) {
    r.error("motion.inertia", e.what());
  }
  c.free_body = f;
}

// [motion] (motion/prescribed_motion.hpp, motion/coupled_body.hpp). After read_time: a
// moving grid needs physical time.
void read_motion(const ConfigReader& r, CaseConfig& c) {
  if (!r.has("motion")) return;
  const std::string type = r.string("motion.type", "how the grid moves: prescribed or free");
  if (type != "prescribed" && type != "free")
    r.error("motion.type", "expected \"prescribed\" or \"free\", got '" + type + "'");
  if (!c.time.unsteady()) r.error("motion.type", "a moving grid needs physical time: add a [time] table");
  if (type == "free") return read_free_body(r, c);
  PrescribedMotionSpec m;
  m.pivot = r.vec3_or("motion.pivot", m.pivot, "the point rotations are about, in grid axes");
  m.velocity = r.vec3_or("motion.velocity", m.velocity, "the constant translation velocity");
  const std::size_t n = r.array_size("motion.oscillation");
  for (std::size_t i = 0; i < n; ++i) {
    const std::string pre = fmt::format("motion.oscillation[{}].", i);
    Oscillation o;
    const std::string dof = r.string(pre + "dof", "the degree of freedom: x, y, z, roll, pitch or yaw");
    o.dof = parse_dof(dof);
    if (o.dof < 0) r.error(pre + "dof", "expected x, y, z, roll, pitch or yaw, got '" + dof + "'");
    o.amplitude = r.number(pre + "amplitude", o.dof < 3 ? "the amplitude (length)" : "the amplitude in degrees");
    if (o.dof >= 3) o.amplitude *= kRadiansPerDegree;
    o.angular_frequency = r.number(pre + "angular_frequency", "the angular frequency (rad per unit time)",
                                   Range::at_least(0.0));
    o.phase = r.number_or(pre + "phase", 0.0, "the phase in degrees") * kRadiansPerDegree;
    m.oscillations.push_back(o);
  }
  c.motion = m;
}

// [flow]: the Reynolds number, the scheme's constants, the free stream and the
// initial state, the body force and the propulsor.
void read_flow(const ConfigReader& r, CaseConfig& c) {
  auto& f = c.flow;
  f.reynolds = r.number("flow.reynolds", "Re = U L / nu", Range::positive());
  f.beta = r.number_or("flow.beta", f.beta, "the artificial compressibility beta (5-10)", Range::positive());
  const std::string visc = r.string_or("flow.viscous", "full", "one of full, thin-layer, inviscid");
  if (visc == "full") f.viscous = ViscousForm::Full;
  else if (visc == "thin-layer") f.viscous = ViscousForm::ThinLayer;
  else if (visc == "inviscid") f.viscous = ViscousForm::Inviscid;
  else r.error("flow.viscous", "expected one of full, thin-layer, inviscid, got '" + visc + "'");
  f.muscl.kappa = r.number_or("flow.muscl_kappa", f.muscl.kappa, "the MUSCL kappa", Range::between(-1, 1));
  f.muscl.phi = r.number_or("flow.muscl_phi", f.muscl.phi, "the MUSCL phi (0 first order, 1 higher order)",
                             Range::between(0, 1));
  c.initial[0] = r.number_or("flow.initial_pressure", 0.0, "the initial pressure");
  c.free_stream = free_stream_direction(r);
  c.initial.tail<3>() = r.vec3_or("flow.initial_velocity", c.free_stream, "the initial velocity [u, v, w]");
  c.body_force = r.vec3_or("flow.body_force", Vec3::Zero(), "a constant body force per unit volume [fx, fy, fz]");
  c.bulk_velocity = r.number_or("flow.bulk_velocity", 0.0,
                                "the bulk velocity the body force is adjusted to (periodic ducts; 0: force fixed)",
                                Range::at_least(0));
  if (c.bulk_velocity > 0.0 && c.body_force.norm() == 0.0)
    r.error("flow.bulk_velocity", "needs flow.body_force for the direction and first estimate of the force");
  c.propulsor = read_propulsor(r);
  c.manufactured = r.boolean_or("flow.manufactured_solution", false, "whether to run the §12.2 manufactured solution");
  if (c.manufactured) c.mms.nu = 1.0 / f.reynolds;
}

// [bc.<label>]: one condition per patch label.
void read_boundary_conditions(const ConfigReader& r, CaseConfig& c) {
  for (const std::string& label : r.subtables("bc")) {
    const std::string pre = "bc." + label + ".";
    PatchBc bc = parse_bc_type(r, pre + "type");
    const bool free_stream = bc.type == BcType::Farfield || bc.type == BcType::Inflow;
    if (free_stream && r.has(pre + "velocity") && (r.has("flow.angle_of_attack") || r.has("flow.drift_angle")))
      r.error(pre + "velocity", "flow.angle_of_attack / flow.drift_angle already set the free stream; give one or "
                                "the other");
    bc.velocity = r.vec3_or(pre + "velocity", bc.type == BcType::Wall ? Vec3::Zero() : c.free_stream,
                            "the velocity [u, v, w]");
    bc.pressure = r.number_or(pre + "pressure", 0.0, "the outflow pressure");
    c.bcs[label] = bc;
  }
  // An appended hull's appendages are walls like the hull: each one not given its own
  // [bc.<name>] takes [bc.body]'s, so that one case file serves every configuration.
  if (c.grid.type == "appended_suboff") {
    const auto body = c.bcs.find("body");
    if (body == c.bcs.end()) r.error("bc.body", "an appended_suboff grid needs [bc.body] (its appendages take it too)");
    const PatchBc hull = body->second;
    for (const auto& a : suboff::make_configuration(c.grid.appended.configuration).appendages)
      c.bcs.try_emplace(a->name(), hull);
  }
}

// [[periodic]]: the pairs of patches that are one another's neighbours.
void read_periodic_pairs(const ConfigReader& r, CaseConfig& c) {
  const std::size_t np = r.array_size("periodic");
  for (std::size_t i = 0; i < np; ++i) {
    const std::string pre = fmt::format("periodic[{}].", i);
    PeriodicConfig p;
    p.a = r.string(pre + "a", "the label of the first periodic patch");
    p.b = r.string(pre + "b", "the label of the second periodic patch");
    if (r.has(pre + "translation")) p.translation = r.vec3(pre + "translation", "the translation from b to a");
    p.axis = r.vec3_or(pre + "axis", Vec3::UnitX(), "the rotation axis");
    if (!(p.axis.norm() > 0.0)) r.error(pre + "axis", "the rotation axis must not be the zero vector");
    p.angle_deg = r.number_or(pre + "angle", 0.0, "the rotation angle from b to a in degrees", Range::between(-360, 360));
    c.periodic.push_back(p);
  }
}

// [solver]: convergence, divergence and the Newton-relaxation's CFL and sweeps.
void read_solver(const ConfigReader& r, SolverConfig& s) {
  s.max_iterations = r.integer_or("solver.max_iterations", s.max_iterations, "the iteration limit",
                                  Range::between(0, 1e9));
  s.residual_drop = r.number_or("solver.residual_drop", s.residual_drop, "the residual reduction that ends the run",
                                Range::open(0, 1));
  s.turbulence_drop = r.number_or("solver.turbulence_drop", s.turbulence_drop,
                                  "the turbulence residuals' reduction convergence waits for (0: residual_drop)",
                                  Range::between(0, 1));
  s.divergence_factor = r.number_or("solver.divergence_factor", s.divergence_factor,
                                    "the residual growth that counts as divergence", Range::above(1));
  s.regrowth_factor = r.number_or("solver.regrowth_factor", s.regrowth_factor,
                                  "the growth above its lowest value that counts as divergence", Range::above(1));
  s.retreats = r.integer_or("solver.retreats", s.retreats,
                             "divergences a steady run returns from to its lowest-residual state, the CFL ceiling "
                             "halved each time (0: it stops at the first)",
                             Range::between(0, 100));
  s.stall_window = r.integer_or("solver.stall_window", s.stall_window,
                                "iterations without a fall by stall_factor that end a run as stalled (0: never)",
                                Range::between(0, 1e9));
  s.stall_factor = r.number_or("solver.stall_factor", s.stall_factor,
                               "the fall of the convergence measure that counts as progress", Range::above(1));
  s.force_tolerance = r.number_or("solver.force_tolerance", s.force_tolerance,
                                  "the wall forces' span over force_window iterations, relative, that convergence "
                                  "also waits for (0: residuals alone)",
                                  Range::between(0, 1));
  s.force_window = r.integer_or("solver.force_window", s.force_window,
                                "the iterations over which the wall forces must be steady", Range::between(2, 1e6));
  s.invariant_shortcut = r.boolean_or("solver.invariant_shortcut", s.invariant_shortcut,
                                   "whether one-cell invariant layers (planar slabs, self-periodic layers) skip their cancelling faces");
  s.newton.cfl_start = r.number_or("solver.cfl_start", s.newton.cfl_start, "the initial CFL number", Range::positive());
  s.newton.cfl_max = r.number_or("solver.cfl_max", s.newton.cfl_max, "the largest CFL number",
                                 Range::at_least(s.newton.cfl_start));
  s.newton.cfl_growth = r.number_or("solver.cfl_growth", s.newton.cfl_growth,
                                    "the largest factor the CFL may grow by per iteration (0: no limit)",
                                    Range::at_least(0.0));
  if (s.newton.cfl_growth > 0.0 && s.newton.cfl_growth <= 1.0)
    r.error("solver.cfl_growth", fmt::format("expected 0 (no limit) or a factor > 1, got {}", s.newton.cfl_growth));
  s.newton.sgs_iterations = r.integer_or("solver.sgs_iterations", s.newton.sgs_iterations,
                                         "symmetric Gauss-Seidel iterations per Newton iteration", kSweepCount);
  // A step beyond 1e-2 is no longer a derivative of the flux.
  s.newton.fd_epsilon = r.number_or("solver.fd_epsilon", s.newton.fd_epsilon, "the Jacobian difference step",
                                    Range{0.0, 1e-2, true, false});
}

// [solver] multigrid keys (§7).
void read_multigrid(const ConfigReader& r, MultigridSettings& mg) {
  mg.levels = r.integer_or("solver.multigrid_levels", 1, "the number of multigrid levels (1: single grid)",
                          Range::between(1, 16));
  mg.min_cells = r.integer_or("solver.multigrid_min_cells", mg.min_cells,
                              "the fewest cells a coarse level keeps in any halved direction of a block",
                              Range::between(1, kMaxCellsPerDirection));
  const std::string cyc = r.string_or("solver.multigrid_cycle", "W", "V or W");
  if (cyc != "V" && cyc != "W") r.error("solver.multigrid_cycle", "expected \"V\" or \"W\", got '" + cyc + "'");
  mg.gamma = cyc == "W" ? 2 : 1;
  mg.pre_smooth = r.integer_or("solver.pre_smooth", mg.pre_smooth, "Newton-SGS iterations before restriction",
                              Range::between(0, kSmoothCount.hi));
  mg.post_smooth = r.integer_or("solver.post_smooth", mg.post_smooth, "Newton-SGS iterations after prolongation",
                               Range::between(0, kSmoothCount.hi));
  mg.coarse_smooth = r.integer_or("solver.coarse_smooth", mg.coarse_smooth, "iterations on the coarsest level",
                                 kSmoothCount);
  const std::string pro = r.string_or("solver.prolongation", "trilinear", "trilinear or injection");
  if (pro != "trilinear" && pro != "injection")
    r.error("solver.prolongation", "expected \"trilinear\" or \"injection\", got '" + pro + "'");
  mg.injection = pro == "injection";
  mg.jacobian_interval = r.integer_or("solver.jacobian_interval", mg.jacobian_interval,
                                      "cycles between reassemblies of the block matrices (multigrid)",
                                      Range::between(1, 1e6));
  mg.reuse_jacobian = r.boolean_or("solver.reuse_jacobian", mg.reuse_jacobian,
                                   "whether post-smoothing reuses the pre-smoothing Jacobians");
}

// [turbulence]: the model, its relaxation and its start; what is left open comes from
// the model (with_model_defaults). Read after [flow]: the non-linear model needs the full stress.
void read_turbulence(const ConfigReader& r, CaseConfig& c) {
  auto& t = c.turbulence;
  std::string valid_models;
  for (const auto& m : turbulence_models()) valid_models += (valid_models.empty() ? "" : ", ") + m.name;
  t.model = r.string_or("turbulence.model", t.model, "the turbulence model (" + valid_models + ")");
  if (!find_turbulence_model(t.model)) r.error("turbulence.model", "expected one of " + valid_models + ", got '" + t.model + "'");
  t.smoother = r.string_or("turbulence.smoother", "", "the model's relaxation: lines or points");
  if (!t.smoother.empty() && t.smoother != "lines" && t.smoother != "points")
    r.error("turbulence.smoother", "expected \"lines\" or \"points\", got '" + t.smoother + "'");
  t.coupling = r.string_or("turbulence.coupling", "", "when multigrid updates the model: cycle or smoothing");
  if (!t.coupling.empty() && t.coupling != "cycle" && t.coupling != "smoothing")
    r.error("turbulence.coupling", "expected \"cycle\" or \"smoothing\", got '" + t.coupling + "'");
  t.freestream_nut_ratio = r.number_or("turbulence.freestream_nut_ratio", t.freestream_nut_ratio,
                                       "the free-stream eddy-viscosity ratio (SA: nu_tilde/nu)", Range::positive());
  t.intensity = r.number_or("turbulence.intensity", t.intensity, "the free-stream turbulence intensity (a fraction)",
                            Range::between(0, 1));
  if (r.has("turbulence.iterations"))
    t.iterations = r.integer("turbulence.iterations", "model iterations per update", kSmoothCount);
  t.sgs_iterations = r.integer_or("turbulence.sgs_iterations", t.sgs_iterations,
                                  "symmetric Gauss-Seidel pairs per model iteration", kSweepCount);
  t.cfl_max = r.number_or("turbulence.cfl_max", t.cfl_max, "the cap of the model's pseudo-time CFL number",
                          Range::positive());
  t.degani_schiff = r.boolean_or("turbulence.degani_schiff", t.degani_schiff,
                                 "whether Baldwin-Lomax takes F_max at the first peak (Degani-Schiff)");
  if (r.has("turbulence.relaxation"))
    t.relaxation = r.number("turbulence.relaxation", "the under-relaxation of the model's update", Range{0.0, 1.0, true, false});
  auto& st = t.start;
  st.coupling = r.string_or("turbulence.start.coupling", "", "when multigrid updates the model during the start: cycle or smoothing");
  if (!st.coupling.empty() && st.coupling != "cycle" && st.coupling != "smoothing")
    r.error("turbulence.start.coupling", "expected \"cycle\" or \"smoothing\", got '" + st.coupling + "'");
  if (r.has("turbulence.start.relaxation"))
    st.relaxation = r.number("turbulence.start.relaxation", "the under-relaxation of the model's update during the start",
                             Range{0.0, 1.0, true, false});
  if (r.has("turbulence.start.iterations"))
    st.iterations = r.integer("turbulence.start.iterations", "model iterations per update during the start", kSmoothCount);
  if (r.has("turbulence.start.force_span"))
    st.force_span = r.number("turbulence.start.force_span",
                             "the wall forces' relative span over start.window cycles that ends the start (0: no start)",
                             Range::between(0, 1));
  st.window = r.integer_or("turbulence.start.window", st.window, "cycles over which the start's force span is taken",
                           Range::between(1, 1e6));
  t.sustain_freestream = r.boolean_or("turbulence.sustain_freestream", t.sustain_freestream,
                                      "whether the free-stream turbulence is sustained against its decay (Spalart-Rumsey)");
  if (t.sustain_freestream && (t.model == "laminar" || t.model == "baldwin-lomax"))
    r.error("turbulence.sustain_freestream", "a sustained free stream needs a transport model (sa, sst or a k-epsilon), got '" +
                                                 t.model + "'");
  t.omega_wall = r.string_or("turbulence.omega_wall", t.omega_wall,
                             "the wall distance in SST's wall value of omega: cell_height or cell_centre");
  if (t.omega_wall != "cell_height" && t.omega_wall != "cell_centre")
    r.error("turbulence.omega_wall", "expected \"cell_height\" or \"cell_centre\", got '" + t.omega_wall + "'");
  if (r.has("turbulence.omega_wall") && t.model != "sst")
    r.error("turbulence.omega_wall", "sets SST's wall value of omega; the model is '" + t.model + "'");
  t = with_model_defaults(t);  // what was left open, from the model
  t.max_growth = r.number_or("turbulence.max_growth", t.max_growth,
                             "the largest factor by which k, epsilon or omega may grow in one step", Range::above(1));
  t.nonlinear.c1 = r.number_or("turbulence.nonlinear_c1", t.nonlinear.c1, "C1 of the quadratic stress (§8.5)");
  t.nonlinear.c2 = r.number_or("turbulence.nonlinear_c2", t.nonlinear.c2, "C2 of the quadratic stress (§8.5)");
  t.nonlinear.c3 = r.number_or("turbulence.nonlinear_c3", t.nonlinear.c3, "C3 of the quadratic stress (§8.5)");
  if (t.model == "nonlinear-k-epsilon" && c.flow.viscous != ViscousForm::Full)
    r.error("flow.viscous", "the non-linear k-epsilon needs the full viscous stress (\"full\", NUMERICS §4.3)");
}

// [output]: restart files and the force and moment references.
void read_output(const ConfigReader& r, OutputConfig& o) {
  o.restart_interval = r.integer_or("output.restart_interval", o.restart_interval,
                                    "iterations between restart files (0: only at the end)", Range::between(0, 1e9));
  o.reference_area = r.number_or("output.reference_area", o.reference_area, "the force reference area", Range::positive());
  o.reference_length = r.number_or("output.reference_length", o.reference_length, "the moment reference length",
                                    Range::positive());
  o.moment_centre = r.vec3_or("output.moment_centre", o.moment_centre, "the moment reference point");
}

}  // namespace

CaseConfig parse_case(const std::string& text, const std::string& display_name, const std::string& base_dir,
                      const std::vector<std::string>& overrides) {
  ConfigReader r(text, display_name);
  const std::vector<ConfigReader::BaseFile> bases = r.merge_base(base_dir);
  for (const auto& o : overrides) r.apply_override(o);
  CaseConfig c;
  c.file = display_name;
  c.text = text;
  for (const ConfigReader::BaseFile& b : bases)  // the restart keeps every file's text (provenance)
    c.text += "\n# ---- base: " + b.path + " ----\n" + b.text;
  c.title = r.string_or("case.title", "untitled", "a one-line description");
  read_grid(r, c.grid);
  read_flow(r, c);
  read_boundary_conditions(r, c);
  read_periodic_pairs(r, c);
  c.split_for = r.integer_or("parallel.split_for", 0, "the rank count the blocks are cut for (0: the ranks of the run)",
                             Range::between(0, kMaxSplitRanks));
  read_solver(r, c.solver);
  read_multigrid(r, c.solver.multigrid);
  read_turbulence(r, c);
  read_time(r, c);
  read_motion(r, c);
  read_controls(r, c);
  read_autopilot(r, c);
  read_zigzag(r, c);
  if (c.propulsor && c.propulsor->rpm_control && c.time.unsteady())
    r.error("propulsor.rpm_control", "finds a steady self-propulsion point; a dual-time run (time.steps > 0) keeps the "
                                     "rotation rate (start it from the steady run's restart, which carries the rate found)");
  read_output(r, c.output);
  r.reject_unknown_keys();
  return c;
}

Vec3 far_water_velocity(const CaseConfig& c) {
  for (const auto& [label, bc] : c.bcs)
    if (bc.type == BcType::Farfield || bc.type == BcType::Inflow) return bc.velocity;
  return c.free_stream;
}

CaseConfig load_case(const std::string& path, const std::vector<std::string>& overrides) {
  ConfigReader probe(path);  // reads the file and reports syntax errors with the path
  const std::string base = std::filesystem::path(path).parent_path().string();
  CaseConfig c = parse_case(probe.text(), path, base.empty() ? "." : base, overrides);
  for (const auto& o : overrides) c.text += "\n# override: " + o;
  return c;
}

namespace {

Grid generate_grid_from(const CaseConfig& c) {
  Grid g;
  const auto& gc = c.grid;
  if (gc.type == "flat_plate") {
    g = make_flat_plate(gc.plate);
  } else if (gc.type == "box") {
    g.blocks.push_back(make_box("box", gc.box_nodes[0], gc.box_nodes[1], gc.box_nodes[2]));
  } else if (gc.type == "body_of_revolution") {
    g = make_body_of_revolution(gc.body);
  } else if (gc.type == "appended_suboff") {
    try {
      g = make_appended_suboff(gc.appended);
    } catch (const Error& e) {
      fail("{}: [grid]: {}", c.file, e.what());
    }
  } else if (gc.type == "perturbed_box") {
    g.blocks.push_back(make_perturbed_box("box", gc.perturbed_cells, gc.perturbed_amplitude));
  } else if (gc.type == "plot3d" || gc.type == "cgns") {
    try {
      g.blocks = gc.type == "cgns" ? read_cgns_grid(gc.grid_file) : read_plot3d(gc.grid_file);
    } catch (const Error& e) {
      fail("{}: key 'grid.file': {}", c.file, e.what());
    }
    for (FilePatch p : gc.file_patches) {
      if (p.block < 0 || p.block >= static_cast<int>(g.blocks.size()))
        fail("{}: key '{}.block': patch '{}' names block {} but '{}' has {} blocks", c.file, p.key, p.label,
             p.block + 1, gc.grid_file, g.blocks.size());
      Block& b = g.blocks[p.block];
      Patch q;
      q.side = p.side;
      q.label = p.label;
      for (int t = 0; t < 3; ++t) {
        q.lo[t] = p.lo[t];
        q.hi[t] = p.hi[t] < 0 ? b.n(t) : p.hi[t];
        if (t != side_dir(p.side) && q.hi[t] > b.n(t))
          fail("{}: key '{}': the range [{}, {}] runs past block {}, which has {} cells in {}: valid ranges lie "
               "within [0, {}]", c.file, p.range_key[t], q.lo[t], q.hi[t], p.block + 1, b.n(t), "ijk"[t], b.n(t));
      }
      b.patches.push_back(q);
    }
  }
  if (gc.split != Index3{1, 1, 1} || gc.split_rotate) g = split_blocks(g, gc.split, gc.split_rotate);
  return g;
}

Grid finish_grid_from(const CaseConfig& c, Grid g, int balance_ranks) {
  const auto& gc = c.grid;
  // Cuts on multiples of 2^(levels - 1) cells of the grid that is run (grid.coarsen
  // levels below the generated one), so every multigrid level stays valid.
  if (balance_ranks > 1) {
    // Baldwin-Lomax searches whole grid lines normal to walls inside a block: keep them.
    std::vector<std::array<bool, 3>> uncut;
    if (c.turbulence.model == "baldwin-lomax")
      for (const Block& b : g.blocks) {
        std::array<bool, 3> keep{false, false, false};
        for (const Patch& p : b.patches) {
          const auto bc = c.bcs.find(p.label);
          if (bc != c.bcs.end() && bc->second.type == BcType::Wall) keep[static_cast<std::size_t>(side_dir(p.side))] = true;
        }
        uncut.push_back(keep);
      }
    g = split_for_balance(g, balance_ranks, 0.05, c.solver.multigrid.levels + gc.coarsen, 4096, uncut);
  }
  // Every labelled patch needs a BC (or a periodic partner); every BC a patch.
  for (const auto& [label, bc] : c.bcs)
    if (assign_bc(g, label, bc) == 0) fail("{}: key 'bc.{}': no patch of the grid has this label", c.file, label);
  for (std::size_t i = 0; i < c.periodic.size(); ++i) {
    const PeriodicConfig& p = c.periodic[i];
    const Mat3 R = Eigen::AngleAxisd(p.angle_deg * kRadiansPerDegree, p.axis.normalized()).toRotationMatrix();
    try {
      connect_periodic(g, p.a, p.b, R, p.translation);
    } catch (const Error& e) {
      fail("{}: key 'periodic[{}]': {}", c.file, i, e.what());
    }
  }
  finalize_grid(g);
  for (int level = 0; level < gc.coarsen; ++level) {
    const std::string why = why_not_coarsenable(g);
    if (!why.empty()) fail("{}: grid.coarsen = {}: coarsening {} failed: {}", c.file, gc.coarsen, level + 1, why);
    g = coarsen(g);
  }
  return g;
}

// `make` run with its errors naming the case file, the grid's source (and an imported
// grid's file).
template <class Make>
Grid naming_the_case(const CaseConfig& c, Make make) {
  try {
    return make();
  } catch (const Error& e) {
    const std::string what = e.what();
    if (what.rfind(c.file, 0) == 0) throw;
    // The blocks of an imported grid are the grid file's: name it too.
    if (c.grid.type == "plot3d" || c.grid.type == "cgns") fail("{}: grid file '{}': {}", c.file, c.grid.grid_file, what);
    fail("{}: {}", c.file, what);
  }
}

}  // namespace

Grid generate_grid(const CaseConfig& c) {
  return naming_the_case(c, [&] { return generate_grid_from(c); });
}

Grid finish_grid(const CaseConfig& c, Grid generated, int balance_ranks) {
  return naming_the_case(c, [&] { return finish_grid_from(c, std::move(generated), balance_ranks); });
}

Grid build_grid(const CaseConfig& c, int balance_ranks) { return finish_grid(c, generate_grid(c), balance_ranks); }

}  // namespace narwhal
