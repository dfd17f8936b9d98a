#include "mesh/plot3d.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.hpp"

namespace narwhal {
namespace {

std::vector<char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail("grid file '{}' does not exist or cannot be read", path);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

bool looks_ascii(const std::vector<char>& d) {
  const std::size_t n = std::min<std::size_t>(d.size(), 4096);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(d[i]);
    if (!(std::isspace(c) || std::isdigit(c) || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E' ||
          c == 'd' || c == 'D'))
      return false;
  }
  return true;
}

Block make_block(int ib, int ni, int nj, int nk) {
  if (ni < 2 || nj < 2 || nk < 2)
    fail("plot3d block {}: node counts {}x{}x{} must all be >= 2", ib + 1, ni, nj, nk);
  return Block(fmt::format("block{}", ib + 1), ni - 1, nj - 1, nk - 1);
}

std::vector<Block> read_ascii(const std::string& path, const std::vector<char>& d) {
  std::string s(d.begin(), d.end());
  for (auto& c : s)
    if (c == 'd' || c == 'D') c = 'e';
  std::istringstream in(s);
  int nb = 0;
  if (!(in >> nb) || nb < 1) fail("plot3d '{}': cannot read the block count", path);
  std::vector<Index3> dims(nb);
  for (int b = 0; b < nb; ++b)
    if (!(in >> dims[b][0] >> dims[b][1] >> dims[b][2]))
      fail("plot3d '{}': truncated header (block {} dimensions)", path, b + 1);
  std::vector<Block> out;
  for (int b = 0; b < nb; ++b) {
    Block blk = make_block(b, dims[b][0], dims[b][1], dims[b][2]);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k <= blk.nk; ++k)
        for (int j = 0; j <= blk.nj; ++j)
          for (int i = 0; i <= blk.ni; ++i)
            if (!(in >> blk.x(i, j, k)[c]))
              fail("plot3d '{}': truncated file: block {} coordinate {} ends at node ({}, {}, {})", path, b + 1,
                   "xyz"[c], i, j, k);
    out.push_back(std::move(blk));
  }
  return out;
}

template <class T>
T read_at(const std::vector<char>& d, std::size_t off) {
  T v;
  std::memcpy(&v, d.data() + off, sizeof(T));
  return v;
}

std::vector<Block> read_binary(const std::string& path, const std::vector<char>& d) {
  if (d.size() < 8) fail("plot3d '{}': truncated file ({} bytes)", path, d.size());
  // Fortran unformatted: [4][nb][4][12*nb][dims][12*nb] then one record per block.
  const bool fortran = read_at<int32_t>(d, 0) == 4 && d.size() >= 12 && read_at<int32_t>(d, 8) == 4;
  std::size_t off = fortran ? 4 : 0;
  const int nb = read_at<int32_t>(d, off);
  off += 4 + (fortran ? 8 : 0);
  if (nb < 1 || nb > 100000) fail("plot3d '{}': implausible block count {}", path, nb);
  if (d.size() < off + 12 * static_cast<std::size_t>(nb)) fail("plot3d '{}': truncated header", path);
  std::vector<Index3> dims(nb);
  std::size_t nodes_total = 0;
  for (int b = 0; b < nb; ++b) {
    for (int c = 0; c < 3; ++c) dims[b][c] = read_at<int32_t>(d, off + 12 * b + 4 * c);
    nodes_total += static_cast<std::size_t>(dims[b][0]) * dims[b][1] * dims[b][2];
  }
  off += 12 * static_cast<std::size_t>(nb) + (fortran ? 4 : 0);
  const std::size_t markers = fortran ? 8 * static_cast<std::size_t>(nb) : 0;
  const std::size_t remaining = d.size() - off;
  std::size_t word = 0;
  if (remaining == 3 * nodes_total * 8 + markers) word = 8;
  else if (remaining == 3 * nodes_total * 4 + markers) word = 4;
  else
    fail("plot3d '{}': truncated or malformed file: {} bytes of coordinates, expected {} (double) or {} (single) "
         "for {} nodes",
         path, remaining, 3 * nodes_total * 8 + markers, 3 * nodes_total * 4 + markers, nodes_total);
  std::vector<Block> out;
  for (int b = 0; b < nb; ++b) {
    Block blk = make_block(b, dims[b][0], dims[b][1], dims[b][2]);
    if (fortran) off += 4;
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k <= blk.nk; ++k)
        for (int j = 0; j <= blk.nj; ++j)
          for (int i = 0; i <= blk.ni; ++i) {
            blk.x(i, j, k)[c] = word == 8 ? read_at<double>(d, off) : read_at<float>(d, off);
            off += word;
          }
    if (fortran) off += 4;
    out.push_back(std::move(blk));
  }
  return out;
}

}  // namespace

std::vector<Block> read_plot3d(const std::string& path) {
  const auto d = slurp(path);
  if (d.empty()) fail("plot3d '{}': the file is empty", path);
  return looks_ascii(d) ? read_ascii(path, d) : read_binary(path, d);
}

void write_plot3d_ascii(const std::string& path, const std::vector<Block>& blocks) {
  std::ofstream out(path);
  out << blocks.size() << "\n";
  for (const auto& b : blocks) out << b.ni + 1 << " " << b.nj + 1 << " " << b.nk + 1 << "\n";
  out.precision(17);
  for (const auto& b : blocks)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k <= b.nk; ++k)
        for (int j = 0; j <= b.nj; ++j)
          for (int i = 0; i <= b.ni; ++i) out << b.x(i, j, k)[c] << "\n";
}

void write_plot3d_fortran(const std::string& path, const std::vector<Block>& blocks) {
  std::ofstream out(path, std::ios::binary);
  auto w32 = [&](int32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
  w32(4);
  w32(static_cast<int32_t>(blocks.size()));
  w32(4);
  w32(static_cast<int32_t>(12 * blocks.size()));
  for (const auto& b : blocks) {
    w32(b.ni + 1);
    w32(b.nj + 1);
    w32(b.nk + 1);
  }
  w32(static_cast<int32_t>(12 * blocks.size()));
  for (const auto& b : blocks) {
    const int32_t bytes = static_cast<int32_t>(3 * 8 * (b.ni + 1) * (b.nj + 1) * (b.nk + 1));
    w32(bytes);
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k <= b.nk; ++k)
        for (int j = 0; j <= b.nj; ++j)
          for (int i = 0; i <= b.ni; ++i) out.write(reinterpret_cast<const char*>(&b.x(i, j, k)[c]), 8);
    w32(bytes);
  }
}

}  // namespace narwhal
