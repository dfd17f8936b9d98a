// The body-force propulsor (NUMERICS §9): open-water curves (a table, the Wageningen
// B-series against its reference file's check values), the Hough-Ordway distribution's
// normalisation, and the source on a multiblock grid: the momentum it puts into the
// fluid, summed from the residual it changes, is T and Q to round-off (issue 19 bar 1).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <regex>

#include "io/table_file.hpp"
#include "motion/grid_motion.hpp"
#include "propulsion/body_force_propulsor.hpp"
#include "propulsion/hough_ordway.hpp"
#include "propulsion/open_water.hpp"
#include "test_support.hpp"

namespace narwhal {
namespace {

using test::source_path;

const std::string kWageningen = "reference_data/propulsor/wageningen_b_series_KT_KQ_coefficients.csv";
const std::string kDtmb4119 = "reference_data/propulsor/dtmb4119_open_water_openprop.csv";

TEST(TableFile, ReadsColumnsAndNamesWhatIsWrong) {
  const auto dir = test::fresh_temp_dir("table");
  const std::string good = (dir / "good.csv").string(), bad = (dir / "bad.csv").string();
  test::write_text(good, "# provenance\nJ,KT,name\n0.1,0.3,a\n0.2,0.25,b\n");
  const Table t = Table::read(good);
  EXPECT_EQ(t.rows(), 2u);
  EXPECT_EQ(t.column("KT")[1], 0.25);
  EXPECT_EQ(t.text("name")[0], "a");
  try {
    (void)t.column("KQ");
    FAIL() << "a missing column was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no column 'KQ' (columns: J, KT, name)"), std::string::npos) << e.what();
  }
  test::write_text(bad, "J,KT\n0.1,0.3\n0.2\n");
  try {
    (void)Table::read(bad);
    FAIL() << "a short row was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3: 1 values"), std::string::npos) << e.what();
  }
}

TEST(OpenWater, MonotoneCubicPassesThroughItsPointsWithoutOvershoot) {
  const std::vector<Real> x{0.0, 1.0, 2.0, 3.0, 4.0}, y{0.0, 0.0, 1.0, 1.0, 1.0};
  const MonotoneCubic f(x, y);
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_EQ(f(x[i]), y[i]);
  for (Real s = 0.0; s <= 4.0; s += 0.01) {
    EXPECT_GE(f(s), -1e-15);
    EXPECT_LE(f(s), 1.0 + 1e-15);  // a natural spline overshoots the step
  }
  const MonotoneCubic line({0.0, 1.0, 3.0}, {1.0, 3.0, 7.0});
  for (Real s : {-1.0, 0.5, 2.0, 4.0}) EXPECT_NEAR(line(s), 1.0 + 2.0 * s, 1e-14) << s;
}

TEST(OpenWater, TableGivesItsPointsAndTakesTenKq) {
  const Table t = Table::read(source_path(kDtmb4119));
  const OpenWaterTable curve(t);
  for (std::size_t r = 0; r < t.rows(); ++r) {
    EXPECT_EQ(curve.kt(t.column("J")[r]), t.column("KT")[r]);
    EXPECT_NEAR(curve.kq(t.column("J")[r]), t.column("10KQ")[r] / 10.0, 1e-16);
  }
}

// The reference file's header gives K_T and K_Q of B4-70 at P/D = 1.0 computed with its
// coefficients: "J=0: KT=0.45474 KQ=0.067538 ; J=0.5: ...". Read from there, not typed.
TEST(OpenWater, WageningenPolynomialsGiveTheReferenceFilesCheckValues) {
  const std::string text = test::read_text(source_path(kWageningen));
  const auto at = text.find("Implementation check");
  ASSERT_NE(at, std::string::npos);
  const std::string line = text.substr(at, text.find('\n', at) - at);
  ASSERT_NE(line.find("B4-70, P/D=1.0"), std::string::npos) << line;
  const std::regex point(R"(J=([0-9.]+): KT=([0-9.]+) KQ=([0-9.]+))");
  const WageningenB b470(Table::read(source_path(kWageningen)), 1.0, 0.70, 4);
  int checked = 0;
  for (auto it = std::sregex_iterator(line.begin(), line.end(), point); it != std::sregex_iterator(); ++it) {
    const Real J = std::stod((*it)[1]), kt = std::stod((*it)[2]), kq = std::stod((*it)[3]);
    // Printed to five significant digits.
    EXPECT_NEAR(b470.kt(J), kt, 5e-5 * kt) << "J = " << J;
    EXPECT_NEAR(b470.kq(J), kq, 5e-5 * kq) << "J = " << J;
    ++checked;
  }
  EXPECT_EQ(checked, 3);
  EXPECT_THROW(WageningenB(Table::read(source_path(kWageningen)), 1.6, 0.7, 4), Error);
  EXPECT_THROW(WageningenB(Table::read(source_path(kWageningen)), 1.0, 0.7, 9), Error);
}

TEST(HoughOrdway, ContinuousDistributionCarriesThrustAndTorque) {
  const hough_ordway::Disk d{0.2, 1.0, 0.05};
  const Real T = 0.7, Q = 0.13;
  // Gauss-Legendre on r* with the substitution r* = 1 - s^2, which takes the square
  // root's end point out: int_0^1 g(r*) dr* = int_0^1 g(1 - s^2) 2 s ds.
  const int n = 40;
  Real thrust = 0.0, torque = 0.0;
  for (int q = 0; q < n; ++q) {
    // Midpoint rule on s, refined: smooth integrand, exact enough at n = 40 x 50.
    for (int m = 0; m < 50; ++m) {
      const Real s = (q * 50 + m + 0.5) / (n * 50.0), ds = 1.0 / (n * 50.0);
      const Real rs = 1.0 - s * s, r = d.hub_radius + rs * (d.tip_radius - d.hub_radius);
      const Real dr = 2.0 * s * ds * (d.tip_radius - d.hub_radius);
      const Real ring = 2.0 * std::numbers::pi * r * d.thickness * dr;
      thrust += hough_ordway::axial_constant(T, d) * hough_ordway::axial_shape(r, d) * ring;
      torque += hough_ordway::tangential_constant(Q, d) * hough_ordway::tangential_shape(r, d) * r * ring;
    }
  }
  EXPECT_NEAR(thrust / T, 1.0, 1e-6);
  EXPECT_NEAR(torque / Q, 1.0, 1e-6);
}

TEST(HoughOrdway, ShapeDerivativeByComplexStep) {
  const hough_ordway::Disk d{0.2, 1.0, 0.05};
  const Real h = 1e-30;
  for (Real r : {0.3, 0.5, 0.75, 0.95}) {
    const std::complex<Real> rc(r, h);
    const Real cs = hough_ordway::axial_shape(rc, d).imag() / h;
    const Real s = hough_ordway::r_star(r, d), ds_dr = 1.0 / (d.tip_radius - d.hub_radius);
    const Real exact = (std::sqrt(1.0 - s) - s / (2.0 * std::sqrt(1.0 - s))) * ds_dr;
    EXPECT_NEAR(cs, exact, 1e-13 * std::abs(exact)) << r;
  }
}

// A box round a disk of radius 1 about the origin, thrust along -x (the fluid pushed
// towards +x), cut into blocks turned every way so that the disk crosses their joins.
Grid disk_box(int n_axial, int n_across) {
  Grid whole;
  whole.blocks.push_back(make_box("box", uniform_nodes(-0.3, 0.3, n_axial), uniform_nodes(-1.3, 1.3, n_across),
                                  uniform_nodes(-1.3, 1.3, n_across)));
  Grid g = split_blocks(whole, {2, 3, 2}, true);
  for (auto s : {"imin", "imax", "jmin", "jmax", "kmin", "kmax"}) assign_bc(g, s, {BcType::Farfield});
  finalize_grid(g);
  return g;
}

PropulsorSpec disk_spec() {
  PropulsorSpec s;
  s.name = "test propeller";
  s.centre = Vec3(0.01, -0.02, 0.03);
  s.axis = Vec3(-1.0, 0.0, 0.0);
  s.rotation = 1;
  s.disk = {0.2, 1.0, 0.1};
  s.rps = 1.5;
  s.wake_fraction = 0.1;
  return s;
}

std::shared_ptr<const OpenWaterCurve> dtmb4119() {
  return std::make_shared<OpenWaterTable>(Table::read(source_path(kDtmb4119)));
}

// The force and the torque about the spin axis that the source puts into the fluid,
// summed over the grid from the residual change it makes: R_c -= V_c f_c.
std::pair<Vec3, Real> fluid_loads(const Grid& g, const BodyForcePropulsor& p) {
  Vec3 force = Vec3::Zero();
  Real torque = 0.0;
  const Vec3 spin = static_cast<Real>(p.spec().rotation) * p.axis();
  for (const Block& b : g.blocks) {
    GhostArray<State> Q(b.ni, b.nj, b.nk, 2, State::Zero()), R(b.ni, b.nj, b.nk, 2, State::Zero());
    p.add_to_residual(b, Q, R);
    for_each_cell(b, [&](int i, int j, int k) {
      const Vec3 f = -R(i, j, k).tail<3>();
      force += f;
      torque += (b.xc(i, j, k) - p.centre()).cross(f).dot(spin);
    });
  }
  return {force, torque};
}

// The force per cell the source puts into the fluid, block after block.
std::vector<Vec3> cell_forces(const Grid& g, const BodyForcePropulsor& p) {
  std::vector<Vec3> f;
  for (const Block& b : g.blocks) {
    GhostArray<State> Q(b.ni, b.nj, b.nk, 2, State::Zero()), R(b.ni, b.nj, b.nk, 2, State::Zero());
    p.add_to_residual(b, Q, R);
    for_each_cell(b, [&](int i, int j, int k) { f.push_back(-R(i, j, k).tail<3>()); });
  }
  return f;
}

TEST(BodyForcePropulsor, OperatingPointFromTheOpenWaterCurve) {
  BodyForcePropulsor p(disk_spec(), dtmb4119());
  p.set_surge_speed(1.2);
  const PropulsorLoads& l = p.loads();
  const Real D = 2.0, n = 1.5;
  EXPECT_DOUBLE_EQ(l.advance_speed, 0.9 * 1.2);
  EXPECT_DOUBLE_EQ(l.advance_ratio, 0.9 * 1.2 / (n * D));
  EXPECT_DOUBLE_EQ(l.thrust, p.curve().kt(l.advance_ratio) * n * n * std::pow(D, 4));
  EXPECT_DOUBLE_EQ(l.torque, p.curve().kq(l.advance_ratio) * n * n * std::pow(D, 5));
  EXPECT_GT(l.thrust, 0.0);
}

TEST(BodyForcePropulsor, FluidTakesThrustAndTorqueExactly) {
  const Grid g = disk_box(8, 36);
  BodyForcePropulsor p(disk_spec(), dtmb4119());
  p.set_surge_speed(1.0);
  p.normalise(Communicator::world(), g);
  const auto [force, torque] = fluid_loads(g, p);
  const Real T = p.loads().thrust, Q = p.loads().torque;
  // The fluid is pushed along -e_a = +x with the thrust, and swirled with the blades.
  EXPECT_NEAR(force[0] / T, 1.0, 1e-10);
  EXPECT_NEAR(torque / Q, 1.0, 1e-10);
  // Off the grid's centre the swirl leaves a side force of the discretization's size.
  EXPECT_LT(std::abs(force[1]) + std::abs(force[2]), 1e-4 * T);
  // A new operating point rescales without normalising again.
  p.set_surge_speed(0.6);
  const auto [force2, torque2] = fluid_loads(g, p);
  EXPECT_NEAR(force2[0] / p.loads().thrust, 1.0, 1e-10);
  EXPECT_NEAR(torque2 / p.loads().torque, 1.0, 1e-10);
  EXPECT_GT(p.loads().thrust, T);
}

TEST(BodyForcePropulsor, CarriedWithARigidlyMovedGridItsCellsKeepTheirShares) {
  // Normalised on the grid as built, then grid and disk moved by one pose: the cells the
  // normalisation kept give, turned, what a propulsor built at the moved place finds by
  // searching the moved grid, and the fluid still takes T and Q about the turned axis.
  Grid g = disk_box(8, 24);
  BodyForcePropulsor carried(disk_spec(), dtmb4119());
  carried.set_surge_speed(1.0);
  carried.normalise(Communicator::world(), g);
  RigidPose pose;
  pose.rotation = (Eigen::AngleAxis<Real>(0.4, Vec3(0.3, -0.5, 0.8).normalized())).toRotationMatrix();
  pose.displacement = Vec3(0.7, -0.2, 0.35);
  const Vec3 pivot(0.1, 0.05, -0.1);
  MovingGrid(g, pivot).place_at(pose);
  carried.place(pose, pivot);
  EXPECT_TRUE(carried.axis().isApprox(pose.rotation * disk_spec().axis, 1e-15));
  EXPECT_TRUE(carried.centre().isApprox(pose.apply(disk_spec().centre, pivot), 1e-15));

  PropulsorSpec moved = disk_spec();
  moved.centre = carried.centre();
  moved.axis = carried.axis();
  BodyForcePropulsor found(moved, dtmb4119());
  found.set_surge_speed(1.0);
  found.normalise(Communicator::world(), g);
  const std::vector<Vec3> a = cell_forces(g, carried), b = cell_forces(g, found);
  ASSERT_EQ(a.size(), b.size());
  Real largest = 0.0, difference = 0.0;
  for (std::size_t c = 0; c < a.size(); ++c) {
    largest = std::max(largest, a[c].norm());
    difference = std::max(difference, (a[c] - b[c]).norm());
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(difference, 1e-12 * largest);
  const auto [force, torque] = fluid_loads(g, carried);
  EXPECT_NEAR(force.dot(-carried.axis()) / carried.loads().thrust, 1.0, 1e-10);
  EXPECT_NEAR(torque / carried.loads().torque, 1.0, 1e-10);
  EXPECT_TRUE(carried.vehicle_force().isApprox(carried.loads().thrust * carried.axis(), 1e-15));
}

TEST(BodyForcePropulsor, BlocksItWasNotNormalisedOnAreSearchedCellByCell) {
  // A copy of the grid (other blocks, as a multigrid level's are) gets the same source.
  const Grid g = disk_box(8, 24);
  BodyForcePropulsor p(disk_spec(), dtmb4119());
  p.set_surge_speed(1.0);
  p.normalise(Communicator::world(), g);
  const Grid copy = g;
  EXPECT_EQ(cell_forces(g, p), cell_forces(copy, p));
}

TEST(BodyForcePropulsor, CentredOnASymmetricGridTheSwirlHasNoSideForce) {
  const Grid g = disk_box(6, 24);
  PropulsorSpec s = disk_spec();
  s.centre = Vec3::Zero();
  BodyForcePropulsor p(s, dtmb4119());
  p.set_surge_speed(1.0);
  p.normalise(Communicator::world(), g);
  const auto [force, torque] = fluid_loads(g, p);
  EXPECT_LT(std::abs(force[1]) + std::abs(force[2]), 1e-12 * p.loads().thrust);
  EXPECT_NEAR(torque / p.loads().torque, 1.0, 1e-10);
}

TEST(BodyForcePropulsor, WithoutSwirlTheFluidTakesThrustAlone) {
  const Grid g = disk_box(6, 16);
  PropulsorSpec s = disk_spec();
  s.swirl = false;
  BodyForcePropulsor p(s, dtmb4119());
  p.set_surge_speed(1.0);
  p.normalise(Communicator::world(), g);
  const auto [force, torque] = fluid_loads(g, p);
  EXPECT_NEAR(force[0] / p.loads().thrust, 1.0, 1e-10);
  EXPECT_EQ(torque, 0.0);
  EXPECT_TRUE(p.vehicle_moment(s.centre).isZero(0.0));
}

TEST(BodyForcePropulsor, AdvanceSpeedMeasuredAheadOfTheDisk) {
  Grid g = disk_box(8, 24);
  PropulsorSpec s = disk_spec();
  s.centre = Vec3(0.1, 0.0, 0.0);
  s.inflow_distance = 0.2;  // the annulus at x = -0.1, inside the box
  BodyForcePropulsor p(s, dtmb4119());
  p.set_surge_speed(1.0);
  p.normalise(Communicator::world(), g);
  EXPECT_DOUBLE_EQ(p.loads().advance_speed, 0.9);  // option a's until measured
  // The water along +x at 0.8 plus a part odd across the axis: its mean over the
  // (symmetric) annulus is 0.8.
  std::vector<GhostArray<State>> Q;
  for (const Block& b : g.blocks) {
    Q.emplace_back(b.ni, b.nj, b.nk, 2, State::Zero());
    for_each_cell(b, [&](int i, int j, int k) { Q.back()(i, j, k) << 0.0, 0.8 + 0.3 * b.xc(i, j, k)[1], 0.1, 0.0; });
  }
  p.measure_inflow(Communicator::world(), g, Q);
  EXPECT_NEAR(p.loads().advance_speed, 0.8, 1e-12);
  EXPECT_NEAR(p.loads().wake_fraction, 0.2, 1e-12);
  EXPECT_NEAR(p.loads().advance_ratio, 0.8 / (1.5 * 2.0), 1e-12);
  EXPECT_DOUBLE_EQ(p.loads().thrust, p.curve().kt(p.loads().advance_ratio) * 1.5 * 1.5 * 16.0);
  // The fluid's loads follow the measured operating point.
  const auto [force, torque] = fluid_loads(g, p);
  EXPECT_NEAR(force[0] / p.loads().thrust, 1.0, 1e-10);
}

TEST(BodyForcePropulsor, LeftHandedBladesSwirlTheOtherWay) {
  const Grid g = disk_box(8, 24);
  PropulsorSpec s = disk_spec();
  BodyForcePropulsor right(s, dtmb4119());
  s.rotation = -1;
  BodyForcePropulsor left(s, dtmb4119());
  for (auto* p : {&right, &left}) {
    p->set_surge_speed(1.0);
    p->normalise(Communicator::world(), g);
  }
  // About +x (the fluid's way): right-handed about e_a = -x turns the fluid negatively.
  auto swirl_about_x = [&](const BodyForcePropulsor& p) {
    Real m = 0.0;
    for (const Block& b : g.blocks) {
      GhostArray<State> Q(b.ni, b.nj, b.nk, 2, State::Zero()), R(b.ni, b.nj, b.nk, 2, State::Zero());
      p.add_to_residual(b, Q, R);
      for_each_cell(b, [&](int i, int j, int k) {
        m += (b.xc(i, j, k) - p.spec().centre).cross(Vec3(-R(i, j, k).tail<3>()))[0];
      });
    }
    return m;
  };
  EXPECT_LT(swirl_about_x(right), 0.0);
  EXPECT_NEAR(swirl_about_x(left), -swirl_about_x(right), 1e-12 * std::abs(swirl_about_x(right)));
}

TEST(BodyForcePropulsor, CutCellsShareTheDisksVolume) {
  const hough_ordway::Disk d = disk_spec().disk;
  const Real exact = std::numbers::pi * (d.tip_radius * d.tip_radius - d.hub_radius * d.hub_radius) * d.thickness;
  // The cut cells' shares from 4^3 sub-points each: the error is a sampling error of the
  // order of a sixty-fourth of the cut cells' volume, falling unevenly with the spacing
  // (measured 7.7e-3, 8.3e-5, 1.1e-3, 2.1e-4 at 6, 12, 24, 48 cells across).
  for (const auto& [n, bound] : std::vector<std::pair<int, Real>>{{6, 2e-2}, {24, 3e-3}, {48, 1e-3}}) {
    BodyForcePropulsor p(disk_spec(), dtmb4119());
    p.normalise(Communicator::world(), disk_box(6, n));
    EXPECT_LT(std::abs(p.disk_volume() - exact) / exact, bound) << n << " cells across";
  }
}

TEST(BodyForcePropulsor, VehicleTakesThrustAndTheTorquesReaction) {
  const Grid g = disk_box(6, 16);
  BodyForcePropulsor p(disk_spec(), dtmb4119());
  p.set_surge_speed(1.0);
  p.normalise(Communicator::world(), g);
  const Vec3 origin(2.0, 0.0, 0.1);
  const Vec3 F = p.vehicle_force(), M = p.vehicle_moment(origin);
  EXPECT_TRUE(F.isApprox(Vec3(-p.loads().thrust, 0.0, 0.0)));
  const Vec3 expected = (p.spec().centre - origin).cross(F) - p.loads().torque * Vec3(-1.0, 0.0, 0.0);
  EXPECT_TRUE(M.isApprox(expected));
}

TEST(BodyForcePropulsor, RefusesADiskOutsideTheGridAndBadGeometry) {
  PropulsorSpec s = disk_spec();
  s.centre = Vec3(10.0, 0.0, 0.0);
  BodyForcePropulsor p(s, dtmb4119());
  EXPECT_THROW(p.normalise(Communicator::world(), disk_box(4, 8)), Error);
  s = disk_spec();
  s.disk.hub_radius = 1.5;
  EXPECT_THROW(BodyForcePropulsor(s, dtmb4119()), Error);
}

// [propulsor] of the R7a case, read as a run reads it, and what a wrong one is told.
std::string disk_case() { return test::read_text(source_path("validation/cases/propulsor_open_water/disk.toml")); }
const std::string kDiskDir = "validation/cases/propulsor_open_water";

std::string propulsor_error(const std::vector<std::string>& overrides, std::string text = disk_case()) {
  try {
    (void)parse_case(text, "disk.toml", source_path(kDiskDir), overrides);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(PropulsorCase, ReadsTheDiskAndItsCurve) {
  const CaseConfig c = parse_case(disk_case(), "disk.toml", source_path(kDiskDir));
  ASSERT_TRUE(c.propulsor.has_value());
  EXPECT_EQ(c.propulsor->spec.disk.tip_radius, 0.5);
  EXPECT_NEAR(c.propulsor->spec.disk.hub_radius, 0.1, 1e-15);
  EXPECT_EQ(c.propulsor->spec.rotation, 1);
  EXPECT_EQ(c.propulsor->curve->kt(1.0), 0.075);
  EXPECT_FALSE(parse_case(disk_case(), "disk.toml", source_path(kDiskDir), {"propulsor.swirl=false"}).propulsor->spec.swirl);
}

TEST(PropulsorCase, BadInputNamesTheKey) {
  std::string e = propulsor_error({"propulsor.open_water=\"no_such_table.csv\""});
  EXPECT_NE(e.find("propulsor.open_water"), std::string::npos) << e;
  EXPECT_NE(e.find("no_such_table.csv"), std::string::npos) << e;
  e = propulsor_error({"propulsor.wageningen=\"x.csv\""});
  EXPECT_NE(e.find("give one open-water curve"), std::string::npos) << e;
  e = propulsor_error({"propulsor.rotation=\"clockwise\""});
  EXPECT_NE(e.find("propulsor.rotation"), std::string::npos) << e;
  e = propulsor_error({"propulsor.hub_ratio=1.0"});
  EXPECT_NE(e.find("propulsor.hub_ratio"), std::string::npos) << e;
  e = propulsor_error({"propulsor.rpm=1.0"});
  EXPECT_NE(e.find("unknown key 'propulsor.rpm'"), std::string::npos) << e;
  e = propulsor_error({"propulsor.rpm_control.interval=5", "time.scheme=\"bdf2\"", "time.step=0.1", "time.steps=3"});
  EXPECT_NE(e.find("propulsor.rpm_control"), std::string::npos) << e;
  EXPECT_NE(e.find("dual-time run"), std::string::npos) << e;
}

}  // namespace
}  // namespace narwhal
