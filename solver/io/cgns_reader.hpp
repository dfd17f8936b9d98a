#pragma once
// Structured multiblock CGNS grids made elsewhere (or written by `narwhal grid`):
// the first base's zones become blocks, their nodes the block nodes, and each BC_t
// with a vertex PointRange on one zone face becomes a patch. A patch's label is the
// BC's FamilyName when it has one (Narwhal writes the case label there), otherwise
// the BC's own name; the case's [bc.<label>] tables assign the conditions. 1-to-1
// connections are not read: finalize_grid connects every face whose nodes coincide
// with another block's, which covers them (and a periodic pair is declared by the
// case's [[periodic]] tables). Errors name the file, the zone and the node.
#include <string>
#include <vector>

#include "mesh/block.hpp"

namespace narwhal {

std::vector<Block> read_cgns_grid(const std::string& path);

}  // namespace narwhal
