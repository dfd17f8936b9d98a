#pragma once
// Monitor files the validation harness reads: history.csv (one row per
// iteration) and surface_<group>.csv (one row per wall face).
#include <cstdio>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "implicit/newton.hpp"
#include "motion/rigid_body.hpp"
#include "physics/wall_forces.hpp"

namespace narwhal {

// A monitor file written a row at a time, each row whole and flushed at once: a killed
// run leaves whole rows (and at most one torn last row). With `resume_after` (a run
// continuing from a restart written at that iteration or step, the first column) the
// existing file is cut back to its complete rows up to it, so the continued file has
// each row once, in order. A failed write is an Error naming the file.
class AppendedCsv {
 public:
  AppendedCsv(const std::string& path, const std::string& header, std::optional<int> resume_after);
  ~AppendedCsv();
  AppendedCsv(const AppendedCsv&) = delete;
  AppendedCsv& operator=(const AppendedCsv&) = delete;
  void append(const std::string& row);

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
};

// history.csv: one row per iteration (or multigrid cycle). `turbulence`: names of the
// turbulence model's variables (a residual column each).
class HistoryWriter {
 public:
  HistoryWriter(const std::string& path, const std::vector<std::string>& groups,
                const std::vector<std::string>& turbulence, std::optional<int> resume_after);
  void write(int iteration, Real wall_seconds, const IterationNorms& n,
             const std::map<std::string, ForceCoefficients>& forces, const std::vector<Real>& turbulence = {});

 private:
  std::vector<std::string> groups_;
  std::size_t turbulence_ = 0;
  AppendedCsv file_;
};

// propulsor.csv of a run with a propulsor (app/propulsion_control.hpp): one row per
// iteration after the controller's step: the rotation rate and advance speed the next
// iteration uses, its J, T and Q, and the walls' resistance along the thrust axis
// (nondimensional, rho = U = 1).
class PropulsorWriter {
 public:
  PropulsorWriter(const std::string& path, std::optional<int> resume_after);
  void write(int iteration, Real rps, Real advance_speed, Real advance_ratio, Real thrust, Real torque,
             Real resistance);

 private:
  AppendedCsv file_;
};

// steps.csv of a dual-time run: one row per physical step (step, time t^{n+1}, the
// sub-iterations it took, the drop |R*| / |R*_0| they reached, each wall group's force
// and moment coefficients at the step's end).
class StepsWriter {
 public:
  StepsWriter(const std::string& path, const std::vector<std::string>& groups, std::optional<int> resume_after);
  void write(int step, Real time, int subiterations, Real drop, const std::map<std::string, ForceCoefficients>& forces);

 private:
  std::vector<std::string> groups_;
  AppendedCsv file_;
};

// motion.csv of a run with a free body (motion/coupled_body.hpp): one row per physical
// step, at its end. Position of the body origin O (grid coordinates), the quaternion
// (body -> grid axes), the Euler angles (degrees) of the body's turn from its axes at
// t = 0 (grid_axes.hpp's: z_B along z; NUMERICS §11.4's ZYX order), the velocities u, v,
// w, p, q, r in body axes, the flow's force X, Y, Z and moment K, M, N about O in body
// axes (flow units), the step's sub-iterations and the last correction's velocity change.
class MotionWriter {
 public:
  MotionWriter(const std::string& path, std::optional<int> resume_after);
  void write(int step, Real time, const RigidBodyState& s, const EulerAngles& turned, const BodyLoads& flow,
             int subiterations, Real coupling_change);

 private:
  AppendedCsv file_;
};

// controls.csv of a run that turns its control surfaces (app/control_surfaces.hpp): one row
// per physical step, the angles it ended with (degrees, suboff_geometry.hpp's signs) and
// the autopilots' pitch command (degrees; 0 without one).
class ControlsWriter {
 public:
  ControlsWriter(const std::string& path, std::optional<int> resume_after);
  void write(int step, Real time, Real rudder, Real stern_planes, Real sail_planes, Real pitch_command);

 private:
  AppendedCsv file_;
};

// The first line of history.csv for these wall groups and turbulence variables.
std::string history_header(const std::vector<std::string>& groups, const std::vector<std::string>& turbulence);

// Written whole or not at all (io/text_file.hpp).
// cf_signed: |tau_w| with the sign of its x component, as NASA TMR reports Cf.
void write_surface_csv(const std::string& path, const std::vector<WallFace>& faces);

}  // namespace narwhal
