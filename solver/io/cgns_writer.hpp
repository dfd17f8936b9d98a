#pragma once
// grid.cgns and solution.cgns: one structured zone per block with its nodes, boundary patches
// (BC_t), 1-to-1 connectivity and cell-centred p, u, v, w, for ParaView.
#include <string>
#include <vector>

#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

// The grid alone (zones, patches with their labels as FamilyName, 1-to-1 connections):
// what `narwhal grid` writes and grid.type = "cgns" reads back.
void write_cgns_grid(const std::string& path, const Grid& g);

// `turbulence`: CGNS names of the turbulence model's variables (written from f.turb);
// when the field has a turbulence model, the eddy viscosity nu - 1/Re is written as
// ViscosityEddyKinematic too.
void write_cgns_solution(const std::string& path, const Grid& g, const FlowField& f,
                         const std::vector<std::string>& turbulence = {}, Real nu_laminar = 0.0);

}  // namespace narwhal
