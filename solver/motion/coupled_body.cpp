#include "motion/coupled_body.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "motion/grid_axes.hpp"

namespace narwhal {

RigidBodyState body_state_at_release(const Vec3& origin, const Vec3& velocity, const Vec3& angular_velocity) {
  RigidBodyState s;
  s.attitude() = quaternion_from_euler(EulerAngles{0.0, 0.0, std::numbers::pi});  // R = diag(-1, -1, 1)
  s.position() = origin;
  s.velocity() = grid_to_body_axes(velocity);
  s.angular_velocity() = grid_to_body_axes(angular_velocity);
  return s;
}

CoupledBody::CoupledBody(const MassProperties& mp, const AccelerationOptions& options, const RigidBodyState& initial,
                         const CouplingSettings& settings, std::vector<BallastChange> ballast, TrimSpec trim)
    : body_(mp, options), settings_(settings), ballast_(std::move(ballast)), trim_(trim), pivot_(initial.position()),
      initial_rotation_(rotation_matrix(initial.attitude())), y_n_(initial), estimate_(initial) {
  if (!(settings.relaxation > 0.0 && settings.relaxation <= 1.0))
    fail("coupled body: the relaxation factor must lie in (0, 1], got {}", settings.relaxation);
  if (!(settings.tolerance > 0.0)) fail("coupled body: the coupling tolerance must be positive, got {}", settings.tolerance);
  if (trim.any() && !(mp.weight > 0.0)) fail("coupled body: trimming by weights needs gravity");
}

BodyLoads CoupledBody::to_body_axes(const BodyLoads& earth) const {
  const Mat3 rt = rotation_matrix(estimate_.attitude()).transpose();
  return {rt * earth.force, rt * earth.moment};
}

Vec3 CoupledBody::down_body(const RigidBodyState& at) const {
  return rotation_matrix(at.attitude()).transpose() * body_.mass_properties().down;
}

void CoupledBody::observe_initial_loads(const BodyLoads& flow_earth) {
  f_latest_ = to_body_axes(flow_earth);
  if (steps_ == 0) find_trim();
}

void CoupledBody::find_trim() {
  trim_weights_ = trim_.any() ? trim_at_release(trim_, body_, estimate_, f_latest_) : TrimWeights{};
}

RigidBodyStep CoupledBody::rk4_pass(const BodyLoads& f_next) {
  // §11.6's interpolation of the flow loads, each stage plus M_A times its acceleration
  // of the previous pass (§11.7's preconditioner; nothing when M_A = 0).
  const Mat6& ma = body_.options().added_mass_estimate;
  // The first step after release takes its end's loads throughout: releasing makes the
  // accelerations, and with them the added-mass part of the loads, jump at t^0, which
  // an interpolation from F^0 would smear over the step (a body started impulsively
  // would keep half its momentum too much).
  const BodyLoads& f_start = steps_ == 1 ? f_next : f_n_;
  const BodyLoads f_mid = 0.5 * (f_start + f_next);
  std::array<BodyLoads, 4> stage{f_start, f_mid, f_mid, f_next};
  for (int s = 0; s < 4; ++s) {
    const Vec6 extra = ma * stage_acc_[s];
    stage[s] += BodyLoads{extra.head<3>(), extra.tail<3>()};
  }
  StateDependentLoads ballast = nullptr;
  if (!ballast_.empty() || trim_.any())
    ballast = [this](const RigidBodyState& at, Real t) {
      const Vec3 down = down_body(at);
      return ballast_loads(ballast_, down, t) + trim_weights_.loads(down);
    };
  RigidBodyStep st = advance_rk4_stages(body_, y_n_, time_, step_, stage, ballast, &stage_acc_);
  // The flow's kinematics (see the header): the step's displacement and turn from the
  // new velocities in earth axes.
  RigidBodyState& y = st.state;
  const Mat3 r = rotation_matrix(y.attitude());
  const Vec3 dx = (step_ * (r * Vec3(y.velocity())) + bdf_.c2 * dx_n_) / bdf_.c0;
  const Vec3 dphi = (step_ * (r * Vec3(y.angular_velocity())) + bdf_.c2 * dphi_n_) / bdf_.c0;
  y.position() = Vec3(y_n_.position()) + dx;
  const Real angle = dphi.norm();
  const Mat3 turn = angle > 0.0 ? Mat3(Eigen::AngleAxis<Real>(angle, dphi / angle)) : Mat3::Identity();
  y.attitude() = quaternion_from_rotation(turn * rotation_matrix(y_n_.attitude()));
  return st;
}

void CoupledBody::begin_step(Real time, Real step, const BdfCoefficients& c) {
  // The step that ended: its displacement and turn (the BDF2 kinematics' dx^n, dphi^n).
  dx_n_ = Vec3(estimate_.position()) - Vec3(y_n_.position());
  const Eigen::AngleAxis<Real> turned(rotation_matrix(estimate_.attitude()) *
                                      rotation_matrix(y_n_.attitude()).transpose());
  dphi_n_ = turned.angle() * turned.axis();
  bdf_ = c;
  y_n_ = estimate_;
  f_nm1_ = f_n_;
  f_n_ = f_latest_;
  time_ = time;
  step_ = step;
  // F^{n+1,*} = 2 F^n - F^{n-1} once F^{n-1} is known (from the second step on).
  const BodyLoads predicted = steps_ >= 1 ? 2.0 * f_n_ + (-1.0) * f_nm1_ : f_n_;
  ++steps_;
  const RigidBodyStep st = rk4_pass(predicted);
  estimate_ = st.state;
  norm_error_ = st.quaternion_norm_error;
}

Real CoupledBody::correct(const BodyLoads& flow_earth) {
  f_latest_ = to_body_axes(flow_earth);
  const RigidBodyStep st = rk4_pass(f_latest_);
  norm_error_ = st.quaternion_norm_error;
  const RigidBodyVector before = estimate_.y;
  estimate_.y += settings_.relaxation * (st.state.y - estimate_.y);
  estimate_.attitude().normalize();
  return (estimate_.y.head<6>() - before.head<6>()).cwiseAbs().maxCoeff();
}

RigidMotionSample motion_sample(const RigidBodyState& s, const Mat3& initial_rotation, const Vec3& pivot) {
  const Mat3 r = rotation_matrix(s.attitude());
  RigidMotionSample m;
  m.pose.rotation = r * initial_rotation.transpose();
  m.pose.displacement = Vec3(s.position()) - pivot;
  m.velocity = r * Vec3(s.velocity());
  m.angular_velocity = r * Vec3(s.angular_velocity());
  return m;
}

RigidMotionSample CoupledBody::sample(const RigidBodyState& s) const { return motion_sample(s, initial_rotation_, pivot_); }

EulerAngles CoupledBody::turn_since_release(const RigidBodyState& s) const {
  return euler_from_quaternion(quaternion_from_rotation(initial_rotation_.transpose() * rotation_matrix(s.attitude())));
}

std::vector<Real> CoupledBody::checkpoint() const {
  std::vector<Real> v;
  auto put = [&](const auto& x) {
    for (Eigen::Index i = 0; i < x.size(); ++i) v.push_back(x[i]);
  };
  put(y_n_.y);
  put(estimate_.y);
  for (const BodyLoads* f : {&f_n_, &f_nm1_, &f_latest_}) {
    put(f->force);
    put(f->moment);
  }
  for (const Vec6& a : stage_acc_) put(a);
  v.push_back(static_cast<Real>(steps_));
  v.push_back(time_);
  v.push_back(step_);
  v.push_back(trim_weights_.weight);
  v.push_back(trim_weights_.first_moment);
  return v;
}

void CoupledBody::restore(const std::vector<Real>& v) {
  const std::size_t expected = 2 * 13 + 3 * 6 + 4 * 6 + 3 + 2;
  if (v.size() != expected)
    fail("restart: the body's state has {} values, this build expects {}", v.size(), expected);
  std::size_t at = 0;
  auto get = [&](auto& x) {
    for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = v[at++];
  };
  get(y_n_.y);
  get(estimate_.y);
  for (BodyLoads* f : {&f_n_, &f_nm1_, &f_latest_}) {
    get(f->force);
    get(f->moment);
  }
  for (Vec6& a : stage_acc_) get(a);
  steps_ = static_cast<int>(v[at++]);
  time_ = v[at++];
  step_ = v[at++];
  trim_weights_.weight = v[at++];
  trim_weights_.first_moment = v[at++];
}

}  // namespace narwhal
