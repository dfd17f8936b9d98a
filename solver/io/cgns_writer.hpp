#pragma once
// solution.cgns: one structured zone per block with its nodes, boundary patches
// (BC_t), 1-to-1 connectivity and cell-centred p, u, v, w, for ParaView.
#include <string>

#include "mesh/block.hpp"
#include "physics/flow.hpp"

namespace narwhal {

void write_cgns_solution(const std::string& path, const Grid& g, const FlowField& f);

}  // namespace narwhal
