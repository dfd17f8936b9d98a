#include "config/propulsor_config.hpp"

#include <filesystem>

#include "config/reader.hpp"
#include "core/error.hpp"
#include "io/table_file.hpp"

namespace narwhal {
namespace {

// A file the curve is read from, with the key named in any error it gives.
template <class Make>
std::shared_ptr<const OpenWaterCurve> curve_from(const ConfigReader& r, const std::string& key, Make make) {
  try {
    return make();
  } catch (const Error& e) {
    r.error(key, e.what());
  }
}

}  // namespace

std::optional<PropulsorConfig> read_propulsor(const ConfigReader& r) {
  if (!r.has("propulsor")) return std::nullopt;
  PropulsorConfig p;
  PropulsorSpec& s = p.spec;
  s.name = r.string_or("propulsor.name", "propulsor", "the propulsor's name in the outputs");
  const bool table = r.has("propulsor.open_water"), series = r.has("propulsor.wageningen");
  if (table == series)
    r.error(table ? "propulsor.wageningen" : "propulsor.open_water",
            "give one open-water curve: propulsor.open_water (a table of J, KT and KQ or 10KQ) or "
            "propulsor.wageningen (the B-series coefficient table, with pitch_ratio, area_ratio and blades)");
  if (table) {
    const std::string f = r.file_path("propulsor.open_water", "the open-water table (CSV)");
    p.curve = curve_from(r, "propulsor.open_water", [&] { return std::make_shared<OpenWaterTable>(Table::read(f)); });
  } else {
    const std::string f = r.file_path("propulsor.wageningen", "the B-series coefficient table (CSV)");
    const Real pd = r.number("propulsor.pitch_ratio", "the pitch ratio P/D at 0.7 R", Range::between(0.5, 1.4));
    const Real ae = r.number("propulsor.area_ratio", "the expanded blade-area ratio Ae/A0", Range::between(0.30, 1.05));
    const int z = r.integer("propulsor.blades", "the number of blades", Range::between(2, 7));
    p.curve = curve_from(r, "propulsor.wageningen", [&] { return std::make_shared<WageningenB>(Table::read(f), pd, ae, z); });
  }
  const Real diameter = r.number("propulsor.diameter", "the propeller diameter D_p (grid units)", Range::positive());
  s.disk.tip_radius = 0.5 * diameter;
  s.disk.hub_radius = s.disk.tip_radius * r.number("propulsor.hub_ratio", "the hub radius over the tip radius R_H / R_P",
                                                   Range{0.0, 1.0, false, true});
  s.disk.thickness = r.number("propulsor.thickness", "the disk's axial thickness (grid units)", Range::positive());
  s.centre = r.vec3("propulsor.centre", "the hub centre [x, y, z] (grid coordinates)");
  s.axis = r.vec3_or("propulsor.axis", Vec3(-1.0, 0.0, 0.0),
                     "the thrust's direction on the vehicle (grid axes; the body's nose is at -x)");
  if (!(s.axis.norm() > 0.0)) r.error("propulsor.axis", "the axis must not be the zero vector");
  const std::string hand = r.string_or("propulsor.rotation", "right", "right or left (the blades' turn about the axis)");
  if (hand != "right" && hand != "left") r.error("propulsor.rotation", "expected \"right\" or \"left\", got '" + hand + "'");
  s.rotation = hand == "right" ? 1 : -1;
  s.rps = r.number("propulsor.rps", "the revolutions per unit time n (nondimensional: n L / U)", Range::positive());
  s.wake_fraction = r.number_or("propulsor.wake_fraction", 0.0,
                                "the Taylor wake fraction w_T of the advance speed V_A = (1 - w_T) u_B",
                                Range{0.0, 1.0, false, true});
  s.swirl = r.boolean_or("propulsor.swirl", s.swirl,
                         "whether the torque swirls the fluid (false: thrust alone, the actuator disk of momentum theory)");
  if (r.has("propulsor.inflow_distance"))
    s.inflow_distance = r.number("propulsor.inflow_distance",
                                 "how far ahead of the disk the advance speed is measured (grid units; NUMERICS §9.1 "
                                 "option b: about half a diameter)",
                                 Range::positive());
  s.sub_points = r.integer_or("propulsor.sub_points", s.sub_points,
                              "sub-points per direction that share a cut cell out to the disk", Range::between(1, 16));
  if (r.has("propulsor.rpm_control")) {
    RpmControlSettings c;
    c.interval = r.integer_or("propulsor.rpm_control.interval", c.interval, "cycles between steps of the rotation rate",
                              Range::between(1, 1e6));
    c.relaxation = r.number_or("propulsor.rpm_control.relaxation", c.relaxation,
                               "the fraction of the Newton step on thrust - resistance taken", Range{0.0, 1.0, true, false});
    c.tolerance = r.number_or("propulsor.rpm_control.tolerance", c.tolerance,
                              "|T - R| / R at which the rotation rate has settled", Range::positive());
    c.max_change = r.number_or("propulsor.rpm_control.max_change", c.max_change,
                               "the largest relative change of the rotation rate in one step", Range::positive());
    p.rpm_control = c;
  }
  return p;
}

}  // namespace narwhal
