#pragma once
// Plot3D whole multi-block grid files (x, y, z per block, no iblank), in ASCII,
// Fortran-unformatted binary (record markers) or raw C binary, double or single
// precision, detected from the file size. A truncated file is an error that says
// how many bytes were expected.
#include <string>
#include <vector>

#include "mesh/block.hpp"

namespace narwhal {

std::vector<Block> read_plot3d(const std::string& path);

// Writers (used by tests and to export generated grids).
void write_plot3d_ascii(const std::string& path, const std::vector<Block>& blocks);
void write_plot3d_fortran(const std::string& path, const std::vector<Block>& blocks);

}  // namespace narwhal
