#pragma once
// Surface quantities on the body's patches (Patch::body_surface: no-slip walls, §4.5,
// and slip walls, pressure only) and their integrals per patch label.
#include <map>
#include <span>
#include <string>
#include <vector>

#include "mesh/block.hpp"
#include "parallel/communicator.hpp"
#include "physics/flow.hpp"

namespace narwhal {

struct WallFace {
  Vec3 x, n;  // face centroid; unit normal pointing into the fluid
  Real area = 0.0, cp = 0.0, y_plus = 0.0;
  Vec3 cf = Vec3::Zero();  // 2 tau_w (fluid on wall)
};

struct ForceCoefficients {
  Vec3 force = Vec3::Zero();   // C_F = 2 F / A_ref
  Vec3 moment = Vec3::Zero();  // C_M = 2 M / (A_ref L_ref)
  // The pressure part of each (-p n); the friction part is the rest (tau_w), so that
  // the parts add up to the totals exactly as they were summed.
  Vec3 pressure_force = Vec3::Zero();
  Vec3 pressure_moment = Vec3::Zero();
  Vec3 friction_force() const { return force - pressure_force; }
  Vec3 friction_moment() const { return moment - pressure_moment; }
};

// Wall faces grouped by patch label (ghosts must be filled).
std::map<std::string, std::vector<WallFace>> wall_faces(const Grid& g, const FlowField& f, const FlowParams& fp);
// The same into existing lists, reusing their storage (no allocation once warm).
void wall_faces(const Grid& g, const FlowField& f, const FlowParams& fp,
                std::map<std::string, std::vector<WallFace>>& out);

ForceCoefficients integrate_forces(std::span<const WallFace> faces, Real area_ref, Real length_ref,
                                   const Vec3& moment_centre);

// Every group's coefficients over all ranks (faces of the owned blocks, from
// wall_faces), summed block by block in block order: the same on any rank count.
// Collective over `comm`.
std::map<std::string, ForceCoefficients> integrate_forces(const Communicator& comm, const Grid& g,
                                                          const std::map<std::string, std::vector<WallFace>>& faces,
                                                          Real area_ref, Real length_ref, const Vec3& moment_centre);

}  // namespace narwhal
