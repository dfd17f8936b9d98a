#include "propulsion/body_force_propulsor.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "mesh/block.hpp"
#include "parallel/reduction.hpp"

namespace narwhal {

BodyForcePropulsor::BodyForcePropulsor(PropulsorSpec spec, std::shared_ptr<const OpenWaterCurve> curve)
    : spec_(std::move(spec)), curve_(std::move(curve)) {
  const auto& d = spec_.disk;
  if (!curve_) fail("propulsor '{}': no open-water curve", spec_.name);
  if (!(d.tip_radius > d.hub_radius && d.hub_radius >= 0.0))
    fail("propulsor '{}': the tip radius ({}) must exceed the hub radius ({}), which must not be negative", spec_.name,
         d.tip_radius, d.hub_radius);
  if (!(d.thickness > 0.0)) fail("propulsor '{}': the disk's thickness must be positive, got {}", spec_.name, d.thickness);
  if (!(spec_.axis.norm() > 0.0)) fail("propulsor '{}': the axis must not be zero", spec_.name);
  if (spec_.rotation != 1 && spec_.rotation != -1) fail("propulsor '{}': rotation must be +1 or -1", spec_.name);
  if (!(spec_.rps > 0.0)) fail("propulsor '{}': the rotation rate must be positive, got {}", spec_.name, spec_.rps);
  if (spec_.sub_points < 1) fail("propulsor '{}': sub_points must be at least 1", spec_.name);
  spec_.axis.normalize();
  centre_ = spec_.centre;
  axis_ = spec_.axis;
}

void BodyForcePropulsor::set_surge_speed(Real surge_speed) {
  loads_.surge_speed = surge_speed;
  // Option b keeps the advance speed it measured (only the wake fraction follows); until
  // the flow is measured the advance speed is option a's.
  set_advance_speed(inflow_measured_ ? loads_.advance_speed : (1.0 - spec_.wake_fraction) * surge_speed);
}

void BodyForcePropulsor::set_advance_speed(Real advance_speed) {
  const Real n = spec_.rps, D = 2.0 * spec_.disk.tip_radius;
  loads_.advance_speed = advance_speed;
  loads_.wake_fraction = loads_.surge_speed != 0.0 ? 1.0 - advance_speed / loads_.surge_speed : 0.0;
  loads_.advance_ratio = advance_speed / (n * D);
  loads_.kt = curve_->kt(loads_.advance_ratio);
  loads_.kq = curve_->kq(loads_.advance_ratio);
  loads_.thrust = loads_.kt * n * n * std::pow(D, 4);  // §9.1, rho = 1
  loads_.torque = loads_.kq * n * n * std::pow(D, 5);
  update_scales();
}

void BodyForcePropulsor::set_rps(Real rps) {
  if (!(rps > 0.0)) fail("propulsor '{}': the rotation rate must stay positive, got {}", spec_.name, rps);
  spec_.rps = rps;
  set_advance_speed(loads_.advance_speed);
}

void BodyForcePropulsor::restore_operating_point(Real rps, Real advance_speed) {
  if (!(rps > 0.0)) fail("propulsor '{}': a restart's rotation rate must be positive, got {}", spec_.name, rps);
  spec_.rps = rps;
  inflow_measured_ = spec_.inflow_distance.has_value();
  set_advance_speed(advance_speed);
}

Real BodyForcePropulsor::thrust_slope() const {
  const Real n = spec_.rps, D = 2.0 * spec_.disk.tip_radius, J = loads_.advance_ratio;
  const Real h = 1e-4;
  const Real dkt = (curve_->kt(J + h) - curve_->kt(J - h)) / (2.0 * h);
  return std::pow(D, 4) * (2.0 * n * loads_.kt - dkt * loads_.advance_speed / D);
}

void BodyForcePropulsor::measure_inflow(const Communicator& comm, const Grid& g, const std::vector<GhostArray<State>>& Q) {
  if (!spec_.inflow_distance) return;
  const Vec3 centre = centre_ + *spec_.inflow_distance * axis_;
  std::vector<Real> partials(2 * g.blocks.size(), 0.0);  // per block: sum V u_a, sum V
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    for_each_cell(b, [&](int i, int j, int k) {
      const auto s = share(b, i, j, k, centre);
      if (!s) return;
      // The water's velocity relative to the grid (a moving grid's own velocity taken off).
      const Vec3 u = Q[ib](i, j, k).tail<3>() - b.motion.at(b.xc(i, j, k));
      const Real V = b.vol(i, j, k) * s->fraction;
      partials[2 * ib] += V * (-u.dot(axis_));
      partials[2 * ib + 1] += V;
    });
  }
  const std::vector<Real> total = sum_in_block_order(comm, g, std::move(partials), 2);
  if (!(total[1] > 0.0))
    fail("propulsor '{}': no cell of the grid lies in its inflow annulus {} ahead of the disk", spec_.name,
         *spec_.inflow_distance);
  inflow_measured_ = true;
  set_advance_speed(total[0] / total[1]);
}

void BodyForcePropulsor::update_scales() {
  if (!normalised_) return;
  axial_scale_ = loads_.thrust / axial_integral_;
  tangential_scale_ = spec_.swirl ? loads_.torque / torque_integral_ : 0.0;
}

std::optional<BodyForcePropulsor::CellShare> BodyForcePropulsor::share(const Block& b, int i, int j, int k,
                                                                       const Vec3& centre) const {
  const auto& d = spec_.disk;
  const Vec3& e = axis_;
  // Cells whose corners all lie farther than the disk reaches are left at once.
  const Vec3 xc = b.xc(i, j, k);
  Real reach = 0.0;
  for (int c = 0; c < 8; ++c) reach = std::max(reach, (b.x(i + (c & 1), j + ((c >> 1) & 1), k + (c >> 2)) - xc).norm());
  const Vec3 rel = xc - centre;
  const Real xa = rel.dot(e), r = (rel - xa * e).norm();
  if (std::abs(xa) > 0.5 * d.thickness + reach || r > d.tip_radius + reach || r < d.hub_radius - reach)
    return std::nullopt;
  // §9.4: the sub-points of the cell's trilinear map, each standing for an equal part.
  const int n = spec_.sub_points;
  const Vec3 w = spin();
  CellShare s;
  int inside = 0;
  for (int c = 0; c < n; ++c)
    for (int bq = 0; bq < n; ++bq)
      for (int a = 0; a < n; ++a) {
        const Real xi = (a + 0.5) / n, eta = (bq + 0.5) / n, zeta = (c + 0.5) / n;
        Vec3 p = Vec3::Zero();
        for (int m = 0; m < 8; ++m) {
          const int di = m & 1, dj = (m >> 1) & 1, dk = m >> 2;
          const Real weight = (di ? xi : 1 - xi) * (dj ? eta : 1 - eta) * (dk ? zeta : 1 - zeta);
          p += weight * b.x(i + di, j + dj, k + dk);
        }
        const Vec3 q = p - centre;
        const Real qa = q.dot(e);
        const Vec3 radial = q - qa * e;
        const Real rq = radial.norm();
        if (std::abs(qa) > 0.5 * d.thickness || rq <= d.hub_radius || rq >= d.tip_radius) continue;
        ++inside;
        s.axial += hough_ordway::axial_shape(rq, d);
        s.tangential += hough_ordway::tangential_shape(rq, d) * w.cross(radial / rq);  // e_theta = w_p x r / r
      }
  if (inside == 0) return std::nullopt;
  const Real points = static_cast<Real>(n) * n * n;
  s.fraction = inside / points;
  s.axial /= points;
  s.tangential /= points;
  return s;
}

void BodyForcePropulsor::normalise(const Communicator& comm, const Grid& g) {
  // Per block: the disk's volume, sum V axial and sum V ((x_c - x_p) x tangential).w_p.
  constexpr int kWidth = 3;
  std::vector<Real> partials(kWidth * g.blocks.size(), 0.0);
  const Vec3 w = spin();
  disk_cells_.clear();
  for (std::size_t ib = 0; ib < g.blocks.size(); ++ib) {
    if (!g.owns(ib)) continue;
    const Block& b = g.blocks[ib];
    BlockDiskCells& kept = disk_cells_[&b];
    kept.size = {b.ni, b.nj, b.nk};
    for_each_cell(b, [&](int i, int j, int k) {
      const auto s = share(b, i, j, k);
      if (!s) return;
      const Real V = b.vol(i, j, k);
      partials[kWidth * ib + 0] += V * s->fraction;
      partials[kWidth * ib + 1] += V * s->axial;
      partials[kWidth * ib + 2] += V * (b.xc(i, j, k) - centre_).cross(s->tangential).dot(w);
      kept.cells.push_back({{i, j, k}, s->axial, turn_.transpose() * s->tangential});
    });
  }
  const std::vector<Real> total = sum_in_block_order(comm, g, std::move(partials), kWidth);
  if (!(total[1] > 0.0) || !(total[2] > 0.0))
    fail("propulsor '{}': no cell of the grid lies inside its disk (centre [{}, {}, {}], radii {} to {}, thickness {})",
         spec_.name, centre_[0], centre_[1], centre_[2], spec_.disk.hub_radius, spec_.disk.tip_radius,
         spec_.disk.thickness);
  disk_volume_ = total[0];
  axial_integral_ = total[1];
  torque_integral_ = total[2];
  normalised_ = true;
  update_scales();
}

Vec3 BodyForcePropulsor::cell_force(Real volume, Real axial, const Vec3& tangential) const {
  // §9.4: f_c = -f_a e_a + f_theta e_theta, the fluid pushed aft and swirled with the blades.
  return volume * (-axial_scale_ * axial * axis_ + tangential_scale_ * tangential);
}

void BodyForcePropulsor::add_to_residual(const Block& b, const GhostArray<State>&, GhostArray<State>& R) const {
  if (!normalised_) fail("propulsor '{}': internal: its source was used before normalise()", spec_.name);
  const auto kept = disk_cells_.find(&b);
  if (kept != disk_cells_.end() && kept->second.size == Index3{b.ni, b.nj, b.nk}) {
    for (const DiskCell& c : kept->second.cells) {
      const auto [i, j, k] = c.cell;
      R(i, j, k).tail<3>() -= cell_force(b.vol(i, j, k), c.axial, turn_ * c.tangential_as_built);
    }
    return;
  }
  for_each_cell(b, [&](int i, int j, int k) {
    const auto s = share(b, i, j, k);
    if (s) R(i, j, k).tail<3>() -= cell_force(b.vol(i, j, k), s->axial, s->tangential);
  });
}

void BodyForcePropulsor::place(const RigidPose& pose, const Vec3& pivot) {
  centre_ = pose.apply(spec_.centre, pivot);
  turn_ = pose.rotation;
  axis_ = turn_ * spec_.axis;
}

Vec3 BodyForcePropulsor::vehicle_force() const { return loads_.thrust * axis_; }

Vec3 BodyForcePropulsor::vehicle_moment(const Vec3& moment_centre) const {
  const Real reaction = spec_.swirl ? loads_.torque : 0.0;
  return (centre_ - moment_centre).cross(vehicle_force()) - reaction * spin();
}

}  // namespace narwhal
