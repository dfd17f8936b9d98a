#pragma once
// The machinery shared by the transport-equation models (SA, k-epsilon, SST),
// NUMERICS §8.6:
// - convection: first-order upwind with the mean flow's numerical volume flux
//   U_f = F_1/beta + k_t of the same face, so a uniform variable stays uniform
//   wherever the discrete continuity equation holds;
// - diffusion: thin-layer, coefficient averaged to the face from the cells (or per
//   side, for SA's non-conservative cb2 form);
// - sources: point values from the model; only their destruction part enters the
//   implicit diagonal;
// - one Newton step per iteration, relaxed by symmetric line or point Gauss-Seidel
//   (TurbulenceSettings::smoother; 2x2 point blocks); block interfaces lag by one
//   iteration, as in the mean flow. Why lines: turbulence/DESIGN.md.
// Boundary ghosts: wall 2 phi_w - phi_1 (phi_w from the model), symmetry and
// outflow zero gradient, far field / inflow the free stream where the flow enters.
#include <algorithm>
#include <array>

#include "implicit/line_solver.hpp"
#include "turbulence/model.hpp"

namespace narwhal {

// What a model's point sources see of a cell.
struct CellFlow {
  Mat3 grad_u;       // grad_u(i, j) = d u_i / d x_j (Green-Gauss, §8.1)
  Real d = 0.0;      // wall distance (+inf without walls)
  Real nu = 0.0;     // laminar kinematic viscosity 1/Re
  Eigen::Matrix<Real, 3, 2> grad_phi;  // gradients of the model variables
  // Gradient of sign(phi_0) sqrt(|phi_0|) (k-epsilon's D = 2 nu |grad sqrt k|^2): the
  // signed root makes the wall ghost -sqrt(k_1) put sqrt(k) = 0 on the wall face.
  Vec3 grad_sqrt_phi0 = Vec3::Zero();
  Real u_tau = 0.0;  // friction velocity at the nearest wall face (models that ask for it)
  Real hessian_u2 = 0.0;  // sum over i, j, l of (d2 u_i / dx_j dx_l)^2 (models that ask for it)
};

struct PointSource {
  TurbState value = TurbState::Zero();     // S per unit volume
  TurbState implicit = TurbState::Zero();  // >= 0: -dS/dphi of the destruction part
};

class TransportModel : public TurbulenceModel {
 public:
  TransportModel(const TurbulenceSettings& s, const Grid& g, const Communicator& comm);

  void initialize(const Grid& g, FlowField& f, const FlowParams& fp, bool keep) override;
  TurbulenceNorms advance(Grid& g, FlowField& f, const FlowParams& fp, Real cfl) override;
  void set_update(Real relaxation, int iterations) override {
    settings_.relaxation = relaxation;
    settings_.iterations = iterations;
  }
  void update_viscosity(const Grid& g, FlowField& f, const FlowParams& fp) override;
  Real eddy_viscosity(const FlowField& f, const FlowParams& fp, int ib, const Index3& c) const override;
  std::string describe_largest_residual(const Grid& g, int m, const Communicator& comm) const override;

  void use_physical_time(const PhysicalTimeTerm* term) override { time_ = term; }
  void walls_moved(const Grid& g) override { wall_ = compute_wall_distance(g); }

  const WallDistance& walls() const { return wall_; }

 protected:
  virtual TurbState freestream(Real nu) const = 0;
  // At the wall face; d1: the wall cell centre's distance, phi1: its values.
  virtual TurbState wall_value(Real nu, Real d1, const TurbState& phi1) const = 0;
  // Second derivatives of the velocity (Launder-Sharma's E term): Green-Gauss applied
  // to face-averaged cell gradients (§8.3).
  virtual bool needs_velocity_hessian() const { return false; }
  // Two-variable models whose sources couple strongly (k-epsilon): 2x2 point-implicit
  // source Jacobian in the relaxation instead of scalar diagonals.
  virtual bool coupled_sources() const { return false; }
  bool coupled() const { return num_variables() == 2 && coupled_sources(); }
  // u_tau of the nearest wall face in CellFlow (Myong-Kasagi's y+ damping).
  virtual bool needs_friction_velocity() const { return false; }
  // Gradient of sqrt(k) (CellFlow::grad_sqrt_phi0), for Launder-Sharma's D term.
  virtual bool needs_root_gradient() const { return false; }
  // Per-cell auxiliary values computed once per iteration from the cell's flow
  // (SST: the blending F1 and nu_t); passed to the diffusivities. Default: none.
  virtual TurbState cell_aux(const TurbState& /*phi*/, const CellFlow& /*c*/) const { return TurbState::Zero(); }
  virtual TurbState diffusivity(const TurbState& phi, Real nu, const TurbState& aux) const = 0;
  // Diffusion coefficients of a face as seen by its left and right cells (equal for
  // a conservative term; SA's cb2 form differs per side). Default: the face average
  // of `diffusivity` for both.
  struct FaceDiffusivity {
    TurbState left, right;
  };
  virtual FaceDiffusivity face_diffusivity(const TurbState& phiL, const TurbState& phiR, Real nu,
                                           const TurbState& auxL, const TurbState& auxR) const {
    const TurbState g = 0.5 * (diffusivity(phiL, nu, auxL) + diffusivity(phiR, nu, auxR));
    return {g, g};
  }
  virtual PointSource source(const TurbState& phi, const CellFlow& c) const = 0;
  TurbState sustaining_source(const TurbState& inf, const CellFlow& c) const;
  virtual Real nut(const TurbState& phi, const CellFlow& c) const = 0;
  // Models with a non-linear Reynolds stress (§8.5): its cell value from the cell's
  // variables and nu_t, stored in FlowField::tau_nl whenever nu_t is updated.
  virtual bool has_nonlinear_stress() const { return false; }
  virtual Mat3 cell_nonlinear_stress(const TurbState& /*phi*/, const CellFlow& /*c*/, Real /*nu_t*/) const {
    return Mat3::Zero();
  }
  // The update actually applied (positivity, §8.6); default: as computed.
  virtual TurbState limit_update(const TurbState& /*phi*/, const TurbState& dphi) const { return dphi; }
  // §8.6 positivity for k, epsilon, omega: a step that would make a variable
  // negative halves it instead. Growth is capped at the factor
  // settings_.max_growth per step (see TurbulenceSettings).
  TurbState keep_positive(const TurbState& phi, const TurbState& dphi) const {
    TurbState d = dphi;
    for (int m = 0; m < 2; ++m) {
      if (phi[m] + d[m] <= 0.0) d[m] = -0.5 * phi[m];
      d[m] = std::min(d[m], (settings_.max_growth - 1.0) * std::max(phi[m], 0.0));
    }
    return d;
  }

  TurbulenceSettings settings_;

 private:
  void fill_scalar_ghosts(Grid& g, FlowField& f, const FlowParams& fp) const;
  // Collective over comm_: each rank measures its own wall faces, the sum gathers all.
  void gather_friction_velocity(const Grid& g, const FlowField& f, const FlowParams& fp);
  CellFlow cell_flow(const Block& b, int ib, const FlowField& f, const FlowParams& fp, const Index3& c,
                     bool for_sources) const;  // false: what nu_t needs only (no gradients of phi, no Hessian)

  // The phases of advance().
  void compute_volume_fluxes(const Grid& g, const FlowField& f, const FlowParams& fp);
  void compute_velocity_gradients(const Grid& g, const FlowField& f);
  void compute_cell_data(const Grid& g, const FlowField& f, const FlowParams& fp);
  TurbulenceNorms assemble(const Grid& g, const FlowField& f, const FlowParams& fp, Real cfl_t);
  FaceDiffusivity face_coefficients(const Block& b, int ib, const FlowField& f, const FlowParams& fp, int d,
                                    const Index3& cL, const Index3& cR, const Index3& fi) const;
  void assemble_interior_faces(const Block& b, int ib, const FlowField& f, const FlowParams& fp);
  void assemble_boundary_faces(const Block& b, int ib, const FlowField& f, const FlowParams& fp);
  void assemble_sources(const Block& b, int ib, const FlowField& f, const FlowParams& fp, Real cfl_t, Real* sums);
  void relax(const Grid& g);
  struct Work;
  void sweep_lines(const Block& b, Work& w, bool forward) const;
  void invert_point_blocks(const Block& b, Work& w) const;
  void sweep_points(const Block& b, Work& w, bool forward) const;
  void apply_update(const Grid& g, FlowField& f);

  Communicator comm_;
  WallDistance wall_;
  const PhysicalTimeTerm* time_ = nullptr;  // dual time: the variables' physical-time term
  std::vector<Real> u_tau_;  // per wall face (WallDistance::faces order), when the model needs it
  // Per block: face volume fluxes per direction, residual, implicit diagonal and
  // off-diagonal coefficients per face (dR_R/dphi_L and dR_L/dphi_R), correction.
  struct Work {
    std::array<GhostArray<Real>, 3> U;
    std::array<GhostArray<TurbState>, 3> aL, aR;
    GhostArray<TurbState> R, D, dphi;
    GhostArray<TurbState> Dx;        // off-diagonal point-block entries (0,1), (1,0) from wall BCs (coupled() only)
    GhostArray<Eigen::Matrix2d> M;   // 2x2 point blocks: D, plus the source couplings (coupled())
    GhostArray<Eigen::Matrix2d> M_inv;  // their inverses (point smoother, coupled() only)
    int line_dir = 0;                // direction of the relaxation's lines (stiffest_direction)
    LineFactorization<2> lines;      // their factorization (smoother "lines")
    GhostArray<Real> lam;         // spectral radius of the cell's faces (pseudo-time term)
    GhostArray<CellFlow> flow;    // the cells' flow data of the current iteration (aux and sources)
  };
  std::vector<Work> work_;
  // Per-block arrays with one ghost layer, filled across interfaces by the halo
  // exchange (hence not in Work): the model's auxiliary cell values, and the cell
  // velocity gradients (when the model needs the Hessian).
  std::vector<GhostArray<TurbState>> aux_;
  std::vector<GhostArray<Mat3>> grad_u_;
};

}  // namespace narwhal
