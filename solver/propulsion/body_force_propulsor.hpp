#pragma once
// A body-force propulsor (NUMERICS §9): thrust and torque from the propeller's open-water
// curve at its operating point, spread over a disk of cells by the Hough-Ordway radial
// distribution and put into the momentum equations as a volume source. The fluid is
// pushed along -e_a and swirled with the blades; the vehicle takes T e_a and the torque's
// reaction -Q w_p (§9.5). One entry of the flow's source list (physics/volume_source.hpp).
//
// Usage:
//   auto prop = std::make_shared<BodyForcePropulsor>(spec, curve);
//   prop->set_surge_speed(1.0);   // the operating point: J, K_T, K_Q, T, Q
//   prop->normalise(comm, grid);  // collective over comm: the disk's cells on every rank
//   fp.sources.push_back(prop);
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/types.hpp"
#include "fields/ghost_array.hpp"
#include "motion/grid_motion.hpp"
#include "parallel/communicator.hpp"
#include "physics/volume_source.hpp"
#include "propulsion/hough_ordway.hpp"
#include "propulsion/open_water.hpp"

namespace narwhal {

struct Grid;

struct PropulsorSpec {
  std::string name = "propulsor";
  Vec3 centre = Vec3::Zero();  // hub centre x_p (grid coordinates, as built)
  Vec3 axis = Vec3::UnitX();   // e_a: the thrust's direction on the vehicle (unit, as built)
  // +1: the blades turn right-handed about e_a (w_p = e_a), -1: left-handed (w_p = -e_a).
  int rotation = 1;
  hough_ordway::Disk disk;
  Real rps = 0.0;            // n, revolutions per unit time (nondimensional, §0.2)
  Real wake_fraction = 0.0;  // w_T of the advance speed V_A = (1 - w_T) u_B (§9.1 option a)
  int sub_points = 4;        // per direction: a cut cell's share of the disk from sub_points^3 points
  // false: thrust alone, no torque on the fluid nor its reaction on the vehicle (the
  // actuator disk of momentum theory, whose far wake has a closed form).
  bool swirl = true;
  // Set: the advance speed measured in the flow (§9.1 option b), the volume mean of the
  // water's speed along -e_a over an annulus of the disk's radii and thickness this far
  // ahead of the disk (along e_a); the wake fraction is then an outcome, 1 - V_A / u_B.
  std::optional<Real> inflow_distance;
};

// The operating point and the loads it gives (nondimensional: rho = 1).
struct PropulsorLoads {
  Real surge_speed = 0.0;    // u_B, the vehicle's speed through the water along e_a
  Real advance_speed = 0.0;  // V_A
  Real wake_fraction = 0.0;  // 1 - V_A / u_B
  Real advance_ratio = 0.0;  // J = V_A / (n D)
  Real kt = 0.0, kq = 0.0;
  Real thrust = 0.0;  // T = K_T n^2 D^4
  Real torque = 0.0;  // Q = K_Q n^2 D^5
};

class BodyForcePropulsor final : public VolumeSource {
 public:
  BodyForcePropulsor(PropulsorSpec spec, std::shared_ptr<const OpenWaterCurve> curve);

  std::string name() const override { return spec_.name; }
  const PropulsorSpec& spec() const { return spec_; }
  const OpenWaterCurve& curve() const { return *curve_; }

  // The operating point at the vehicle's surge speed u_B (its speed through the water
  // along e_a): V_A = (1 - w_T) u_B, J = V_A / (n D), T and Q from the curve (§9.1).
  // Once the inflow has been measured (option b) V_A stays the measured one.
  void set_surge_speed(Real surge_speed);
  // With an inflow_distance: V_A measured in the flow f on g (§9.1 option b; lagged: the
  // loads of the next residuals follow it). Collective over comm, the ranks sharing g. Without
  // one it does nothing.
  void measure_inflow(const Communicator& comm, const Grid& g, const std::vector<GhostArray<State>>& Q);
  const PropulsorLoads& loads() const { return loads_; }
  // A new rotation rate (an rpm controller's): the loads at the present advance speed.
  void set_rps(Real rps);
  // A restart's rotation rate and advance speed (as the run that wrote it had them).
  void restore_operating_point(Real rps, Real advance_speed);
  // dT/dn at the present advance speed: D^4 (2 n K_T - K_T'(J) V_A / D), K_T' by central
  // differences of the curve.
  Real thrust_slope() const;

  // The discrete renormalisation (§9.4): the constants that make the disk's cells of g
  // carry T and Q exactly (sum_c V_c f_a,c = T, sum_c V_c ((x_c - x_p) x f_c).w_p = Q).
  // Collective over comm, the ranks that share g (a sum in block order: the same on any rank
  // count); the operating point rescales them without a new call. It also keeps the
  // disk's cells of g's owned blocks and their shares, so that a residual visits only
  // those: g must outlive the source's use on its blocks (the run's grid does). Other
  // blocks (multigrid's coarse levels) are searched cell by cell with the fine level's
  // constants: a source that does not depend on the state cancels from FAS's coarse
  // equations, whatever they evaluate.
  void normalise(const Communicator& comm, const Grid& g);
  // The disk's volume on g's cells as normalise found it (the cut cells' shares counted).
  Real disk_volume() const { return disk_volume_; }

  // R_c -= V_c f_c over the block's cells inside the disk.
  void add_to_residual(const Block& b, const GhostArray<State>& Q, GhostArray<State>& R) const override;

  // The disk carried with a grid in rigid motion (motion/grid_motion.hpp): its centre to
  // pose.apply(x_p), its axis turned with the pose. The grid's cells keep their shares of
  // the disk and their volumes under a rigid motion, so the normalisation stands; a grid
  // that deforms near the disk must be normalised again.
  void place(const RigidPose& pose, const Vec3& pivot);
  const Vec3& centre() const { return centre_; }  // x_p now
  const Vec3& axis() const { return axis_; }      // e_a now

  // The loads on the vehicle about x_O (§9.5): F = T e_a, M = (x_p - x_O) x F - Q w_p.
  Vec3 vehicle_force() const;
  Vec3 vehicle_moment(const Vec3& moment_centre) const;

 private:
  // A cell's part of the disk: the means over its sub-points of the axial shape and of
  // the tangential shape times e_theta (zero at points outside the disk).
  struct CellShare {
    Real fraction = 0.0;  // of its sub-points inside the disk
    Real axial = 0.0;
    Vec3 tangential = Vec3::Zero();
  };
  // A disk cell of a block normalise() saw; its tangential share in the axes as built.
  struct DiskCell {
    Index3 cell;
    Real axial = 0.0;
    Vec3 tangential_as_built = Vec3::Zero();
  };
  struct BlockDiskCells {
    Index3 size;  // the block's cells, checked on use
    std::vector<DiskCell> cells;
  };
  // Of the disk (at its present place), or of the annulus like it centred at `centre`.
  std::optional<CellShare> share(const Block& b, int i, int j, int k, const Vec3& centre) const;
  std::optional<CellShare> share(const Block& b, int i, int j, int k) const { return share(b, i, j, k, centre_); }
  void set_advance_speed(Real advance_speed);  // J, K_T, K_Q, T, Q and the scales
  Vec3 spin() const { return static_cast<Real>(spec_.rotation) * axis_; }
  void update_scales();  // the force per volume per unit shape, from T, Q and the integrals
  // V_c f_c of a cell with these shares (tangential in the present axes), §9.4.
  Vec3 cell_force(Real volume, Real axial, const Vec3& tangential) const;

  PropulsorSpec spec_;
  std::shared_ptr<const OpenWaterCurve> curve_;
  Vec3 centre_, axis_;                           // x_p and e_a now (placed with the grid)
  Mat3 turn_ = Mat3::Identity();                 // from the axes as built to the present ones
  std::unordered_map<const Block*, BlockDiskCells> disk_cells_;  // of the grid normalised on
  PropulsorLoads loads_;
  Real axial_scale_ = 0.0, tangential_scale_ = 0.0;  // force per volume per unit shape
  Real axial_integral_ = 0.0, torque_integral_ = 0.0;  // sum_c V_c axial, sum_c V_c q_c (normalise)
  Real disk_volume_ = 0.0;
  bool normalised_ = false;
  bool inflow_measured_ = false;  // option b's V_A known (measured, or a restart's)
};

}  // namespace narwhal
