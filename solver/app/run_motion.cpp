#include "app/run_motion.hpp"

#include "core/error.hpp"

namespace narwhal {

RunMotion::RunMotion(const CaseConfig& c, const std::vector<Grid*>& grids, std::size_t described)
    : described_(described) {
  if (described >= grids.size()) fail("internal: RunMotion: grid {} of {} described", described, grids.size());
  if (c.free_body) {
    const FreeBodySpec& f = *c.free_body;
    body_ = std::make_unique<CoupledBody>(f.mass, f.options,
                                          body_state_at_release(f.origin, f.velocity, f.angular_velocity), f.coupling,
                                          f.ballast, f.trim);
    pivot_ = body_->pivot();
  } else {
    prescribed_ = std::make_unique<PrescribedMotion>(*c.motion);
    pivot_ = prescribed_->pivot();
  }
  for (Grid* g : grids) moving_.push_back(std::make_unique<MovingGrid>(*g, pivot_));
}

RigidMotionSample RunMotion::present() const {
  return body_ ? body_->sample(body_->state()) : prescribed_->sample(time_);
}

void RunMotion::move_all(const RigidMotionSample& m, Real dt, const BdfCoefficients& c, bool new_step) {
  for (auto& g : moving_) g->move_to(m, dt, c, new_step);
}

void RunMotion::place_at_start() {
  time_ = 0.0;
  for (auto& g : moving_) g->place_at(present().pose);
}

void RunMotion::start(const BodyLoads& loads) {
  if (body_) body_->observe_initial_loads(loads);
}

void RunMotion::begin_step(Real t_n, Real dt, const BdfCoefficients& c) {
  time_ = t_n + dt;
  if (body_) body_->begin_step(t_n, dt, c);
  move_all(present(), dt, c, true);
}

Real RunMotion::correct(const BodyLoads& loads, Real dt, const BdfCoefficients& c) {
  const Real change = body_->correct(loads);
  move_all(present(), dt, c, false);
  return change;
}

void RunMotion::reshape_all(std::vector<std::vector<GhostArray<Vec3>>> shapes) {
  if (shapes.size() != moving_.size())
    fail("internal: {} grid shapes for the run's {} moving grids", shapes.size(), moving_.size());
  for (std::size_t i = 0; i < moving_.size(); ++i) moving_[i]->reshape(std::move(shapes[i]));
}

Vec3 RunMotion::now(const Vec3& as_built) const { return present().pose.apply(as_built, pivot_); }

std::vector<Real> RunMotion::checkpoint() const { return body_ ? body_->checkpoint() : std::vector<Real>{}; }

void RunMotion::place_at_previous_level(const RestartInfo& info, Real dt) {
  RigidPose previous;
  if (body_) {
    if (info.body_state.empty())
      fail("restart: it holds no free body's state (written by a run without [motion] type = \"free\")");
    body_->restore(info.body_state);
    previous = body_->sample(body_->start_of_step()).pose;
  } else {
    previous = prescribed_->pose(info.time - dt);
  }
  for (auto& g : moving_) g->place_at(previous);
}

void RunMotion::move_to_present_level(const RestartInfo& info, Real dt, const BdfCoefficients& c) {
  time_ = info.time;
  move_all(present(), dt, c, true);
}

}  // namespace narwhal
