#pragma once
// restart.h5: everything needed to continue a run bit-for-bit (the state of every
// block, the iteration count, the SER reference norm), with provenance (version,
// git SHA, the case file text) and what it was written for (turbulence model,
// block sizes and extents), all of it guarded by checksums.
//
// Layout: an HDF5 file behind a 4 KiB HDF5 user block (h5py and h5dump open it as
// usual). The user block holds a text header: the format, the file size, a chunk
// size and the CRC-32 of every chunk of the bytes after the user block. Any change
// to the file — a flipped byte, a truncation, appended data — is found before HDF5
// reads a byte of it, and the message says which bytes.
#include <array>
#include <string>
#include <vector>

#include "implicit/cfl_control.hpp"
#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

struct RestartInfo {
  int iteration = 0;
  Real wall_seconds = 0.0;
  Real turbulence_reference[2] = {-1.0, -1.0};  // first residuals of the turbulence model's variables
  Real body_force = -1.0;  // magnitude of a flow-rate-controlled body force (< 0: none)
  std::string turbulence_model = "laminar";
  // The monitors of the iteration that produced the state, so that a run resumed from
  // a restart written at its end (converged, or at the limit) reports exactly what the
  // uninterrupted run did without iterating again.
  std::array<Real, 4> residual{};  // RMS residual per equation (IterationNorms::l2)
  std::array<Real, 4> residual_reference{-1.0, -1.0, -1.0, -1.0};  // the largest so far, per equation
  Real residual_total = 0.0;
  Real cfl = 0.0;
  // The CFL controller (dataset cfl_control). Restarts written before it had the reference
  // norm as an attribute, the last CFL as the monitors', no cut and no ceiling, or the cut
  // and the ceiling as pieces of their own: all still read.
  CflControlState cfl_control{};
  Real residual_drop = 1.0;                  // |R| / |R_0| of the mean flow
  std::array<Real, 2> turbulence_residual{};  // the model's residuals
  Real turbulence_drop = 0.0;                 // the largest drop of the model's residuals
  // The stall detector's anchor and the iteration it was set (app/stall_detector.hpp);
  // anchor < 0: none (also for restarts written before the detector existed).
  Real stall_anchor = -1.0;
  int stall_anchor_iteration = 0;
  // The force-steadiness window (app/force_steadiness.hpp), flattened oldest first,
  // and the components per sample; empty: none (also for older restarts).
  std::vector<Real> force_window{};
  int force_components = 0;
  // The turbulence model's start (app/turbulence_coupling.hpp): whether the state is
  // still in it, the cycle that ended it (0: none), and its force window as above.
  // Older restarts: not starting.
  bool turbulence_starting = false;
  int turbulence_start_ended = 0;
  std::vector<Real> start_window{};
  int start_components = 0;
  // A dual-time run (app/dual_time.hpp): the physical steps taken, t^n, the last step's
  // dt; its Q^{n-1} is the `previous` field of write/read_restart. 0 steps: a steady state.
  int time_step = 0;
  Real time = 0.0;
  Real time_step_size = 0.0;
  // A moving grid's blocks are checked against the grid as built: their extents there
  // (empty: the grid written is as built).
  std::vector<std::array<double, 6>> reference_extents{};
  // A free body's state (CoupledBody::checkpoint; empty: none).
  std::vector<Real> body_state{};
  // A body-force propulsor's operating point and its rpm controller (app/propulsion_control.hpp),
  // flattened; empty: none (also for older restarts).
  std::vector<Real> propulsor_state{};
  // The control surfaces' angles of the last two levels and the autopilots' state
  // (app/control_surfaces.hpp); empty: none.
  std::vector<Real> control_state{};
};

// Writes atomically (temporary file + rename) so a crash never leaves a torn restart;
// any write error (a full disk) is an Error naming the file.
void write_restart(const std::string& path, const Grid& g, const FlowField& f, const RestartInfo& info,
                   const std::string& case_text, const FlowField* previous = nullptr);

// Verifies the checksums, then reads the state into `f` (allocated for `g`). Refused
// with a message: a corrupt file, another turbulence model than `turbulence_model`,
// another block count, block names, sizes or extents than `g`.
// `previous`: where a dual-time restart's Q^{n-1} goes (allocated for g); a restart of
// a dual-time run read without it, or one without Q^{n-1}, is refused.
RestartInfo read_restart(const std::string& path, const Grid& g, FlowField& f, const std::string& turbulence_model,
                         FlowField* previous = nullptr);

// The checksum layer alone (for tests): throws naming the file and the bytes that
// do not match, or returns quietly.
void verify_restart_checksums(const std::string& path);
// Writes the checksums of the file as it is (for tests that rewrite a restart in an older
// layout).
void stamp_restart_checksums(const std::string& path);

}  // namespace narwhal
