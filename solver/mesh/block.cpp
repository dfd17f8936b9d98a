#include "mesh/block.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "mesh/ghost_sweep.hpp"

namespace narwhal {

const char* to_string(BcType t) {
  switch (t) {
    case BcType::Wall: return "wall";
    case BcType::Farfield: return "farfield";
    case BcType::Inflow: return "inflow";
    case BcType::Outflow: return "outflow";
    case BcType::Symmetry: return "symmetry";
    case BcType::Dirichlet: return "dirichlet";
    case BcType::Interface: return "interface";
  }
  return "?";
}

const char* side_name(int side) {
  static const char* names[6] = {"imin", "imax", "jmin", "jmax", "kmin", "kmax"};
  return (side >= 0 && side < 6) ? names[side] : "?";
}

int parse_side(const std::string& s) {
  for (int i = 0; i < 6; ++i)
    if (s == side_name(i)) return i;
  return -1;
}

void check_block_size(const std::string& where, std::int64_t ci, std::int64_t cj, std::int64_t ck) {
  if (ci < 1 || cj < 1 || ck < 1) fail("{}: cell counts must be >= 1, got {}x{}x{}", where, ci, cj, ck);
  if (ci > kMaxCellsPerDirection || cj > kMaxCellsPerDirection || ck > kMaxCellsPerDirection)
    fail("{}: {}x{}x{} cells: at most {} per direction", where, ci, cj, ck, kMaxCellsPerDirection);
  if (ci * cj * ck > kMaxBlockCells)
    fail("{}: {}x{}x{} = {} cells: at most {} in one block", where, ci, cj, ck, ci * cj * ck, kMaxBlockCells);
}

Block::Block(std::string block_name, int ci, int cj, int ck)
    : name(std::move(block_name)), ni(ci), nj(cj), nk(ck) {
  check_block_size(fmt::format("block '{}'", name), ci, cj, ck);
  x.resize(ni + 1, nj + 1, nk + 1, kGhost, Vec3::Zero());
  for (int d = 0; d < 3; ++d) {
    Index3 n = dims();
    n[d] += 1;
    S[d].resize(n[0], n[1], n[2], kGhost, Vec3::Zero());
    xf[d].resize(n[0], n[1], n[2], kGhost, Vec3::Zero());
    kt[d].resize(n[0], n[1], n[2], kGhost, 0.0);
  }
  vol.resize(ni, nj, nk, kGhost, 0.0);
  xc.resize(ni, nj, nk, kGhost, Vec3::Zero());
}

std::size_t Grid::cells() const {
  std::size_t n = 0;
  for (const auto& b : blocks) n += b.cells();
  return n;
}

Index3 Interface::map_node(const Index3& a) const {
  Index3 r;
  for (int m = 0; m < 3; ++m) {
    int v = b0[m];
    for (int n = 0; n < 3; ++n) v += T(m, n) * (a[n] - a0[n]);
    r[m] = v;
  }
  return r;
}

Index3 Interface::map_cell(const Index3& c) const {
  // Work in doubled node coordinates so that a cell maps through its centre.
  Index3 r;
  for (int m = 0; m < 3; ++m) {
    int v = 2 * b0[m];
    for (int n = 0; n < 3; ++n) v += T(m, n) * (2 * c[n] + 1 - 2 * a0[n]);
    r[m] = (v - 1) / 2;
  }
  return r;
}

// §2.2: S = 1/2 (x_c - x_a) x (x_d - x_b) with the node orders of the table,
// translated to 0-based cells (cell j spans node planes j and j+1).
void compute_metrics(Block& b) {
  const auto& X = b.x;
  auto face = [&](int d, int i, int j, int k, Vec3& S, Vec3& c) {
    Vec3 xa, xb, xc, xd;
    if (d == 0) {
      xa = X(i, j, k), xb = X(i, j + 1, k), xc = X(i, j + 1, k + 1), xd = X(i, j, k + 1);
    } else if (d == 1) {
      xa = X(i, j, k), xb = X(i, j, k + 1), xc = X(i + 1, j, k + 1), xd = X(i + 1, j, k);
    } else {
      xa = X(i, j, k), xb = X(i + 1, j, k), xc = X(i + 1, j + 1, k), xd = X(i, j + 1, k);
    }
    S = 0.5 * (xc - xa).cross(xd - xb);
    c = 0.25 * (xa + xb + xc + xd);
  };
  for (int d = 0; d < 3; ++d) {
    auto& Sd = b.S[d];
    for (int k = -kGhost; k < Sd.nk() + kGhost; ++k)
      for (int j = -kGhost; j < Sd.nj() + kGhost; ++j)
        for (int i = -kGhost; i < Sd.ni() + kGhost; ++i) {
          // Faces need the nodes one further along each tangential direction.
          Index3 top{i, j, k};
          bool ok = true;
          for (int t = 0; t < 3; ++t)
            if (t != d && top[t] + 1 > b.n(t) + kGhost) ok = false;
          if (top[d] > b.n(d) + kGhost) ok = false;
          if (!ok) continue;
          face(d, i, j, k, Sd(i, j, k), b.xf[d](i, j, k));
        }
  }
  // §2.3: V = 1/3 sum_f s_f xbar_f . S_f (exact for the trilinear hexahedron).
  for (int k = -kGhost; k < b.nk + kGhost; ++k)
    for (int j = -kGhost; j < b.nj + kGhost; ++j)
      for (int i = -kGhost; i < b.ni + kGhost; ++i) {
        Real v = 0.0;
        v += b.xf[0](i + 1, j, k).dot(b.S[0](i + 1, j, k)) - b.xf[0](i, j, k).dot(b.S[0](i, j, k));
        v += b.xf[1](i, j + 1, k).dot(b.S[1](i, j + 1, k)) - b.xf[1](i, j, k).dot(b.S[1](i, j, k));
        v += b.xf[2](i, j, k + 1).dot(b.S[2](i, j, k + 1)) - b.xf[2](i, j, k).dot(b.S[2](i, j, k));
        b.vol(i, j, k) = v / 3.0;
        Vec3 c = Vec3::Zero();
        for (int dk = 0; dk < 2; ++dk)
          for (int dj = 0; dj < 2; ++dj)
            for (int di = 0; di < 2; ++di) c += X(i + di, j + dj, k + dk);
        b.xc(i, j, k) = c / 8.0;
      }
}

void fill_ghost_nodes(Grid& g) {
  ghost_sweep(g, [&](int ib, const Patch& p, int m) {
    Block& b = g.blocks[ib];
    const int d = side_dir(p.side);
    const bool high = side_high(p.side);
    // Node range of the patch: cell range lo..hi -> nodes lo..hi inclusive.
    Index3 lo = p.lo, hi = p.hi;
    for (int t = 0; t < 3; ++t) {
      if (t == d) continue;
      if (t < d) {
        if (lo[t] == 0) lo[t] = -kGhost;
        if (hi[t] == b.n(t)) hi[t] = b.n(t) + kGhost;
      }
    }
    const int plane = high ? b.n(d) : 0;
    const int out = high ? 1 : -1;
    const Interface* itf = p.type == BcType::Interface && p.interface >= 0 ? &g.interfaces[p.interface] : nullptr;
    const Block* donor = itf ? &g.blocks[itf->donor] : nullptr;
    for (int k = (d == 2 ? 0 : lo[2]); k <= (d == 2 ? 0 : hi[2]); ++k)
      for (int j = (d == 1 ? 0 : lo[1]); j <= (d == 1 ? 0 : hi[1]); ++j)
        for (int i = (d == 0 ? 0 : lo[0]); i <= (d == 0 ? 0 : hi[0]); ++i) {
          Index3 gidx{i, j, k}, in{i, j, k}, on{i, j, k};
          gidx[d] = plane + out * m;
          in[d] = plane - out * m;
          on[d] = plane;
          if (donor) {
            b.x(gidx) = itf->R * donor->x(itf->map_node(gidx)) + itf->t;
          } else {
            b.x(gidx) = 2.0 * b.x(on) - b.x(in);
          }
        }
  });
}

void prepare_geometry(Grid& g) {
  fill_ghost_nodes(g);
  for (auto& b : g.blocks) compute_metrics(b);
}

std::array<double, 6> node_extent(const Block& b, const GhostArray<Vec3>& nodes) {
  std::array<double, 6> e{1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
  for (int k = 0; k <= b.nk; ++k)
    for (int j = 0; j <= b.nj; ++j)
      for (int i = 0; i <= b.ni; ++i)
        for (int d = 0; d < 3; ++d) {
          e[d] = std::min(e[d], nodes(i, j, k)[d]);
          e[3 + d] = std::max(e[3 + d], nodes(i, j, k)[d]);
        }
  return e;
}

}  // namespace narwhal
